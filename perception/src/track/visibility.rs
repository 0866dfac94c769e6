//! What the current scan sees along each direction: a range image of the filtered scan, in
//! the sensor frame. It answers the question that separates a moving object from a wall whose
//! visible part slides along it as the vehicle passes: is the place where the object was a
//! moment ago now seen through (the laser went past it and hit something farther), still hit,
//! or hidden?
//!
//! A static object can never be seen through where it stands; an object that moved away can.

use nalgebra::Vector3;

use crate::Point;
use crate::angle::fast_atan2_branchless;

/// Azimuth resolution of the image (degrees).
const AZIMUTH_STEP_DEG: f64 = 0.25;
/// Elevation resolution (degrees) and the band covered, generous for a 64-beam sensor.
const ELEVATION_STEP_DEG: f64 = 0.5;
const ELEVATION_MIN_DEG: f64 = -30.0;
const ELEVATION_MAX_DEG: f64 = 10.0;
/// Ranges within this (m) of a probe's count as hitting it.
const HIT_TOLERANCE: f64 = 0.4;
/// Cells around a point that measured more than this (m) nearer than it show an occluder in
/// front of it, not the space around it (see [`RangeImage::visibility_past_occluders`]).
const OCCLUDER_GAP: f64 = 2.0;
/// The widest window [`RangeImage::visibility_across`] looks at: this many columns to either
/// side (5 degrees).
const MAX_HALF_COLUMNS: i64 = 20;
/// A direction whose fast angles ([`fast_atan2_branchless`], in `f32`) lie within this fraction of a cell
/// of a cell boundary is placed by the library's `atan2` and `asin` instead: the fast angles'
/// error (below 1e-5 rad) is under a quarter of it (4.4e-5 rad for a column, 8.7e-5 rad for a
/// row), so every point lands in the cell the library's functions give.
const EXACT_MARGIN: f64 = 0.01;

/// Points [`RangeImage::build`] places at once.
const CHUNK: usize = 64;

/// A batch of points on their way into the image (coordinates axis by axis), with their fast
/// angles (in cell units) and ranges.
struct Chunk {
    x: [f32; CHUNK],
    y: [f32; CHUNK],
    z: [f32; CHUNK],
    range: [f32; CHUNK],
    column: [f32; CHUNK],
    row: [f32; CHUNK],
    len: usize,
}

impl Default for Chunk {
    fn default() -> Self {
        Self {
            x: [0.0; CHUNK],
            y: [0.0; CHUNK],
            z: [0.0; CHUNK],
            range: [0.0; CHUNK],
            column: [0.0; CHUNK],
            row: [0.0; CHUNK],
            len: 0,
        }
    }
}

