//! What the current scan sees along each direction: a range image of the filtered scan, in
//! the sensor frame. It answers the question that separates a moving object from a wall whose
//! visible part slides along it as the vehicle passes: is the place where the object was a
//! moment ago now seen through (the laser went past it and hit something farther), still hit,
//! or hidden?
//!
//! A static object can never be seen through where it stands; an object that moved away can.

use nalgebra::Vector3;

use crate::Point;

/// Azimuth resolution of the image (degrees).
const AZIMUTH_STEP_DEG: f64 = 0.25;
/// Elevation resolution (degrees) and the band covered, generous for a 64-beam sensor.
const ELEVATION_STEP_DEG: f64 = 0.5;
const ELEVATION_MIN_DEG: f64 = -30.0;
const ELEVATION_MAX_DEG: f64 = 10.0;
/// Ranges within this (m) of a probe's count as hitting it.
const HIT_TOLERANCE: f64 = 0.4;

/// What the scan shows of a point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Visibility {
    /// The scan measured farther along its direction: the point is free space now.
    SeenThrough,
    /// The scan measured a return at the point.
    Hit,
    /// Something nearer hides it.
    Hidden,
    /// No return along its direction (sky, out of the field of view).
    Unknown,
}

/// The nearest range per direction cell of one scan.
#[derive(Clone, Debug, Default)]
pub struct RangeImage {
    columns: usize,
    rows: usize,
    /// Nearest range per cell (∞: no return).
    ranges: Vec<f32>,
}

impl RangeImage {
    /// Rebuilds the image from a scan's points in the sensor frame (ground included: it is
    /// what the laser hits after passing where an object was).
    pub fn build<'a>(&mut self, points: impl IntoIterator<Item = &'a Point>) {
        self.columns = (360.0 / AZIMUTH_STEP_DEG).round() as usize;
        self.rows = ((ELEVATION_MAX_DEG - ELEVATION_MIN_DEG) / ELEVATION_STEP_DEG).round() as usize;
        self.ranges.clear();
        self.ranges.resize(self.columns * self.rows, f32::INFINITY);
        for p in points {
            let v = Vector3::new(p.x as f64, p.y as f64, p.z as f64);
            if let Some((cell, range)) = self.cell_of(&v) {
                let r = &mut self.ranges[cell];
                *r = r.min(range as f32);
            }
        }
    }

    /// The cell and range of a sensor-frame point.
    fn cell_of(&self, p: &Vector3<f64>) -> Option<(usize, f64)> {
        let range = p.norm();
        if !range.is_finite() || range < 1e-3 || self.ranges.is_empty() {
            return None;
        }
        let azimuth = p.y.atan2(p.x).to_degrees().rem_euclid(360.0);
        let elevation = (p.z / range).asin().to_degrees();
        let column = ((azimuth / AZIMUTH_STEP_DEG) as usize).min(self.columns - 1);
        let row = (elevation - ELEVATION_MIN_DEG) / ELEVATION_STEP_DEG;
        if !(0.0..self.rows as f64).contains(&row) {
            return None;
        }
        Some((row as usize * self.columns + column, range))
    }

    /// What the scan shows of the sensor-frame point `p`. It is seen through only when the
    /// scan measured farther in its cell and the 8 cells around: a point on the edge of a
    /// thin post seen from a new angle is not free space.
    pub fn visibility(&self, p: &Vector3<f64>) -> Visibility {
        let Some((cell, range)) = self.cell_of(p) else {
            return Visibility::Unknown;
        };
        let (row, column) = ((cell / self.columns) as i64, (cell % self.columns) as i64);
        let mut measured = f64::INFINITY;
        for (dr, dc) in (-1..=1).flat_map(|a| (-1..=1).map(move |b| (a, b))) {
            let r = row + dr;
            if (0..self.rows as i64).contains(&r) {
                let c = (column + dc).rem_euclid(self.columns as i64);
                measured = measured.min(f64::from(
                    self.ranges[r as usize * self.columns + c as usize],
                ));
            }
        }
        if !measured.is_finite() {
            Visibility::Unknown
        } else if measured > range + HIT_TOLERANCE {
            Visibility::SeenThrough
        } else if measured >= range - HIT_TOLERANCE {
            Visibility::Hit
        } else {
            Visibility::Hidden
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A vertical wall of points at x = `x`, y in [-5, 5], z in [-1.5, 1].
    fn wall(x: f32) -> Vec<Point> {
        let mut out = Vec::new();
        for i in 0..500 {
            for k in 0..50 {
                out.push(Point::new(
                    x,
                    -5.0 + i as f32 * 0.02,
                    -1.5 + k as f32 * 0.05,
                    0.0,
                ));
            }
        }
        out
    }

    #[test]
    fn tells_seen_through_from_hit_and_hidden() {
        let mut image = RangeImage::default();
        image.build(&wall(10.0));
        assert_eq!(
            image.visibility(&Vector3::new(5.0, 0.0, 0.0)),
            Visibility::SeenThrough
        );
        assert_eq!(
            image.visibility(&Vector3::new(10.0, 0.5, 0.0)),
            Visibility::Hit
        );
        assert_eq!(
            image.visibility(&Vector3::new(15.0, 0.5, 0.0)),
            Visibility::Hidden
        );
        // Nothing measured behind the sensor.
        assert_eq!(
            image.visibility(&Vector3::new(-5.0, 0.0, 0.0)),
            Visibility::Unknown
        );
    }
}
