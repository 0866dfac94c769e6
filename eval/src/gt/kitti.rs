//! Ground truth of a KITTI tracking sequence (eval-protocol.md, class-agnostic):
//! `label_02/<seq>.txt`, its `calib/<seq>.txt`, and the scans `velodyne/<seq>/*.bin` to count
//! the LiDAR points inside each box.
//!
//! - Counted classes: Car, Van, Truck, Tram, Pedestrian, Person_sitting, Cyclist, as one class.
//! - Centre: the label's bottom centre raised by h/2 in the rectified camera frame, mapped to
//!   the Velodyne frame with inv(R0_rect · Tr_velo_to_cam).
//! - Kept only if the centre projects with P2 into the 1242 x 375 image with positive depth and
//!   lies within 40 m (BEV), and the oriented box holds at least 10 points.
//! - Dropped counted boxes and Misc boxes become ignore-near boxes; DontCare 2-D boxes become
//!   ignore regions.

use std::path::{Path, PathBuf};

use nalgebra::{Matrix4, Point3, Vector4};
use trackd_dataset::{
    DatasetError,
    bin::read_bin,
    calib::{TrackingCalib, read_tracking_calib},
    labels::{KittiLabel, read_label_02},
};

use crate::{
    error::EvalError,
    gt::{
        GroundTruth, GtFiltering, GtFrame, GtObject,
        candidates::{Candidate, sort_into},
        oriented_box::OrientedBox,
    },
    view::{Camera, ImageBox, KITTI_IMAGE_SIZE, View},
};

/// The label classes that count, all as one class.
pub const COUNTED_CLASSES: [&str; 7] = [
    "Car",
    "Van",
    "Truck",
    "Tram",
    "Pedestrian",
    "Person_sitting",
    "Cyclist",
];

/// The class whose boxes only excuse nearby hypotheses.
pub const MISC: &str = "Misc";

/// The protocol's parameters for KITTI ground truth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KittiRules {
    /// Boxes with fewer LiDAR points inside are dropped.
    pub min_points: u32,
    /// Largest BEV distance from the Velodyne origin that is scored (metres).
    pub max_range: f64,
    /// Image width and height (pixels) of the field-of-view test.
    pub image_size: (f64, f64),
}

impl Default for KittiRules {
    /// The protocol's: 10 points, 40 m, 1242 x 375.
    fn default() -> Self {
        Self {
            min_points: 10,
            max_range: 40.0,
            image_size: KITTI_IMAGE_SIZE,
        }
    }
}

/// Where a KITTI tracking sequence's ground truth is.
#[derive(Clone, Debug, PartialEq)]
pub struct KittiTrackingFiles {
    /// `label_02/<seq>.txt`.
    pub labels: PathBuf,
    /// `calib/<seq>.txt`.
    pub calib: PathBuf,
    /// `velodyne/<seq>/` (scans `NNNNNN.bin`); `None` skips the points-in-box rule.
    pub scans: Option<PathBuf>,
}

impl KittiTrackingFiles {
    /// The files of the sequence whose labels are `labels` (`<root>/label_02/<seq>.txt`), as
    /// KITTI lays them out: `<root>/calib/<seq>.txt` and `<root>/velodyne/<seq>/`, the scans
    /// only if that folder exists.
    pub fn beside(labels: &Path) -> Self {
        let seq = labels.file_stem().unwrap_or_default();
        let root = labels
            .parent()
            .and_then(Path::parent)
            .unwrap_or(Path::new("."));
        let mut calib = root.join("calib").join(seq);
        calib.set_extension("txt");
        let scans = root.join("velodyne").join(seq);
        Self {
            labels: labels.to_path_buf(),
            calib,
            scans: scans.is_dir().then_some(scans),
        }
    }
}

/// Reads and filters the ground truth of a KITTI tracking sequence.
pub fn read_kitti_tracking_ground_truth(
    files: &KittiTrackingFiles,
    rules: &KittiRules,
) -> Result<GroundTruth, EvalError> {
    let labels = read_label_02(&files.labels)?;
    let calib = read_tracking_calib(&files.calib)?;
    let scans = files.scans.as_deref();
    let points = |frame: u32| -> Result<Vec<Point3<f64>>, DatasetError> {
        let Some(dir) = scans else {
            return Ok(Vec::new());
        };
        let scan = read_bin(&dir.join(format!("{frame:06}.bin")))?;
        Ok(scan
            .iter()
            .map(|p| Point3::new(f64::from(p.x), f64::from(p.y), f64::from(p.z)))
            .collect())
    };
    let last_scan = scans.map(last_scan_frame).transpose()?.flatten();
    kitti_tracking_ground_truth(
        &labels,
        &calib,
        scans.is_some().then_some(points),
        last_scan,
        rules,
        &files.labels,
    )
}