/// Where the fast angles put a direction.
enum FastCell {
    /// In this cell.
    Cell(usize),
    /// Outside the image's elevation band.
    Outside,
    /// Too near a cell boundary to tell: the library's functions decide.
    Exact,
}

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
        let mut chunk = Chunk::default();
        for p in points {
            let k = chunk.len;
            (chunk.x[k], chunk.y[k], chunk.z[k]) = (p.x, p.y, p.z);
            chunk.len += 1;
            if chunk.len == CHUNK {
                self.add_chunk(&mut chunk);
            }
        }
        self.add_chunk(&mut chunk);
    }

    /// Adds the points of `chunk` and empties it: the fast angles of all of them first, in one
    /// loop over arrays (SIMD), then each point into its cell.
    fn add_chunk(&mut self, chunk: &mut Chunk) {
        for k in 0..CHUNK {
            let (x, y, z) = (chunk.x[k], chunk.y[k], chunk.z[k]);
            let horizontal = (x * x + y * y).sqrt();
            chunk.range[k] = (horizontal * horizontal + z * z).sqrt();
            (chunk.column[k], chunk.row[k]) = self.fast_angles(x, y, z, horizontal);
        }
        for k in 0..chunk.len {
            let range = chunk.range[k];
            if !range.is_finite() || range < 1e-3 {
                continue;
            }
            let placed = match self.fast_cell(chunk.column[k], chunk.row[k]) {
                FastCell::Cell(cell) => Some((cell, range)),
                FastCell::Outside => None,
                FastCell::Exact => {
                    let p = Vector3::new(chunk.x[k], chunk.y[k], chunk.z[k]).map(f64::from);
                    self.exact_cell_of(&p, p.norm())
                        .map(|(cell, range)| (cell, range as f32))
                }
            };
            if let Some((cell, range)) = placed {
                let r = &mut self.ranges[cell];
                *r = r.min(range);
            }
        }
        chunk.len = 0;
    }

    /// The cell and range of a sensor-frame point: [`Self::exact_cell_of`]'s answer, from fast
    /// angles unless they are too near a cell boundary to tell.
    fn cell_of(&self, p: &Vector3<f64>) -> Option<(usize, f64)> {
        let range = p.norm();
        if !range.is_finite() || range < 1e-3 || self.ranges.is_empty() {
            return None;
        }
        let (x, y, z) = (p.x as f32, p.y as f32, p.z as f32);
        let (column, row) = self.fast_angles(x, y, z, (x * x + y * y).sqrt());
        match self.fast_cell(column, row) {
            FastCell::Cell(cell) => Some((cell, range)),
            FastCell::Outside => None,
            FastCell::Exact => self.exact_cell_of(p, range),
        }
    }

    /// The direction of sensor-frame point (x, y, z), `horizontal` from the sensor, in cell
    /// units from the fast angles: the column counter-clockwise from +x, the row from the
    /// band's lower edge. Branch-free, so that a loop over points runs it on SIMD registers.
    #[inline]
    fn fast_angles(&self, x: f32, y: f32, z: f32, horizontal: f32) -> (f32, f32) {
        let columns_per_rad = (self.columns as f64 / std::f64::consts::TAU) as f32;
        let rows_per_rad = (1.0f64.to_degrees() / ELEVATION_STEP_DEG) as f32;
        let row_offset = (ELEVATION_MIN_DEG / ELEVATION_STEP_DEG) as f32;
        let column = fast_atan2_branchless(y, x) * columns_per_rad;
        let column = if column < 0.0 {
            column + self.columns as f32
        } else {
            column
        };
        let row = fast_atan2_branchless(z, horizontal) * rows_per_rad - row_offset;
        (column, row)
    }

    /// Where [`Self::fast_angles`]' `column` and `row` put a direction.
    fn fast_cell(&self, column: f32, row: f32) -> FastCell {
        let margin = EXACT_MARGIN as f32;
        if !(-margin..self.rows as f32 + margin).contains(&row) {
            return FastCell::Outside;
        }
        // Both are ≥ -EXACT_MARGIN here.
        let near_boundary = |u: f32| !(margin..=1.0 - margin).contains(&(u - u.trunc()));
        if near_boundary(column) || near_boundary(row) {
            return FastCell::Exact;
        }
        let (column, row) = ((column as usize).min(self.columns - 1), row as usize);
        FastCell::Cell(row * self.columns + column)
    }

    /// The cell of a sensor-frame point at `range` (its norm, ≥ 1 mm) from the library's
    /// `atan2` and `asin`.
    fn exact_cell_of(&self, p: &Vector3<f64>, range: f64) -> Option<(usize, f64)> {
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
    /// scan measured farther in its cell, the cell rows above and below, and the columns up to
    /// `half_width` metres to either side of it at its range (at least one: a half-width of 0
    /// is the cell and its 8 neighbours). A point on the edge of a thin post seen from a new
    /// angle, or from a pose a little off, is not free space.
    pub fn visibility_across(&self, p: &Vector3<f64>, half_width: f64) -> Visibility {
        self.visibility_in_window(p, half_width, f64::INFINITY)
    }

    /// As [`Self::visibility_across`], but the cells around `p`'s own that measured more than
    /// `OCCLUDER_GAP` nearer than it are left out: what stands well in front of a point
    /// (a parked car hiding a walker's legs, from the rows below) tells nothing of the space
    /// at the point. Its own cell measuring nearer still hides it.
    pub fn visibility_past_occluders(&self, p: &Vector3<f64>, half_width: f64) -> Visibility {
        self.visibility_in_window(p, half_width, OCCLUDER_GAP)
    }

    /// What the scan shows of `p`, judged on the nearest range of its own cell and of the
    /// cells around it (one row to either side, the columns within `half_width` metres) that
    /// measured at most `occluder_gap` nearer than `p`.
    fn visibility_in_window(
        &self,
        p: &Vector3<f64>,
        half_width: f64,
        occluder_gap: f64,
    ) -> Visibility {
        let Some((cell, range)) = self.cell_of(p) else {
            return Visibility::Unknown;
        };
        let horizontal = (p.x * p.x + p.y * p.y).sqrt();
        let angle = (half_width / horizontal.max(1e-3)).atan().to_degrees();
        let half_columns = ((angle / AZIMUTH_STEP_DEG).ceil() as i64).clamp(1, MAX_HALF_COLUMNS);
        let nearest_counted = (range - occluder_gap) as f32;
        let (row, column) = ((cell / self.columns) as i64, (cell % self.columns) as i64);
        let mut measured = f64::from(self.ranges[cell]);
        for r in (row - 1..=row + 1).filter(|r| (0..self.rows as i64).contains(r)) {
            for dc in -half_columns..=half_columns {
                let c = (column + dc).rem_euclid(self.columns as i64);
                let around = self.ranges[r as usize * self.columns + c as usize];
                if around >= nearest_counted {
                    measured = measured.min(f64::from(around));
                }
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

    /// `count` sensor-frame points within 60 m (8 m in height), every fourth exactly on a
    /// cell boundary, where the fast angles hand over to the library's.
    fn sample_points(count: usize) -> Vec<Vector3<f64>> {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut uniform = |range: f64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 * range - range
        };
        (0..count)
            .map(|i| {
                let p = Vector3::new(uniform(60.0), uniform(60.0), uniform(8.0));
                if i % 4 != 0 {
                    return p;
                }
                let azimuth = (uniform(720.0).round() * 0.25).to_radians();
                let elevation = (uniform(40.0).round() * 0.5).to_radians();
                let r = 1.0 + uniform(40.0).abs();
                Vector3::new(
                    r * elevation.cos() * azimuth.cos(),
                    r * elevation.cos() * azimuth.sin(),
                    r * elevation.sin(),
                )
            })
            .collect()
    }

    #[test]
    fn cells_are_the_library_functions_cells() {
        let mut image = RangeImage::default();
        image.build(&wall(10.0));
        let mut placed = 0;
        for p in sample_points(200_000) {
            let expected = image.exact_cell_of(&p, p.norm());
            assert_eq!(image.cell_of(&p), expected, "{p:?}");
            placed += usize::from(expected.is_some());
        }
        assert!(placed > 10_000, "{placed}");
    }

    #[test]
    fn build_puts_every_point_in_the_library_functions_cell() {
        let points: Vec<Point> = sample_points(50_000)
            .iter()
            .map(|p| Point::new(p.x as f32, p.y as f32, p.z as f32, 0.0))
            .collect();
        let mut image = RangeImage::default();
        image.build(&points);
        let mut expected = vec![f32::INFINITY; image.ranges.len()];
        for p in &points {
            let v = Vector3::new(p.x, p.y, p.z).map(f64::from);
            if let Some((cell, range)) = image.exact_cell_of(&v, v.norm()) {
                expected[cell] = expected[cell].min(range as f32);
            }
        }
        let placed = expected.iter().filter(|r| r.is_finite()).count();
        assert!(placed > 10_000, "{placed}");
        for (cell, (got, want)) in image.ranges.iter().zip(&expected).enumerate() {
            assert!(
                got == want || (got - want).abs() <= 1e-5 * want,
                "cell {cell}: {got} vs {want}"
            );
        }
    }

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
    fn a_wide_window_does_not_see_through_beside_a_thin_post() {
        // A post 0.15 m wide 15 m away, a wall 40 m away behind it.
        let mut points = wall(40.0);
        for k in 0..40 {
            for i in 0..4 {
                let y = -0.075 + 0.05 * i as f32;
                points.push(Point::new(15.0, y, -1.5 + 0.05 * k as f32, 0.0));
            }
        }
        let mut image = RangeImage::default();
        image.build(&points);
        // Where a view from a slightly wrong pose puts the post's edge: 0.2 m to its side.
        let beside = Vector3::new(15.0, 0.2, -0.5);
        assert_eq!(
            image.visibility_across(&beside, 0.0),
            Visibility::SeenThrough
        );
        assert_eq!(image.visibility_across(&beside, 0.4), Visibility::Hit);
        assert_eq!(
            image.visibility_past_occluders(&beside, 0.4),
            Visibility::Hit
        );
        // Nothing within 0.4 m: free space either way.
        let clear = Vector3::new(15.0, 1.0, -0.5);
        assert_eq!(
            image.visibility_across(&clear, 0.4),
            Visibility::SeenThrough
        );
    }

    #[test]
    fn an_occluder_well_in_front_hides_only_its_own_directions_past_occluders() {
        // A wall 40 m away; 15 m away, a low wall reaching up to the row just below the
        // direction 1.75° down (row boundaries every 0.5° from -30°).
        let mut points = wall(40.0);
        let top = 15.0 * (-2.25f32).to_radians().tan();
        for i in 0..200 {
            for k in 0..=((top + 1.5) / 0.02) as usize {
                let z = -1.5 + k as f32 * 0.02;
                points.push(Point::new(15.0, -2.0 + i as f32 * 0.02, z, 0.0));
            }
        }
        let mut image = RangeImage::default();
        image.build(&points);
        // 20 m away, above the low wall's top row: the rows below show the wall in front.
        let above = Vector3::new(20.0, 0.0, 20.0 * (-1.75f64).to_radians().tan());
        assert_eq!(image.visibility_across(&above, 0.15), Visibility::Hidden);
        assert_eq!(
            image.visibility_past_occluders(&above, 0.15),
            Visibility::SeenThrough
        );
        // Straight behind the low wall: hidden either way.
        let behind = Vector3::new(20.0, 0.0, 20.0 * (-3.25f64).to_radians().tan());
        assert_eq!(
            image.visibility_past_occluders(&behind, 0.15),
            Visibility::Hidden
        );
        // Within the gap of the low wall: it still counts.
        let near = Vector3::new(16.5, 0.0, 16.5 * (-1.75f64).to_radians().tan());
        assert_eq!(
            image.visibility_past_occluders(&near, 0.15),
            Visibility::Hidden
        );
    }

    #[test]
    fn tells_seen_through_from_hit_and_hidden() {
        let mut image = RangeImage::default();
        image.build(&wall(10.0));
        assert_eq!(
            image.visibility_across(&Vector3::new(5.0, 0.0, 0.0), 0.0),
            Visibility::SeenThrough
        );
        assert_eq!(
            image.visibility_across(&Vector3::new(10.0, 0.5, 0.0), 0.0),
            Visibility::Hit
        );
        assert_eq!(
            image.visibility_across(&Vector3::new(15.0, 0.5, 0.0), 0.0),
            Visibility::Hidden
        );
        // Nothing measured behind the sensor.
        assert_eq!(
            image.visibility_across(&Vector3::new(-5.0, 0.0, 0.0), 0.0),
            Visibility::Unknown
        );
    }
}
