//! The paper's Algorithm 2 for one vehicle: pose → filter → ground → world → DBSCAN → VFH →
//! tracking → occupancy → super frame, one scan at a time.

use nalgebra::Isometry3;
use thiserror::Error;

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
}

/// Why a scan could not be processed. The pipeline's state is unchanged when this is returned.
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
}

/// One vehicle's perception state: pose filter, tracker, occupancy map, super-frame trigger.
pub struct Pipeline {
    config: Config,
    vehicle: Vehicle,
    next_index: u64,
    last_timestamp: Option<f64>,
}

impl Pipeline {
    /// A pipeline for `vehicle` with `config`.
    pub fn new(config: Config, vehicle: Vehicle) -> Self {
        Self {
            config,
            vehicle,
            next_index: 0,
            last_timestamp: None,
        }
    }

    /// The configuration in use.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The vehicle this pipeline runs for.
    pub fn vehicle(&self) -> &Vehicle {
        &self.vehicle
    }

    /// Processes one scan. (Under construction: stages are wired in as they land.)
    pub fn process(&mut self, frame: Frame) -> Result<FrameOutput, PipelineError> {
        if let Some(previous) = self.last_timestamp
            && frame.timestamp <= previous
        {
            return Err(PipelineError::TimeNotIncreasing {
                previous,
                got: frame.timestamp,
            });
        }
        self.last_timestamp = Some(frame.timestamp);
        let index = self.next_index;
        self.next_index += 1;
        Ok(FrameOutput {
            index,
            timestamp: frame.timestamp,
            ego_pose: Isometry3::identity(),
            tracking_frame: TrackingFrame::Sensor,
            tracks: Vec::new(),
            superframe: None,
            timings: StageTimings::default(),
            counts: FrameCounts {
                points: frame.points.len(),
                ..Default::default()
            },
        })
    }
}