/// The highest frame number among the `NNNNNN.bin` files of a scan folder.
fn last_scan_frame(dir: &Path) -> Result<Option<u32>, DatasetError> {
    let entries = std::fs::read_dir(dir).map_err(|e| DatasetError::io(dir, e))?;
    let mut last = None;
    for entry in entries {
        let entry = entry.map_err(|e| DatasetError::io(dir, e))?;
        let path = entry.path();
        if path.extension().is_some_and(|e| e == "bin")
            && let Some(frame) = path
                .file_stem()
                .and_then(|s| s.to_str())
                .and_then(|s| s.parse::<u32>().ok())
        {
            last = last.max(Some(frame));
        }
    }
    Ok(last)
}

/// The ground truth of a KITTI tracking sequence from its labels and calibration.
/// `scan_points(frame)` gives the Velodyne points of a frame for the points-in-box rule (`None`:
/// the rule is skipped); `last_scan` extends the sequence to frames past the last label;
/// `labels_path` names the labels in errors.
pub fn kitti_tracking_ground_truth<F>(
    labels: &[KittiLabel],
    calib: &TrackingCalib,
    mut scan_points: Option<F>,
    last_scan: Option<u32>,
    rules: &KittiRules,
    labels_path: &Path,
) -> Result<GroundTruth, EvalError>
where
    F: FnMut(u32) -> Result<Vec<Point3<f64>>, DatasetError>,
{
    let invalid = |message: String| EvalError::Invalid {
        path: labels_path.to_path_buf(),
        message,
    };
    let velo_to_rect = calib.velo_to_rect_cam();
    let rect_to_velo = velo_to_rect
        .try_inverse()
        .ok_or_else(|| invalid("R0_rect · Tr_velo_to_cam is singular".to_string()))?;
    let view = View {
        max_range: rules.max_range,
        camera: Some(Camera {
            velo_to_rect,
            projection: calib.p2(),
            width: rules.image_size.0,
            height: rules.image_size.1,
        }),
    };
    let last_label = labels.iter().map(|l| l.frame).max();
    let last = last_label
        .map(|f| u32::try_from(f).map_err(|_| invalid(format!("frame {f} out of range"))))
        .transpose()?
        .max(last_scan);
    let mut frames: Vec<GtFrame> = (0..last.map_or(0, |f| f + 1))
        .map(|frame| GtFrame {
            frame,
            ..GtFrame::default()
        })
        .collect();
    let mut by_frame: Vec<Vec<&KittiLabel>> = vec![Vec::new(); frames.len()];
    for label in labels {
        by_frame[label.frame].push(label);
    }
    let mut filtering = GtFiltering {
        points_checked: scan_points.is_some(),
        ..GtFiltering::default()
    };
    for (frame, here) in frames.iter_mut().zip(by_frame) {
        let mut candidates = Vec::new();
        for label in here {
            if label.is_dont_care() {
                let [left, top, right, bottom] = label.bbox;
                frame.ignore_regions.push(ImageBox {
                    left,
                    top,
                    right,
                    bottom,
                });
                continue;
            }
            let counted = COUNTED_CLASSES.contains(&label.object_type.as_str());
            if !counted && label.object_type != MISC {
                continue;
            }
            let id = u64::try_from(label.track_id)
                .map_err(|_| invalid(format!("frame {}: negative track id", label.frame)))?;
            let centre =
                rect_to_velo * Vector4::new(label.x, label.y - label.h / 2.0, label.z, 1.0);
            candidates.push(Candidate {
                object: GtObject {
                    id,
                    class: label.object_type.clone(),
                    centre: [centre.x, centre.y, centre.z],
                },
                counted,
                bbox: OrientedBox::kitti_camera(
                    [label.x, label.y, label.z],
                    label.h,
                    label.w,
                    label.l,
                    label.rotation_y,
                ),
            });
        }
        let number = frame.frame;
        let points = || match scan_points.as_mut() {
            Some(points) => Ok(Some(to_rect(&points(number)?, &velo_to_rect))),
            None => Ok(None),
        };
        sort_into(
            frame,
            candidates,
            &view,
            points,
            rules.min_points,
            &mut filtering,
            invalid,
        )?;
    }
    Ok(GroundTruth {
        frames,
        view: Some(view),
        filtering,
    })
}

