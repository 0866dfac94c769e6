//! The ground under the clusters, in the world frame: a plane (RANSAC's, or a horizontal one)
//! refined by a grid of local ground heights from the scan's ground points, so heights above
//! the ground stay right on slopes, crests and dips where one plane does not fit 50 m away.

use nalgebra::{Vector2, Vector3};

use crate::Point;

/// Edge of a ground cell (m).
const CELL: f64 = 2.0;
/// Cells a grid spans along x and y (centred on the sensor): ±60 m.
const CELLS: usize = 60;
/// Ground points a cell needs before its mean height is trusted.
const MIN_CELL_POINTS: u32 = 3;

/// Ground heights: a plane, refined by local cells where the scan saw the ground.
#[derive(Clone, Debug, PartialEq)]
pub struct Ground {
    /// Unit normal of the plane, pointing up.
    normal: Vector3<f64>,
    /// Offset of the plane: heights are `normal · p + offset`.
    offset: f64,
    /// World (x, y) of the grid's lower corner.
    corner: Vector2<f64>,
    /// Per cell: sum of ground z and count.
    cells: Vec<(f64, u32)>,
}

impl Ground {
    /// The plane `normal · p + offset = 0` (normal pointing up), without local cells.
    pub fn plane(normal: Vector3<f64>, offset: f64) -> Self {
        let n = normal.norm().max(1e-12);
        let (normal, offset) = if normal.z < 0.0 {
            (-normal / n, -offset / n)
        } else {
            (normal / n, offset / n)
        };
        Self {
            normal,
            offset,
            corner: Vector2::zeros(),
            cells: Vec::new(),
        }
    }

    /// A horizontal ground at height `z`.
    pub fn horizontal(z: f64) -> Self {
        Self::plane(Vector3::z(), -z)
    }

    /// Replaces the plane and forgets the local cells (their buffer is kept).
    pub fn set_plane(&mut self, normal: Vector3<f64>, offset: f64) {
        let plane = Self::plane(normal, offset);
        self.normal = plane.normal;
        self.offset = plane.offset;
        self.cells.clear();
    }

    /// Fills the local cells around `center` from the scan's ground points (world frame).
    pub fn fill_cells(&mut self, center: Vector2<f64>, points: &[Point]) {
        let half = CELL * CELLS as f64 / 2.0;
        self.corner = center - Vector2::repeat(half);
        self.cells.clear();
        self.cells.resize(CELLS * CELLS, (0.0, 0));
        for p in points {
            if let Some(k) = self.cell_of(p.x as f64, p.y as f64) {
                let c = &mut self.cells[k];
                c.0 += p.z as f64;
                c.1 += 1;
            }
        }
    }

    /// Index of the cell holding (x, y), if inside the grid.
    fn cell_of(&self, x: f64, y: f64) -> Option<usize> {
        if self.cells.is_empty() {
            return None;
        }
        // Truncation is the floor on the grid (without a call to the C library's floor: the
        // build's baseline x86-64 has no rounding instruction); NaN is outside.
        let (i, j) = ((x - self.corner.x) / CELL, (y - self.corner.y) / CELL);
        let inside = (0.0..CELLS as f64).contains(&i) && (0.0..CELLS as f64).contains(&j);
        inside.then(|| j as usize * CELLS + i as usize)
    }

    /// The world z of the ground straight below (or above) `p`: the mean of the ground points
    /// of its cell (or of the 3 × 3 cells around it), else the plane.
    pub fn z_below(&self, p: &Vector3<f64>) -> f64 {
        if let Some(k) = self.cell_of(p.x, p.y) {
            let (sum, count) = self.cells[k];
            if count >= MIN_CELL_POINTS {
                return sum / count as f64;
            }
            let (i, j) = ((k % CELLS) as i64, (k / CELLS) as i64);
            let (mut sum, mut count) = (0.0, 0);
            for (di, dj) in (-1..=1).flat_map(|a| (-1..=1).map(move |b| (a, b))) {
                let (a, b) = (i + di, j + dj);
                if (0..CELLS as i64).contains(&a) && (0..CELLS as i64).contains(&b) {
                    let c = self.cells[b as usize * CELLS + a as usize];
                    sum += c.0;
                    count += c.1;
                }
            }
            if count >= MIN_CELL_POINTS {
                return sum / count as f64;
            }
        }
        if self.normal.z.abs() < 1e-6 {
            return p.z;
        }
        p.z - (self.normal.dot(p) + self.offset) / self.normal.z
    }

    /// Height of `p` above the ground.
    pub fn height(&self, p: &Vector3<f64>) -> f64 {
        p.z - self.z_below(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plane_gives_heights_along_its_normal_direction() {
        // Rising 5 % along x, through z = -1.73 at the origin.
        let g = Ground::plane(Vector3::new(-0.05, 0.0, 1.0), 1.73);
        assert!((g.z_below(&Vector3::new(0.0, 0.0, 5.0)) + 1.73).abs() < 1e-9);
        assert!((g.z_below(&Vector3::new(40.0, 3.0, 0.0)) - (2.0 - 1.73)).abs() < 1e-9);
        // An upside-down normal is turned up.
        let flipped = Ground::plane(Vector3::new(0.05, 0.0, -1.0), -1.73);
        assert!(
            (flipped.height(&Vector3::new(40.0, 3.0, 1.0))
                - g.height(&Vector3::new(40.0, 3.0, 1.0)))
            .abs()
                < 1e-9
        );
    }

    #[test]
    fn local_cells_follow_a_crest_the_plane_misses() {
        let mut g = Ground::horizontal(0.0);
        // Ground points on a crest: z = 1.5 m around x = 30, flat elsewhere.
        let mut points = Vec::new();
        for i in -50..50 {
            for j in -20..20 {
                let (x, y) = (i as f32, j as f32 * 0.5);
                let z = if (25.0..35.0).contains(&x) { 1.5 } else { 0.0 };
                points.push(Point::new(x, y, z, 0.0));
            }
        }
        g.fill_cells(Vector2::zeros(), &points);
        assert!((g.z_below(&Vector3::new(30.0, 2.0, 3.0)) - 1.5).abs() < 1e-6);
        assert!(g.z_below(&Vector3::new(-10.0, 2.0, 3.0)).abs() < 1e-6);
        // A car on the crest, its underside hiding one cell: the neighbours answer.
        let hidden: Vec<Point> = points
            .into_iter()
            .filter(|p| !(p.x >= 30.0 && p.x < 32.0 && p.y >= 2.0 && p.y < 4.0))
            .collect();
        g.fill_cells(Vector2::zeros(), &hidden);
        assert!((g.z_below(&Vector3::new(31.0, 3.0, 3.0)) - 1.5).abs() < 1e-6);
        // Far outside the grid, the plane.
        assert!(g.z_below(&Vector3::new(500.0, 0.0, 3.0)).abs() < 1e-9);
    }
}
