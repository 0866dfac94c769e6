//! Oriented 3-D boxes and the LiDAR points inside them (the protocol drops GT boxes holding
//! fewer than 10 points).

use nalgebra::{Point3, Rotation3, Vector3};

/// A box: centre, orientation and half extents along its own axes.
#[derive(Clone, Debug, PartialEq)]
pub struct OrientedBox {
    /// Centre of the box.
    pub centre: Point3<f64>,
    /// Maps the box's own axes to the frame's.
    pub rotation: Rotation3<f64>,
    /// Half extents along the box's own x, y, z axes.
    pub half_extents: Vector3<f64>,
}

impl OrientedBox {
    /// A KITTI label box in the rectified camera frame: bottom centre `(x, y, z)` (y points
    /// down), height `h`, width `w`, length `l`, rotation `ry` about the camera's y axis (the
    /// length lies along the box's x axis, KITTI's devkit convention).
    pub fn kitti_camera(bottom: [f64; 3], h: f64, w: f64, l: f64, ry: f64) -> Self {
        Self {
            centre: Point3::new(bottom[0], bottom[1] - h / 2.0, bottom[2]),
            rotation: Rotation3::from_axis_angle(&Vector3::y_axis(), ry),
            half_extents: Vector3::new(l / 2.0, h / 2.0, w / 2.0),
        }
    }

    /// A KITTI raw tracklet box in the Velodyne frame: bottom centre `(tx, ty, tz)` (z up),
    /// height `h`, width `w`, length `l`, yaw `rz` about z.
    pub fn kitti_velodyne(bottom: [f64; 3], h: f64, w: f64, l: f64, rz: f64) -> Self {
        Self {
            centre: Point3::new(bottom[0], bottom[1], bottom[2] + h / 2.0),
            rotation: Rotation3::from_axis_angle(&Vector3::z_axis(), rz),
            half_extents: Vector3::new(l / 2.0, w / 2.0, h / 2.0),
        }
    }

    /// Whether a point lies inside the box (faces included).
    pub fn contains(&self, p: &Point3<f64>) -> bool {
        let local = self.rotation.inverse_transform_vector(&(p - self.centre));
        local.x.abs() <= self.half_extents.x
            && local.y.abs() <= self.half_extents.y
            && local.z.abs() <= self.half_extents.z
    }

    /// How many of `points` lie inside the box.
    pub fn count_inside(&self, points: &[Point3<f64>]) -> usize {
        points.iter().filter(|p| self.contains(p)).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn camera_box_follows_kitti_conventions() {
        // A 4 m long, 2 m wide, 1.5 m high car 10 m ahead, bottom at y = 1.7 (camera y down).
        let b = OrientedBox::kitti_camera([0.0, 1.7, 10.0], 1.5, 2.0, 4.0, 0.0);
        assert_eq!(b.centre, Point3::new(0.0, 0.95, 10.0));
        // ry = 0: the length lies along camera x.
        assert!(b.contains(&Point3::new(1.9, 1.0, 10.0)));
        assert!(!b.contains(&Point3::new(0.0, 1.0, 11.5)));
        assert!(!b.contains(&Point3::new(0.0, 0.1, 10.0)));
        // ry = π/2: the length lies along camera z.
        let turned = OrientedBox::kitti_camera([0.0, 1.7, 10.0], 1.5, 2.0, 4.0, FRAC_PI_2);
        assert!(turned.contains(&Point3::new(0.0, 1.0, 11.5)));
        assert!(!turned.contains(&Point3::new(1.9, 1.0, 10.0)));
    }

    #[test]
    fn velodyne_box_counts_points() {
        let b = OrientedBox::kitti_velodyne([10.0, 0.0, -1.7], 1.5, 2.0, 4.0, FRAC_PI_2);
        let points = [
            Point3::new(10.0, 1.9, -1.0), // along the length (now y)
            Point3::new(10.9, 0.0, -0.3), // along the width, near the top
            Point3::new(11.5, 0.0, -1.0), // beyond the width
            Point3::new(10.0, 0.0, -1.8), // below the bottom
        ];
        assert_eq!(b.count_inside(&points), 2);
    }
}
