//! The real drive the capacity benchmark uploads: the 40 scans of KITTI tracking sequence 0000
//! in `../shared/data/kitti-tracking-0000-first40`, with their Velodyne poses.

use std::path::Path;

use anyhow::Context;
use trackd_client::{ScanBody, api::KITTI_BIN};
use trackd_dataset::{OpenOptions, open};
use trackd_perception::Ego;

/// Where the drive lives under the shared data folder.
const DRIVE: &str = "kitti-tracking-0000-first40/training";
/// The sequence.
const SEQUENCE: &str = "0000";
/// Seconds between scans.
const PERIOD_S: f64 = 0.1;

/// One recorded scan: the `.bin` file's bytes and the sensor pose `x,y,z,qw,qx,qy,qz`.
struct RecordedScan {
    bytes: Vec<u8>,
    pose: [f64; 7],
}

/// The scans of a drive, replayed forwards then backwards without end, so that the vehicle
/// never jumps from the last pose back to the first.
pub struct KittiDrive {
    scans: Vec<RecordedScan>,
}

impl KittiDrive {
    /// Reads the drive from the shared data folder `shared`.
    pub fn read(shared: &Path) -> anyhow::Result<Self> {
        let root = shared.join(DRIVE);
        let poses = root.join("poses").join(format!("{SEQUENCE}.txt"));
        let source = open(
            &root,
            &OpenOptions {
                seq: Some(SEQUENCE.into()),
                poses: Some(poses),
            },
        )
        .with_context(|| format!("opening {}", root.display()))?;
        anyhow::ensure!(source.len() >= 2, "{}: fewer than 2 scans", root.display());
        let mut scans = Vec::with_capacity(source.len());
        for i in 0..source.len() {
            let path = source.scan_path(i)?;
            let bytes =
                std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
            let Ego::Pose(pose) = source.frame(i)?.ego else {
                anyhow::bail!("{}: scan {i} has no pose", root.display());
            };
            let (t, q) = (pose.translation.vector, pose.rotation);
            scans.push(RecordedScan {
                bytes,
                pose: [t.x, t.y, t.z, q.w, q.i, q.j, q.k],
            });
        }
        Ok(Self { scans })
    }

    /// Number of distinct scans.
    pub fn len(&self) -> usize {
        self.scans.len()
    }

    /// Points in the first scan.
    pub fn points_per_scan(&self) -> usize {
        self.scans[0].bytes.len() / 16
    }

    /// The upload of the `k`-th scan of the endless replay (timestamp `k` periods).
    pub fn upload(&self, k: u64) -> ScanBody {
        let n = self.scans.len() as u64;
        let round = 2 * (n - 1);
        let step = k % round;
        let index = if step < n { step } else { round - step };
        let scan = &self.scans[index as usize];
        ScanBody::Raw {
            bytes: scan.bytes.clone(),
            content_type: KITTI_BIN,
            timestamp: k as f64 * PERIOD_S,
            pose: Some(scan.pose),
            oxts: None,
        }
    }
}
