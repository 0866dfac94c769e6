//! Ground truth of a KITTI raw drive: `tracklet_labels.xml` (boxes in the Velodyne frame), with
//! the same counted classes, range and points rules as KITTI tracking (eval-protocol.md); the
//! camera field-of-view filter uses the date folder's calibration when it is there, and points
//! are counted in `velodyne_points/data/*.bin` when the scans are there.

use std::path::{Path, PathBuf};

use nalgebra::Point3;
use trackd_dataset::{
    DatasetError,
    bin::read_bin,
    calib::{CAM_TO_CAM_FILE, RectifiedCamera, read_raw_calib},
    tracklets::{Tracklet, read_tracklets},
};

use crate::{
    error::EvalError,
    gt::{
        GroundTruth, GtFiltering, GtFrame, GtObject,
        candidates::{Candidate, sort_into},
        kitti::{COUNTED_CLASSES, KittiRules, MISC},
        oriented_box::OrientedBox,
    },
    view::{Camera, View},
};

/// How KITTI raw tracklets spell the sitting-person class (tracking labels: `Person_sitting`).
const PERSON_SITTING: &str = "Person (sitting)";

/// Where a KITTI raw drive's ground truth is.
#[derive(Clone, Debug, PartialEq)]
pub struct KittiRawFiles {
    /// `<date>_drive_<n>_sync/tracklet_labels.xml`.
    pub tracklets: PathBuf,
    /// The date folder with `calib_*.txt`; `None` leaves only the range filter.
    pub calib_dir: Option<PathBuf>,
    /// `velodyne_points/data/` (scans `NNNNNNNNNN.bin`); `None` skips the points-in-box rule.
    pub scans: Option<PathBuf>,
}

impl KittiRawFiles {
    /// The files of the drive whose tracklets are `tracklets`, as KITTI lays them out: the
    /// calibration in the drive folder's parent and the scans in
    /// `velodyne_points/data/`, each only if present.
    pub fn beside(tracklets: &Path) -> Self {
        let drive = tracklets.parent().unwrap_or(Path::new("."));
        let date = drive.parent().unwrap_or(Path::new(".."));
        let scans = drive.join("velodyne_points").join("data");
        Self {
            tracklets: tracklets.to_path_buf(),
            calib_dir: date
                .join(CAM_TO_CAM_FILE)
                .is_file()
                .then(|| date.to_path_buf()),
            scans: scans.is_dir().then_some(scans),
        }
    }
}

/// Reads and filters the ground truth of a KITTI raw drive.
pub fn read_kitti_raw_ground_truth(
    files: &KittiRawFiles,
    rules: &KittiRules,
) -> Result<GroundTruth, EvalError> {
    let tracklets = read_tracklets(&files.tracklets)?;
    let camera = files
        .calib_dir
        .as_deref()
        .map(read_raw_calib)
        .transpose()?
        .map(|calib| calib.rectified_camera());
    let scans = files.scans.as_deref();
    let points = |frame: u32| -> Result<Vec<Point3<f64>>, DatasetError> {
        let Some(dir) = scans else {
            return Ok(Vec::new());
        };
        let scan = read_bin(&dir.join(format!("{frame:010}.bin")))?;
        Ok(scan
            .iter()
            .map(|p| Point3::new(f64::from(p.x), f64::from(p.y), f64::from(p.z)))
            .collect())
    };
    kitti_raw_ground_truth(
        &tracklets,
        camera.as_ref(),
        scans.is_some().then_some(points),
        rules,
        &files.tracklets,
    )
}

/// The ground truth of a KITTI raw drive from its tracklets. `camera` (from the raw
/// calibration) bounds the view, else only the range does; `scan_points(frame)` gives the
/// Velodyne points of a frame for the points-in-box rule (`None`: skipped); `path` names the
/// tracklets in errors.
pub fn kitti_raw_ground_truth<F>(
    tracklets: &[Tracklet],
    camera: Option<&RectifiedCamera>,
    mut scan_points: Option<F>,
    rules: &KittiRules,
    path: &Path,
) -> Result<GroundTruth, EvalError>
where
    F: FnMut(u32) -> Result<Vec<Point3<f64>>, DatasetError>,
{
    let invalid = |message: String| EvalError::Invalid {
        path: path.to_path_buf(),
        message,
    };
    let view = View {
        max_range: rules.max_range,
        camera: camera.map(|c| Camera {
            velo_to_rect: c.velo_to_rect_cam,
            projection: c.p2,
            width: rules.image_size.0,
            height: rules.image_size.1,
        }),
    };
    let end = tracklets.iter().map(Tracklet::end_frame).max().unwrap_or(0);
    let end = u32::try_from(end).map_err(|_| invalid(format!("frame {end} out of range")))?;
    let mut frames: Vec<GtFrame> = (0..end)
        .map(|frame| GtFrame {
            frame,
            ..GtFrame::default()
        })
        .collect();
    let mut filtering = GtFiltering {
        points_checked: scan_points.is_some(),
        ..GtFiltering::default()
    };
    for frame in &mut frames {
        let mut candidates = Vec::new();
        for (id, tracklet) in tracklets.iter().enumerate() {
            let Some(pose) = tracklet.pose_at(frame.frame as usize) else {
                continue;
            };
            let class = tracklet.object_type.as_str();
            let counted = class == PERSON_SITTING || COUNTED_CLASSES.contains(&class);
            if !counted && class != MISC {
                continue;
            }
            let bbox = OrientedBox::kitti_velodyne(
                [pose.tx, pose.ty, pose.tz],
                tracklet.h,
                tracklet.w,
                tracklet.l,
                pose.rz,
            );
            candidates.push(Candidate {
                object: GtObject {
                    id: id as u64,
                    class: tracklet.object_type.clone(),
                    centre: bbox.centre.into(),
                },
                counted,
                bbox,
            });
        }
        let number = frame.frame;
        let points = || match scan_points.as_mut() {
            Some(points) => points(number).map(Some),
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
