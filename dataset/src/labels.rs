//! KITTI tracking labels and results (`label_02/<seq>.txt`): one object per line, boxes in the
//! rectified camera-0 frame, image boxes in image 2. Results add a 18th column, the score.

use std::path::Path;

use crate::error::{DatasetError, parse_f64, read_text, write_bytes};

/// One line of a `label_02` file (KITTI's columns, in order).
#[derive(Clone, Debug, PartialEq)]
pub struct KittiLabel {
    /// Frame index in the sequence.
    pub frame: usize,
    /// Track id, -1 for `DontCare` regions.
    pub track_id: i64,
    /// `Car`, `Van`, `Truck`, `Pedestrian`, `Person_sitting`, `Cyclist`, `Tram`, `Misc`,
    /// `DontCare`.
    pub object_type: String,
    /// Truncation: 0 (in image), 1 (partly), 2 (mostly); -1 for `DontCare`.
    pub truncated: f64,
    /// Occlusion: 0 visible, 1 partly, 2 largely occluded, 3 unknown; -1 for `DontCare`.
    pub occluded: i32,
    /// Observation angle of the object, [-pi, pi].
    pub alpha: f64,
    /// 2D box in image 2: left, top, right, bottom (pixels).
    pub bbox: [f64; 4],
    /// Box height (metres).
    pub h: f64,
    /// Box width (metres).
    pub w: f64,
    /// Box length (metres).
    pub l: f64,
    /// Bottom centre in the rectified camera-0 frame (x right, y down, z forward; metres).
    pub x: f64,
    /// See [`Self::x`].
    pub y: f64,
    /// See [`Self::x`].
    pub z: f64,
    /// Rotation about the camera's y axis, [-pi, pi].
    pub rotation_y: f64,
    /// Confidence, in results only (higher is better).
    pub score: Option<f64>,
}

impl KittiLabel {
    /// Whether this line marks a region to ignore rather than an object.
    pub fn is_dont_care(&self) -> bool {
        self.object_type == "DontCare"
    }
}

/// Reads a `label_02` file (17 columns, or 18 with a score).
pub fn read_label_02(path: &Path) -> Result<Vec<KittiLabel>, DatasetError> {
    let text = read_text(path)?;
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| parse_label(path, i + 1, l))
        .collect()
}

/// Writes tracking results in KITTI's format: one line per label, 17 columns plus the score
/// when it has one.
pub fn write_tracking_results(path: &Path, labels: &[KittiLabel]) -> Result<(), DatasetError> {
    let text: String = labels.iter().map(|l| format_label(l) + "\n").collect();
    write_bytes(path, text.as_bytes())
}

/// One label as a line (no newline), formatted as KITTI's devkit writes it.
pub fn format_label(l: &KittiLabel) -> String {
    let truncated = if l.truncated.fract() == 0.0 && l.truncated.abs() < 1e9 {
        format!("{}", l.truncated as i64)
    } else {
        format!("{:.6}", l.truncated)
    };
    let mut line = format!(
        "{} {} {} {truncated} {} {:.6}",
        l.frame, l.track_id, l.object_type, l.occluded, l.alpha
    );
    for v in l
        .bbox
        .iter()
        .chain(&[l.h, l.w, l.l, l.x, l.y, l.z, l.rotation_y])
    {
        line.push_str(&format!(" {v:.6}"));
    }
    if let Some(score) = l.score {
        line.push_str(&format!(" {score:.6}"));
    }
    line
}

