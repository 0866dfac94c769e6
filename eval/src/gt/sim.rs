//! Ground truth of a simulated drive: `gt_tracks.csv`.
//!
//! Header `frame,id,class,x,y,z,l,w,h,yaw,vx,vy,npoints`: box centre and yaw in that frame's
//! Velodyne frame, `npoints` the LiDAR points on the object. Objects with fewer than 10 points
//! or beyond 50 m (BEV) are "don't care" (eval-protocol.md).

use std::{collections::HashMap, path::Path};

use crate::{
    csv::{Table, read_text},
    error::EvalError,
    gt::{GroundTruth, GtFiltering, GtFrame, GtObject},
};

/// One object in one frame of a simulated drive.
#[derive(Clone, Debug, PartialEq)]
pub struct SimGtRow {
    /// Frame index.
    pub frame: u32,
    /// Object identity.
    pub id: u64,
    /// Class name as written.
    pub class: String,
    /// Box centre in the Velodyne frame of that frame (metres).
    pub centre: [f64; 3],
    /// Box length, width, height (metres).
    pub size: [f64; 3],
    /// Heading about z in the Velodyne frame (radians).
    pub yaw: f64,
    /// Velocity over ground (m/s).
    pub velocity: [f64; 2],
    /// LiDAR points on the object in that scan.
    pub npoints: u32,
}

/// When a simulated object is "don't care".
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimRules {
    /// Objects with fewer points than this are don't care.
    pub min_points: u32,
    /// Objects farther than this (BEV, metres) are don't care.
    pub max_range: f64,
}

impl Default for SimRules {
    /// The protocol's: fewer than 10 points or beyond 50 m.
    fn default() -> Self {
        Self {
            min_points: 10,
            max_range: 50.0,
        }
    }
}

/// The columns of `gt_tracks.csv`, in the order they are written.
pub const GT_TRACKS_HEADER: [&str; 13] = [
    "frame", "id", "class", "x", "y", "z", "l", "w", "h", "yaw", "vx", "vy", "npoints",
];

/// Reads a `gt_tracks.csv` file and applies `rules`.
pub fn read_sim_ground_truth(path: &Path, rules: &SimRules) -> Result<GroundTruth, EvalError> {
    Ok(sim_ground_truth(&read_gt_tracks_csv(path)?, rules))
}

/// Reads and validates a `gt_tracks.csv` file.
pub fn read_gt_tracks_csv(path: &Path) -> Result<Vec<SimGtRow>, EvalError> {
    parse_gt_tracks_csv(&read_text(path)?, path)
}

/// Parses and validates the text of a `gt_tracks.csv` file (a repeated (frame, id) or a
/// non-finite coordinate is an error); `path` names it in errors.
pub fn parse_gt_tracks_csv(text: &str, path: &Path) -> Result<Vec<SimGtRow>, EvalError> {
    let table = Table::new(path, text, &GT_TRACKS_HEADER)?;
    let mut first_line: HashMap<(u32, u64), usize> = HashMap::new();
    let mut rows = Vec::new();
    for row in table.rows(&GT_TRACKS_HEADER) {
        let row = row?;
        let object = SimGtRow {
            frame: row.parse(0)?,
            id: row.parse(1)?,
            class: row.text(2).to_string(),
            centre: [row.finite(3)?, row.finite(4)?, row.finite(5)?],
            size: [row.parse(6)?, row.parse(7)?, row.parse(8)?],
            yaw: row.parse(9)?,
            velocity: [row.parse(10)?, row.parse(11)?],
            npoints: row.parse(12)?,
        };
        if let Some(&first) = first_line.get(&(object.frame, object.id)) {
            return Err(EvalError::Duplicate {
                path: path.to_path_buf(),
                line: row.line,
                first_line: first,
                frame: object.frame,
                id: object.id,
            });
        }
        first_line.insert((object.frame, object.id), row.line);
        rows.push(object);
    }
    Ok(rows)
}

/// The ground truth of a simulated drive: frames 0 to the last one with an object; objects
/// with too few points or too far away are don't care.
pub fn sim_ground_truth(rows: &[SimGtRow], rules: &SimRules) -> GroundTruth {
    let last = rows.iter().map(|r| r.frame).max();
    let mut frames: Vec<GtFrame> = (0..last.map_or(0, |f| f + 1))
        .map(|frame| GtFrame {
            frame,
            ..GtFrame::default()
        })
        .collect();
    for row in rows {
        let object = GtObject {
            id: row.id,
            class: row.class.clone(),
            centre: row.centre,
        };
        let frame = &mut frames[row.frame as usize];
        let too_far = row.centre[0].hypot(row.centre[1]) > rules.max_range;
        if row.npoints < rules.min_points || too_far {
            frame.dont_care.push(object);
        } else {
            frame.objects.push(object);
        }
    }
    GroundTruth {
        frames,
        view: None,
        // Don't-care objects stay in the frames; the npoints column is the point count.
        filtering: GtFiltering {
            points_checked: true,
            ..GtFiltering::default()
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "frame,id,class,x,y,z,l,w,h,yaw,vx,vy,npoints\n";

    #[test]
    fn few_points_or_far_objects_are_dont_care() {
        let text = format!(
            "{HEADER}0,1,car,10,0,0,4,2,1.5,0,0,0,120\n0,2,car,20,0,0,4,2,1.5,0,0,0,9\n\
             0,3,car,49,9,0,4,2,1.5,0,0,0,30\n2,4,cyclist,30,40,0,2,0.6,1.7,0,0,0,40\n\
             2,1,car,12,0,0,4,2,1.5,0,0,0,10\n"
        );
        let rows = parse_gt_tracks_csv(&text, Path::new("gt_tracks.csv")).unwrap();
        let gt = sim_ground_truth(&rows, &SimRules::default());
        assert_eq!(gt.frames.len(), 3);
        let ids = |objects: &[GtObject]| objects.iter().map(|o| o.id).collect::<Vec<_>>();
        // 9 points: don't care; 49.8 m: kept; 50.0 m exactly: kept (only beyond 50 m is not).
        assert_eq!(ids(&gt.frames[0].objects), [1, 3]);
        assert_eq!(ids(&gt.frames[0].dont_care), [2]);
        assert!(gt.frames[1].objects.is_empty());
        assert_eq!(ids(&gt.frames[2].objects), [4, 1]);
        let strict = SimRules {
            min_points: 11,
            max_range: 49.0,
        };
        let gt = sim_ground_truth(&rows, &strict);
        assert_eq!(ids(&gt.frames[0].dont_care), [2, 3]);
        assert_eq!(ids(&gt.frames[2].dont_care), [4, 1]);
        assert_eq!(gt.num_objects(), 1);
    }

    #[test]
    fn repeated_object_in_a_frame_is_invalid() {
        let text =
            format!("{HEADER}0,1,car,10,0,0,4,2,1.5,0,0,0,120\n0,1,car,11,0,0,4,2,1.5,0,0,0,120\n");
        let err = parse_gt_tracks_csv(&text, Path::new("gt_tracks.csv")).unwrap_err();
        assert!(matches!(err, EvalError::Duplicate { line: 3, id: 1, .. }));
    }
}
