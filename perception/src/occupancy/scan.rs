//! One scan's input to the occupancy map, for a map updated apart from the pipeline.

use nalgebra::Vector3;

use crate::Point;

/// What [`super::OccupancyMap::integrate`] takes of one scan, owned: the sensor position and the
/// obstacle and ground points, all in the world (odometry) frame.
#[derive(Clone, Debug, Default)]
pub struct OccupancyScan {
    /// Where the rays start.
    pub sensor: Vector3<f64>,
    /// Points that are hits.
    pub obstacles: Vec<Point>,
    /// Ground points the rays clear the space above the road through.
    pub ground: Vec<Point>,
}
