//! What goes into the pipeline (one scan with what is known of the ego pose) and what comes
//! out of it (the tracks after that scan).

use nalgebra::{Isometry3, Vector2, Vector3};
use serde::{Deserialize, Serialize};

use crate::{Point, oxts::Oxts};

/// One LiDAR scan and what is known of the vehicle's pose when it was taken.
#[derive(Clone, Debug, Default)]
pub struct Frame {
    /// Seconds, any epoch; the pipeline only uses differences, never the wall clock.
    pub timestamp: f64,
    /// Points in the sensor (Velodyne) frame.
    pub points: Vec<Point>,
    /// How the ego pose is known.
    pub ego: Ego,
}

/// How the ego pose of a scan is known.
#[derive(Clone, Debug, Default)]
pub enum Ego {
    /// A raw GPS/IMU packet, fused by the ego-pose EKF.
    Oxts(Oxts),
    /// The pose of the Velodyne frame in the world frame, given (e.g. KITTI odometry poses).
    Pose(Isometry3<f64>),
    /// Nothing: the scan is tracked in the sensor frame.
    #[default]
    None,
}

/// Object classes told apart without training.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ObjectClass {
    /// Not (yet) identified.
    #[default]
    Unknown,
    /// Car, van, truck, tram.
    Car,
    /// A rider on a bicycle.
    Cyclist,
    /// A person on foot.
    Pedestrian,
    /// Something that moves but fits none of the above.
    OtherMovable,
}

impl ObjectClass {
    /// The lower-case name used in CSV files and JSON.
    pub fn as_str(&self) -> &'static str {
        match self {
            Self::Unknown => "unknown",
            Self::Car => "car",
            Self::Cyclist => "cyclist",
            Self::Pedestrian => "pedestrian",
            Self::OtherMovable => "other_movable",
        }
    }
}

/// A confirmed object track after a frame, in the world frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrackState {
    /// Stable identifier of the track.
    pub id: u64,
    /// What the object was identified as.
    pub class: ObjectClass,
    /// Box centre in the world frame (metres).
    pub center: Vector3<f64>,
    /// Box extents: length (along yaw), width, height (metres).
    pub size: Vector3<f64>,
    /// Heading of the box in the world frame (radians, about z).
    pub yaw: f64,
    /// Velocity over ground in the world frame (m/s).
    pub velocity: Vector2<f64>,
    /// Tracking confidence in [0, 1].
    pub confidence: f32,
    /// Frames since birth.
    pub age: u32,
    /// Frames in which the track was matched to a cluster.
    pub hits: u32,
}

/// Wall time of each stage of one frame, in milliseconds (measurement only: tracking never
/// reads the clock).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct StageTimings {
    /// (stage name, milliseconds), in pipeline order.
    pub stages: Vec<(&'static str, f64)>,
}

impl StageTimings {
    /// Sum of all stages.
    pub fn total_ms(&self) -> f64 {
        self.stages.iter().map(|(_, ms)| ms).sum()
    }
}