/// Velodyne points in the rectified camera frame.
fn to_rect(points: &[Point3<f64>], velo_to_rect: &Matrix4<f64>) -> Vec<Point3<f64>> {
    points
        .iter()
        .map(|p| Point3::from((velo_to_rect * p.to_homogeneous()).xyz()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, Matrix3x4};

    /// Camera 0 looks along Velodyne +x: rect x = −velo y, rect y = −velo z, rect z = velo x.
    fn calib() -> TrackingCalib {
        #[rustfmt::skip]
        let p2 = Matrix3x4::new(
            700.0, 0.0, 621.0, 0.0,
            0.0, 700.0, 187.5, 0.0,
            0.0, 0.0, 1.0, 0.0,
        );
        #[rustfmt::skip]
        let tr = Matrix3x4::new(
            0.0, -1.0, 0.0, 0.0,
            0.0, 0.0, -1.0, 0.0,
            1.0, 0.0, 0.0, 0.0,
        );
        TrackingCalib {
            p: [p2; 4],
            r0_rect: Matrix3::identity(),
            tr_velo_to_cam: tr,
            tr_imu_to_velo: None,
        }
    }

    /// A label whose box bottom centre is at Velodyne (x, y, −1.7).
    fn label(frame: usize, id: i64, class: &str, x: f64, y: f64) -> KittiLabel {
        KittiLabel {
            frame,
            track_id: id,
            object_type: class.to_string(),
            truncated: 0.0,
            occluded: 0,
            alpha: 0.0,
            bbox: [0.0, 0.0, 0.0, 0.0],
            h: 1.5,
            w: 1.8,
            l: 4.0,
            x: -y,
            y: 1.7,
            z: x,
            rotation_y: 0.0,
            score: None,
        }
    }

    /// `n` points around the centre of the box of `label(.., x, y)`, in the Velodyne frame.
    fn points_at(x: f64, y: f64, n: usize) -> Vec<Point3<f64>> {
        (0..n)
            .map(|k| Point3::new(x + 0.05 * k as f64 % 0.6, y, -0.95 + 0.01 * k as f64 % 0.5))
            .collect()
    }

    fn build(
        labels: &[KittiLabel],
        points: impl FnMut(u32) -> Result<Vec<Point3<f64>>, DatasetError>,
    ) -> Result<GroundTruth, EvalError> {
        kitti_tracking_ground_truth(
            labels,
            &calib(),
            Some(points),
            Some(2),
            &KittiRules::default(),
            Path::new("label_02/0000.txt"),
        )
    }

    #[test]
    fn counted_boxes_in_view_with_enough_points_are_kept() {
        let labels = [
            label(0, 1, "Car", 10.0, 0.0),      // 20 points: kept
            label(0, 2, "Van", 15.0, 2.0),      // 5 points: dropped
            label(0, 3, "Cyclist", -10.0, 0.0), // behind: dropped
            label(0, 4, "Car", 45.0, 0.0),      // beyond 40 m: dropped
            label(0, 5, "Misc", 12.0, -1.0),    // Misc: ignore near
            label(1, 1, "Car", 11.0, 0.0),      // frame 1: kept
        ];
        let mut dont_care = label(0, -1, "DontCare", 0.0, 0.0);
        dont_care.bbox = [10.0, 20.0, 110.0, 220.0];
        let mut all = labels.to_vec();
        all.push(dont_care);
        let gt = build(&all, |frame| {
            Ok(match frame {
                0 => [points_at(10.0, 0.0, 20), points_at(15.0, 2.0, 5)].concat(),
                _ => points_at(11.0, 0.0, 10),
            })
        })
        .unwrap();
        // Frames 0..=2: the last scan extends the sequence past the last label.
        assert_eq!(gt.frames.len(), 3);
        let f0 = &gt.frames[0];
        assert_eq!(f0.objects.len(), 1);
        let car = &f0.objects[0];
        assert_eq!(car.id, 1);
        for (got, want) in car.centre.iter().zip([10.0, 0.0, -0.95]) {
            assert!((got - want).abs() < 1e-12, "{:?}", car.centre);
        }
        let near: Vec<u64> = f0.ignore_near.iter().map(|o| o.id).collect();
        assert_eq!(near, [3, 4, 5, 2]);
        assert_eq!(f0.ignore_regions.len(), 1);
        assert_eq!(f0.ignore_regions[0].right, 110.0);
        assert_eq!(gt.frames[1].objects.len(), 1);
        assert_eq!(gt.filtering.outside_view, 2);
        assert_eq!(gt.filtering.too_few_points, 1);
        assert!(gt.filtering.points_checked);
    }

    #[test]
    fn an_object_labelled_twice_in_a_frame_is_invalid() {
        let labels = [label(0, 1, "Car", 10.0, 0.0), label(0, 1, "Van", 20.0, 0.0)];
        let err = build(&labels, |_| Ok(Vec::new())).unwrap_err();
        assert!(err.to_string().contains("labelled twice"), "{err}");
    }
}
