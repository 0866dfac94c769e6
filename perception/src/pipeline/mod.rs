//! The paper's Algorithm 2 for one vehicle: pose → filter → ground → world → DBSCAN → VFH →
//! tracking → occupancy → super frame, one scan at a time. Every buffer is kept from scan to
//! scan, so a steady stream of scans allocates next to nothing.
//!
//! It comes in two halves: [`Segmentation`] (pose to DBSCAN, the clusters gathered and
//! described by their VFH) reads nothing the tracker writes, and [`Tracking`] (clusters split
//! among the tracks that claim them, tracking, occupancy, super frames) takes what it made.
//! [`Pipeline`] runs one after the other; `trackd run` runs them on two threads, the next
//! scan's segmentation overlapping this one's tracking.

mod gather;
mod segmentation;
mod tracking;

pub use segmentation::{Segmentation, Segmented};
pub use tracking::Tracking;

use std::time::Instant;

use nalgebra::{Isometry3, Translation3};
use thiserror::Error;

use crate::cluster::ClusterError;
use crate::occupancy::{OccupancyMap, OccupancyScan};
use crate::pose::PoseError;
use crate::track::Tracker;
use crate::{Frame, StageTimings, TrackState, config::Config, geo::GeoOrigin};

/// Who runs the pipeline and where its world frame is.
#[derive(Clone, Debug)]
pub struct Vehicle {
    /// The vehicle's id in the fleet (Zenoh key, super frames).
    pub id: String,
    /// The fleet's geodetic origin; `None`: the first GPS fix becomes the origin.
    pub origin: Option<GeoOrigin>,
    /// KITTI's `Tr_imu_to_velo`: maps IMU coordinates to Velodyne coordinates.
    pub imu_to_velo: Isometry3<f64>,
}

/// The frame the tracks are expressed in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TrackingFrame {
    /// The fleet's world frame (a pose was known).
    World,
    /// The sensor frame of each scan (no pose source).
    Sensor,
}

/// The sensor pose of one scan as the pipeline uses it.
struct EgoPose {
    /// In the odometry frame every stage works in: continuous from scan to scan.
    odometry: Isometry3<f64>,
    /// Places the odometry frame in the world frame the outputs are in.
    world_from_odometry: Translation3<f64>,
    /// What the tracks are expressed in.
    frame: TrackingFrame,
}

/// Point and cluster counts of one frame.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct FrameCounts {
    /// Points in the scan.
    pub points: usize,
    /// Points left after range filtering.
    pub filtered: usize,
    /// Points left after ground removal.
    pub non_ground: usize,
    /// DBSCAN clusters.
    pub clusters: usize,
}

/// What one processed scan yields.
#[derive(Clone, Debug)]
pub struct FrameOutput {
    /// 0-based index of the scan in this pipeline's input.
    pub index: u64,
    /// The scan's timestamp (seconds).
    pub timestamp: f64,
    /// Pose of the Velodyne frame in the world frame (identity when tracking in the sensor frame).
    pub ego_pose: Isometry3<f64>,
    /// The same pose in the odometry frame the tracker works in (see
    /// [`PoseEstimator::odometry`](crate::pose::PoseEstimator::odometry)); equal to `ego_pose`
    /// unless OXTS drives the pose.
    pub odometry_pose: Isometry3<f64>,
    /// The frame the tracks are expressed in.
    pub tracking_frame: TrackingFrame,
    /// Confirmed object tracks (static structure excluded), in the world frame.
    pub tracks: Vec<TrackState>,
    /// The super frame this scan triggered, if any.
    pub superframe: Option<trackd_proto::SuperFrame>,
    /// Wall time per stage.
    pub timings: StageTimings,
    /// Point and cluster counts.
    pub counts: FrameCounts,
    /// The scan's update of the occupancy map, when the pipeline hands it out (see
    /// [`Pipeline::hand_out_occupancy`]) instead of integrating it.
    pub occupancy_scan: Option<OccupancyScan>,
}

/// Why a scan could not be processed. The pipeline's tracks are unchanged when this is
/// returned.
#[derive(Debug, Error)]
pub enum PipelineError {
    /// The scan's timestamp is not after the previous scan's.
    #[error("scan timestamp {got} is not after the previous one ({previous})")]
    TimeNotIncreasing {
        /// The previous timestamp.
        previous: f64,
        /// The rejected timestamp.
        got: f64,
    },
    /// The ego-pose filter refused the scan's OXTS packet (e.g. no GPS fix yet).
    #[error("ego pose: {0}")]
    Pose(#[from] PoseError),
    /// DBSCAN could not run.
    #[error("clustering: {0}")]
    Cluster(#[from] ClusterError),
}

/// Stage timing: the milliseconds since the last lap, under `name`.
struct Laps {
    last: Instant,
    timings: StageTimings,
}

impl Laps {
    /// Laps from now into `timings` (cleared).
    fn start(mut timings: StageTimings) -> Self {
        timings.stages.clear();
        Self::resume(timings)
    }

    /// Laps from now after those already in `timings`.
    fn resume(timings: StageTimings) -> Self {
        Self {
            last: Instant::now(),
            timings,
        }
    }

    fn finish(self) -> StageTimings {
        self.timings
    }

    fn lap(&mut self, name: &'static str) {
        let now = Instant::now();
        let ms = (now - self.last).as_secs_f64() * 1e3;
        self.timings.stages.push((name, ms));
        self.last = now;
    }
}

/// One vehicle's perception: both halves, run one after the other on each scan.
pub struct Pipeline {
    segmentation: Segmentation,
    tracking: Tracking,
    /// The scan between the halves (kept for its buffers).
    scan: Segmented,
}

impl Pipeline {
    /// A pipeline for `vehicle` with `config`.
    pub fn new(config: Config, vehicle: Vehicle) -> Self {
        let tracking = Tracking::new(config.clone(), vehicle.id.clone());
        Self {
            segmentation: Segmentation::new(&config, vehicle),
            tracking,
            scan: Segmented::default(),
        }
    }

    /// The two halves, to run on threads of their own.
    pub fn into_halves(self) -> (Segmentation, Tracking) {
        (self.segmentation, self.tracking)
    }

    /// The configuration in use.
    pub fn config(&self) -> &Config {
        self.tracking.config()
    }

    /// The vehicle this pipeline runs for.
    pub fn vehicle(&self) -> &Vehicle {
        self.segmentation.vehicle()
    }

    /// The tracker (every track, tentative and structure included).
    pub fn tracker(&self) -> &Tracker {
        self.tracking.tracker()
    }

    /// The occupancy map built so far.
    pub fn occupancy(&self) -> &OccupancyMap {
        self.tracking.occupancy()
    }

    /// See [`Tracking::hand_out_occupancy`].
    pub fn hand_out_occupancy(&mut self) {
        self.tracking.hand_out_occupancy();
    }

    /// The fleet's geodetic origin, once known (given, or the first GPS fix).
    pub fn origin(&self) -> Option<GeoOrigin> {
        self.segmentation.origin()
    }

    /// Processes one scan.
    pub fn process(&mut self, frame: Frame) -> Result<FrameOutput, PipelineError> {
        self.segmentation.segment(&frame, &mut self.scan)?;
        Ok(self.tracking.track(&mut self.scan))
    }
}