fn parse_label(path: &Path, line: usize, text: &str) -> Result<KittiLabel, DatasetError> {
    let t: Vec<&str> = text.split_whitespace().collect();
    if t.len() != 17 && t.len() != 18 {
        return Err(DatasetError::parse(
            path,
            line,
            format!(
                "{} columns, a label_02 line has 17 (or 18 with a score)",
                t.len()
            ),
        ));
    }
    let int = |i: usize, what: &str| -> Result<i64, DatasetError> {
        t[i].parse::<i64>().map_err(|_| {
            DatasetError::parse(path, line, format!("{what}: {:?} is not an integer", t[i]))
        })
    };
    let num = |i: usize, what: &str| parse_f64(path, line, what, t[i]);
    let frame = int(0, "frame")?;
    let frame = usize::try_from(frame)
        .map_err(|_| DatasetError::parse(path, line, format!("frame: {frame} is negative")))?;
    Ok(KittiLabel {
        frame,
        track_id: int(1, "track_id")?,
        object_type: t[2].to_string(),
        truncated: num(3, "truncated")?,
        occluded: i32::try_from(int(4, "occluded")?)
            .map_err(|_| DatasetError::parse(path, line, "occluded: out of range"))?,
        alpha: num(5, "alpha")?,
        bbox: [
            num(6, "bbox left")?,
            num(7, "bbox top")?,
            num(8, "bbox right")?,
            num(9, "bbox bottom")?,
        ],
        h: num(10, "height")?,
        w: num(11, "width")?,
        l: num(12, "length")?,
        x: num(13, "x")?,
        y: num(14, "y")?,
        z: num(15, "z")?,
        rotation_y: num(16, "rotation_y")?,
        score: if t.len() == 18 {
            Some(num(17, "score")?)
        } else {
            None
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shared_data_dir;

    fn label(frame: usize, id: i64, score: Option<f64>) -> KittiLabel {
        KittiLabel {
            frame,
            track_id: id,
            object_type: "Car".into(),
            truncated: 0.0,
            occluded: 1,
            alpha: -1.5,
            bbox: [100.25, 150.5, 300.0, 250.125],
            h: 1.5,
            w: 1.625,
            l: 4.0,
            x: 2.5,
            y: 1.75,
            z: 20.0,
            rotation_y: -1.625,
            score,
        }
    }

    #[test]
    fn results_round_trip_with_and_without_score() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("0000.txt");
        let mut partial = label(3, 7, None);
        partial.truncated = 0.25;
        let labels = vec![label(0, 1, Some(0.875)), label(0, 2, None), partial];
        write_tracking_results(&path, &labels).unwrap();
        assert_eq!(read_label_02(&path).unwrap(), labels);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.starts_with(
                "0 1 Car 0 1 -1.500000 100.250000 150.500000 300.000000 250.125000 1.500000 "
            ),
            "{text}"
        );
        assert_eq!(
            text.lines()
                .map(|l| l.split(' ').count())
                .collect::<Vec<_>>(),
            [18, 17, 17]
        );
    }

    #[test]
    fn real_labels_are_read_and_written_back_identically() {
        let Some(data) =
            shared_data_dir("labels::real_labels_are_read_and_written_back_identically")
        else {
            return;
        };
        for path in [
            data.join("kitti-tracking-0000-first40/training/label_02/0000.txt"),
            data.join("kitti-format-samples/tracking/label_02/0001.txt"),
        ] {
            let labels = read_label_02(&path).unwrap();
            let original = std::fs::read_to_string(&path).unwrap();
            assert_eq!(labels.len(), original.lines().count());
            let dir = tempfile::tempdir().unwrap();
            let copy = dir.path().join("copy.txt");
            write_tracking_results(&copy, &labels).unwrap();
            assert_eq!(
                std::fs::read_to_string(&copy).unwrap(),
                original,
                "{}",
                path.display()
            );
        }
        let labels =
            read_label_02(&data.join("kitti-tracking-0000-first40/training/label_02/0000.txt"))
                .unwrap();
        assert_eq!(labels.last().unwrap().frame, 39);
        let cyclist = labels
            .iter()
            .find(|l| l.frame == 0 && l.track_id == 1)
            .unwrap();
        assert_eq!(
            (cyclist.object_type.as_str(), cyclist.z),
            ("Cyclist", 5.776261)
        );
        assert!(
            labels
                .iter()
                .filter(|l| l.is_dont_care())
                .all(|l| l.track_id == -1)
        );
    }

    #[test]
    fn bad_lines_name_file_and_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("0003.txt");
        let good = format_label(&label(0, 1, None));
        for (bad, needle) in [
            (format!("{good}\n0 1 Car 0 0\n"), "5 columns"),
            (
                format!("{good}\n{}\n", good.replacen("0 1 Car", "0 x Car", 1)),
                "track_id",
            ),
            (
                format!("{good}\n{}\n", good.replace("20.000000", "far")),
                "z: \"far\"",
            ),
            (
                format!("{good}\n{}\n", good.replacen("0 1 Car", "-2 1 Car", 1)),
                "negative",
            ),
        ] {
            std::fs::write(&path, bad).unwrap();
            let err = read_label_02(&path).unwrap_err();
            assert!(matches!(err, DatasetError::Parse { line: 2, .. }), "{err}");
            assert!(err.to_string().contains(needle), "{err}");
        }
    }
}
