//! Dropping the points a scan file holds but no sensor measured: all-zero and non-finite ones.

use trackd_perception::Point;

/// Whether a point is a real return: finite in all four values and not exactly at the sensor
/// origin (KITTI and PCL write `0 0 0` or NaN for "no return").
pub fn is_valid(p: &Point) -> bool {
    p.is_finite() && !(p.x == 0.0 && p.y == 0.0 && p.z == 0.0)
}

/// Removes the points that are not real returns (see [`is_valid`]), keeping the order of the
/// others; returns how many were removed.
pub fn drop_invalid(points: &mut Vec<Point>) -> usize {
    let before = points.len();
    points.retain(is_valid);
    before - points.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drops_zero_and_nan_points_and_keeps_order() {
        let mut points = vec![
            Point::new(1.0, 2.0, 3.0, 0.5),
            Point::new(0.0, 0.0, 0.0, 0.0),
            Point::new(f32::NAN, 1.0, 1.0, 0.0),
            Point::new(0.0, 0.0, 0.0, 0.7),
            Point::new(4.0, 0.0, 0.0, 0.0),
            Point::new(1.0, f32::INFINITY, 1.0, 0.0),
            Point::new(1.0, 1.0, 1.0, f32::NAN),
        ];
        assert_eq!(drop_invalid(&mut points), 5);
        assert_eq!(
            points,
            vec![
                Point::new(1.0, 2.0, 3.0, 0.5),
                Point::new(4.0, 0.0, 0.0, 0.0)
            ]
        );
    }
}
