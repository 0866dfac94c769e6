//! Stage 4: points from the sensor frame into the world frame with the ego pose.

use nalgebra::{Isometry3, Point3};

use crate::Point;

/// Writes `pose * p` for every point of `points` into `out` (cleared first), keeping the
/// intensity. The arithmetic is `f64`; results are rounded to `f32` once.
pub fn to_world(points: &[Point], pose: &Isometry3<f64>, out: &mut Vec<Point>) {
    let rotation = pose.rotation.to_rotation_matrix();
    let r = rotation.matrix();
    let t = pose.translation.vector;
    out.clear();
    out.extend(points.iter().map(|p| {
        let (x, y, z) = (p.x as f64, p.y as f64, p.z as f64);
        Point::new(
            (r[(0, 0)] * x + r[(0, 1)] * y + r[(0, 2)] * z + t.x) as f32,
            (r[(1, 0)] * x + r[(1, 1)] * y + r[(1, 2)] * z + t.y) as f32,
            (r[(2, 0)] * x + r[(2, 1)] * y + r[(2, 2)] * z + t.z) as f32,
            p.intensity,
        )
    }));
}

/// The sensor's position in the world frame: the viewpoint of every point of the scan.
pub fn sensor_origin(pose: &Isometry3<f64>) -> Point3<f64> {
    pose * Point3::origin()
}

#[cfg(test)]
mod tests {
    use nalgebra::{Translation3, UnitQuaternion, Vector3};

    use super::*;

    #[test]
    fn matches_nalgebra_and_keeps_intensity() {
        let pose = Isometry3::from_parts(
            Translation3::new(1200.5, -340.25, 12.0),
            UnitQuaternion::from_euler_angles(0.02, -0.01, 2.3),
        );
        let points = [
            Point::new(1.0, 2.0, -1.7, 0.3),
            Point::new(-30.0, 4.5, 0.2, 0.9),
        ];
        let mut out = vec![Point::default(); 7];
        to_world(&points, &pose, &mut out);
        assert_eq!(out.len(), 2);
        for (p, q) in points.iter().zip(&out) {
            let expected = pose * Point3::new(p.x as f64, p.y as f64, p.z as f64);
            assert!((q.x as f64 - expected.x).abs() < 1e-3);
            assert!((q.y as f64 - expected.y).abs() < 1e-3);
            assert!((q.z as f64 - expected.z).abs() < 1e-4);
            assert_eq!(q.intensity, p.intensity);
        }
        assert_eq!(
            sensor_origin(&pose).coords,
            Vector3::new(1200.5, -340.25, 12.0)
        );
    }

    #[test]
    fn identity_changes_nothing() {
        let points = [Point::new(1.5, -2.25, 0.125, 0.5)];
        let mut out = Vec::new();
        to_world(&points, &Isometry3::identity(), &mut out);
        assert_eq!(out, points);
    }
}
