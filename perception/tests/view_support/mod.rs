//! What the tracker's tests with range images share: a sensor standing at the world origin,
//! [`SENSOR_Z`] above the ground, and the recording of what it sees.

use nalgebra::Isometry3;
use trackd_perception::Point;
use trackd_perception::track::{RecentViews, View};

/// Sensor height above the ground (m).
pub const SENSOR_Z: f64 = 1.73;

/// Records in `views` scan `t` of the sensor at (0, 0, [`SENSOR_Z`]) seeing the world-frame
/// `points`, with `pose` as the pose the tracker is given for it.
pub fn record_view<'a>(
    views: &mut RecentViews,
    t: f64,
    pose: Isometry3<f64>,
    points: impl IntoIterator<Item = &'a Point>,
) {
    let in_sensor: Vec<Point> = points
        .into_iter()
        .map(|p| Point::new(p.x, p.y, p.z - SENSOR_Z as f32, 0.0))
        .collect();
    let mut image = views.take_buffer(t);
    image.build(&in_sensor);
    views.push(View {
        timestamp: t,
        pose,
        image,
    });
}
