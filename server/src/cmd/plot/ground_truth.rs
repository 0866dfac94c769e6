//! Ground-truth trajectories to draw beside the tracks: a simulated drive's `gt_tracks.csv` or
//! a KITTI tracking `label_02/<seq>.txt`, placed in the world frame with the run's ego poses.

use std::collections::BTreeMap;
use std::path::Path;

use nalgebra::{Isometry3, Point3};
use trackd_eval::GroundTruth;
use trackd_eval::gt::kitti::{KittiRules, KittiTrackingFiles, read_kitti_tracking_ground_truth};
use trackd_eval::gt::sim::{SimRules, read_sim_ground_truth};

/// One ground-truth object's positions over the drive, in the world frame.
#[derive(Clone, Debug, PartialEq)]
pub struct GtTrajectory {
    /// Object id.
    pub id: u64,
    /// Box centres (x, y, metres), by frame.
    pub positions: Vec<[f64; 2]>,
}

/// Reads the ground truth at `path` (format by extension) and places every labelled object of
/// the frames the run processed in the world frame.
pub fn read(path: &Path, ego: &[Isometry3<f64>]) -> anyhow::Result<Vec<GtTrajectory>> {
    let gt = match path.extension().and_then(|e| e.to_str()) {
        Some("csv") => read_sim_ground_truth(path, &SimRules::default())?,
        Some("txt") => {
            let files = KittiTrackingFiles {
                scans: None,
                ..KittiTrackingFiles::beside(path)
            };
            let rules = KittiRules {
                max_range: f64::INFINITY,
                ..KittiRules::default()
            };
            read_kitti_tracking_ground_truth(&files, &rules)?
        }
        _ => anyhow::bail!(
            "{}: not a ground truth trackd plots (gt_tracks.csv or label_02/<seq>.txt)",
            path.display()
        ),
    };
    Ok(trajectories(&gt, ego))
}

/// Every object of `gt` (counted or don't care) in the frames that have an ego pose, by id.
pub fn trajectories(gt: &GroundTruth, ego: &[Isometry3<f64>]) -> Vec<GtTrajectory> {
    let mut by_id: BTreeMap<u64, Vec<[f64; 2]>> = BTreeMap::new();
    for frame in &gt.frames {
        let Some(pose) = ego.get(frame.frame as usize) else {
            continue;
        };
        for object in frame.objects.iter().chain(&frame.dont_care) {
            let [x, y, z] = object.centre;
            let p = pose * Point3::new(x, y, z);
            by_id.entry(object.id).or_default().push([p.x, p.y]);
        }
    }
    by_id
        .into_iter()
        .map(|(id, positions)| GtTrajectory { id, positions })
        .collect()
}
