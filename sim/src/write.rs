//! Writing simulated drives in KITTI's raw layout, through the dataset crate's writers:
//! `<out>/2011_09_26/` holds KITTI's calibration of that day, and vehicle k's drive is
//! `<out>/2011_09_26/2011_09_26_drive_<k+1>_sync/` with `velodyne_points/`, `oxts/`,
//! `tracklet_labels.xml`, `gt_tracks.csv` and `poses_truth.txt` (the true poses, in KITTI
//! odometry format, for `trackd run --poses`).

use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, Vector3};
use trackd_dataset::bin::write_bin;
use trackd_dataset::calib::{RawCalib, isometry, write_raw_calib};
use trackd_dataset::oxts::{write_dataformat, write_oxts};
use trackd_dataset::poses::write_poses;
use trackd_dataset::timestamps::write_timestamps;
use trackd_dataset::tracklets::write_tracklets;

use crate::error::SimError;
use crate::gt::{GtObject, write_gt_csv};
use crate::simulation::{SimFrame, SimRun, Simulation};
use crate::tracklet::tracklets;

/// The date folder of simulated drives (the day of the calibration they use).
pub const DATE: &str = "2011_09_26";

/// The drive folder of vehicle `vehicle` (0-based) under `out`.
pub fn drive_dir(out: &Path, vehicle: usize) -> PathBuf {
    out.join(DATE)
        .join(format!("{DATE}_drive_{:04}_sync", vehicle + 1))
}

fn create_dir(path: &Path) -> Result<(), SimError> {
    std::fs::create_dir_all(path).map_err(|source| SimError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Writes one drive folder frame by frame.
#[derive(Debug)]
pub struct DriveWriter {
    dir: PathBuf,
    timestamps: Vec<f64>,
    objects: Vec<GtObject>,
    /// True Velodyne pose of each frame in the world.
    velodyne_poses: Vec<Isometry3<f64>>,
}

impl DriveWriter {
    /// Creates vehicle `vehicle`'s drive folder under `out` (and the date folder with its
    /// calibration).
    pub fn create(out: &Path, vehicle: usize) -> Result<Self, SimError> {
        let date = out.join(DATE);
        create_dir(&date)?;
        write_raw_calib(&date, &RawCalib::kitti_2011_09_26())?;
        let dir = drive_dir(out, vehicle);
        create_dir(&dir.join("velodyne_points").join("data"))?;
        create_dir(&dir.join("oxts").join("data"))?;
        write_dataformat(&dir.join("oxts").join("dataformat.txt"))?;
        Ok(Self {
            dir,
            timestamps: Vec::new(),
            objects: Vec::new(),
            velodyne_poses: Vec::new(),
        })
    }

    /// Writes the next frame's scan and OXTS packet and keeps its timestamp and ground truth.
    pub fn push(&mut self, frame: &SimFrame) -> Result<(), SimError> {
        let name = format!("{:010}", self.timestamps.len());
        write_bin(
            &self
                .dir
                .join("velodyne_points")
                .join("data")
                .join(format!("{name}.bin")),
            &frame.points,
        )?;
        write_oxts(
            &self
                .dir
                .join("oxts")
                .join("data")
                .join(format!("{name}.txt")),
            &frame.oxts,
        )?;
        self.timestamps.push(frame.timestamp);
        self.objects.extend(frame.objects.iter().cloned());
        self.velodyne_poses.push(frame.velodyne_pose);
        Ok(())
    }

    /// Writes the timestamps and ground-truth files; returns the drive folder.
    pub fn finish(self) -> Result<PathBuf, SimError> {
        write_timestamps(
            &self.dir.join("velodyne_points").join("timestamps.txt"),
            &self.timestamps,
        )?;
        write_timestamps(
            &self.dir.join("oxts").join("timestamps.txt"),
            &self.timestamps,
        )?;
        write_tracklets(
            &self.dir.join("tracklet_labels.xml"),
            &tracklets(&self.objects),
        )?;
        write_gt_csv(&self.dir.join("gt_tracks.csv"), &self.objects)?;
        write_poses(
            &self.dir.join(POSES_TRUTH_FILE),
            &camera_poses(&self.velodyne_poses),
        )?;
        Ok(self.dir)
    }
}

/// The drive's true poses, as KITTI odometry poses of the rectified camera.
pub const POSES_TRUTH_FILE: &str = "poses_truth.txt";

/// KITTI odometry poses (rectified left camera of frame i in the camera frame of frame 0) of
/// the Velodyne poses `velodyne` with the drive's calibration: `V·inv(P_0)·P_i·inv(V)`.
fn camera_poses(velodyne: &[Isometry3<f64>]) -> Vec<Isometry3<f64>> {
    let v = RawCalib::kitti_2011_09_26()
        .rectified_camera()
        .velo_to_rect_cam;
    let v = isometry(
        &v.fixed_view::<3, 3>(0, 0).into_owned(),
        &Vector3::new(v[(0, 3)], v[(1, 3)], v[(2, 3)]),
    );
    let first = velodyne.first().copied().unwrap_or_default().inverse();
    velodyne
        .iter()
        .map(|p| v * first * p * v.inverse())
        .collect()
}

/// Writes a run held in memory; returns the drive folders, vehicle by vehicle.
pub fn write_run(run: &SimRun, out: &Path) -> Result<Vec<PathBuf>, SimError> {
    run.vehicles
        .iter()
        .enumerate()
        .map(|(k, frames)| {
            let mut w = DriveWriter::create(out, k)?;
            for f in frames {
                w.push(f)?;
            }
            w.finish()
        })
        .collect()
}

/// Makes and writes every frame of a simulation one at a time (memory stays at one frame);
/// `progress(vehicle, frame)` is called after each frame. Returns the drive folders.
pub fn write_simulation(
    sim: &Simulation,
    out: &Path,
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<PathBuf>, SimError> {
    (0..sim.config().vehicles)
        .map(|k| {
            let mut w = DriveWriter::create(out, k)?;
            for (i, f) in sim.frames(k).enumerate() {
                w.push(&f)?;
                progress(k, i);
            }
            w.finish()
        })
        .collect()
}
