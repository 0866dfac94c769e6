//! A cubic-cell grid over a point cloud, built without hashing: points are bucketed by their
//! (x, y) column with a counting sort over a dense column table, then ordered by z-cell inside
//! each column, so every cell is a contiguous run of points and the cells of a column are sorted
//! by height. The grid DBSCAN's index; all buffers are reused from frame to frame.

use crate::Point;

/// Most (x, y) columns the dense column table may hold (16 MiB of offsets); wider clouds get
/// coarser cells.
const MAX_COLUMNS: usize = 1 << 22;

/// Most z-cells for which columns are ordered by one counting sort over the z-cells (a
/// LiDAR scan spans a few dozen); taller clouds sort column by column.
const MAX_ZCELLS: usize = 1 << 16;

/// Most cells along one axis (keeps cell coordinates far inside `i32`).
const MAX_CELLS_PER_AXIS: f64 = (1u64 << 30) as f64;

/// The integer coordinates of a grid cell.
pub(crate) type CellCoord = [i32; 3];

/// Points bucketed into cubic cells (see the module docs).
#[derive(Debug, Default)]
pub(crate) struct CellGrid {
    /// Number of columns along x and y.
    nx: usize,
    ny: usize,
    /// Indices of the input points, cell after cell (non-finite points are left out).
    order: Vec<u32>,
    /// Positions of the points in `order`, as `f32` copies for cache-friendly scans.
    xyz: Vec<[f32; 3]>,
    /// Start of each cell in `order`; one more entry than cells.
    cell_start: Vec<u32>,
    /// Integer coordinates of each cell.
    cell_coord: Vec<CellCoord>,
    /// Start of each column's cells in `cell_start`; `nx * ny + 1` entries.
    column_cells: Vec<u32>,
    /// Scratch: column and z-cell of every input point (`u32::MAX`: left out).
    point_column: Vec<u32>,
    point_zcell: Vec<i32>,
    /// Scratch: the (z-cell, index) pairs of one column while sorting it.
    column_scratch: Vec<(i32, u32)>,
    /// Scratch: the kept points by z-cell, then index, and each z-cell's start among them.
    by_zcell: Vec<u32>,
    zcell_start: Vec<u32>,
    /// Scratch: per neighbouring column, the next of its cells that may still be in reach.
    cursors: Vec<(usize, usize)>,
}

impl CellGrid {
    /// Rebuilds the grid over the finite points of `points` with cells of edge at least
    /// `min_side` (metres, > 0). The edge grows only when the cloud is too wide for the dense
    /// column table. Returns the edge used.
    pub(crate) fn build(&mut self, points: &[Point], min_side: f64) -> f64 {
        let (lowest, hi) = bounds(points);
        let extent = [0, 1, 2].map(|axis| hi[axis] - lowest[axis]);
        let mut side = min_side
            .max(extent[0].max(extent[1]).max(extent[2]) / MAX_CELLS_PER_AXIS)
            .max(((extent[0] + min_side) * (extent[1] + min_side) / MAX_COLUMNS as f64).sqrt());
        if !side.is_finite() || side <= 0.0 {
            side = 1.0;
        }
        // Cells are aligned to multiples of the edge, so a cell's place does not depend on
        // where the cloud happens to start.
        let (lo, nx, ny) = loop {
            let lo = lowest.map(|v| (v / side).floor() * side);
            let nx = ((hi[0] - lo[0]) * (1.0 / side)) as usize + 1;
            let ny = ((hi[1] - lo[1]) * (1.0 / side)) as usize + 1;
            if nx * ny <= MAX_COLUMNS {
                break (lo, nx, ny);
            }
            side *= 1.25;
        };
        let inv = 1.0 / side;
        self.nx = nx;
        self.ny = ny;
        let columns = nx * ny;

        // Column and z-cell of each point, and the size of each column.
        self.point_column.clear();
        self.point_zcell.clear();
        self.column_cells.clear();
        self.column_cells.resize(columns + 1, 0);
        let mut kept = 0usize;
        for p in points {
            if !finite_xyz(p) {
                self.point_column.push(u32::MAX);
                self.point_zcell.push(0);
                continue;
            }
            // Offsets from the lower corner are >= 0: truncation is floor (and much cheaper),
            // and they stay far below 2³¹ (see MAX_CELLS_PER_AXIS): the i32 conversion is one
            // instruction where the usize one is several.
            let cx = (((p.x as f64) - lo[0]) * inv) as i32 as usize;
            let cy = (((p.y as f64) - lo[1]) * inv) as i32 as usize;
            let cz = (((p.z as f64) - lo[2]) * inv) as i32;
            let column = cx.min(nx - 1) * ny + cy.min(ny - 1);
            self.point_column.push(column as u32);
            self.point_zcell.push(cz);
            self.column_cells[column + 1] += 1;
            kept += 1;
        }
        // Prefix sums: column_cells temporarily holds the start of each column in `order`.
        for c in 0..columns {
            self.column_cells[c + 1] += self.column_cells[c];
        }
        self.order.clear();
        self.order.resize(kept, 0);
        // Points in (z-cell, index) order, when the cloud is not too tall for a table of
        // z-cells: scattered into columns in that order, every column comes out sorted.
        let z_sorted = self.sort_by_zcell(kept);
        {
            // Scatter, using column_cells[c] as the write cursor of column c (shifted back below).
            let cursor = &mut self.column_cells;
            let mut place = |i: u32| {
                let column = self.point_column[i as usize];
                let slot = &mut cursor[column as usize];
                self.order[*slot as usize] = i;
                *slot += 1;
            };
            if z_sorted {
                self.by_zcell.iter().for_each(|&i| place(i));
            } else {
                (0..self.point_column.len() as u32)
                    .filter(|&i| self.point_column[i as usize] != u32::MAX)
                    .for_each(place);
            }
            // cursor[c] now holds the end of column c = start of column c + 1.
            for c in (1..=columns).rev() {
                cursor[c] = cursor[c - 1];
            }
            cursor[0] = 0;
        }

        // Sort every column by z-cell (then index, for determinism) unless it already is, and
        // cut it into cells.
        self.cell_start.clear();
        self.cell_coord.clear();
        let mut column_start = 0u32;
        for column in 0..columns {
            let column_end = self.column_cells[column + 1];
            // From here on column_cells[column] is the first cell of the column.
            self.column_cells[column] = self.cell_start.len() as u32;
            if column_end == column_start {
                continue;
            }
            let run = &mut self.order[column_start as usize..column_end as usize];
            if !z_sorted && run.len() > 1 {
                self.column_scratch.clear();
                self.column_scratch
                    .extend(run.iter().map(|&i| (self.point_zcell[i as usize], i)));
                self.column_scratch.sort_unstable();
                for (slot, &(_, i)) in run.iter_mut().zip(&self.column_scratch) {
                    *slot = i;
                }
            }
            let (cx, cy) = ((column / ny) as i32, (column % ny) as i32);
            let mut previous = None;
            for k in column_start..column_end {
                let cz = self.point_zcell[self.order[k as usize] as usize];
                if previous != Some(cz) {
                    self.cell_start.push(k);
                    self.cell_coord.push([cx, cy, cz]);
                    previous = Some(cz);
                }
            }
            column_start = column_end;
        }
        self.column_cells[columns] = self.cell_start.len() as u32;
        self.cell_start.push(kept as u32);

        self.xyz.clear();
        self.xyz
            .extend(self.order.iter().map(|&i| points[i as usize].xyz()));
        side
    }

    /// Fills `by_zcell` with the kept points (`kept` of them) ordered by z-cell, then index,
    /// with a counting sort over the z-cells; returns false, leaving it untouched, when
    /// there are more than [`MAX_ZCELLS`] z-cells.
    fn sort_by_zcell(&mut self, kept: usize) -> bool {
        let mut top = 0;
        for (&column, &cz) in self.point_column.iter().zip(&self.point_zcell) {
            if column != u32::MAX {
                top = top.max(cz);
            }
        }
        let zcells = top as usize + 1;
        if zcells > MAX_ZCELLS {
            return false;
        }
        let start = &mut self.zcell_start;
        start.clear();
        start.resize(zcells + 1, 0);
        for (&column, &cz) in self.point_column.iter().zip(&self.point_zcell) {
            if column != u32::MAX {
                start[cz as usize + 1] += 1;
            }
        }
        for z in 0..zcells {
            start[z + 1] += start[z];
        }
        self.by_zcell.clear();
        self.by_zcell.resize(kept, 0);
        for (i, (&column, &cz)) in self.point_column.iter().zip(&self.point_zcell).enumerate() {
            if column != u32::MAX {
                let slot = &mut start[cz as usize];
                self.by_zcell[*slot as usize] = i as u32;
                *slot += 1;
            }
        }
        true
    }

    /// Number of cells.
    pub(crate) fn cell_count(&self) -> usize {
        self.cell_coord.len()
    }

    /// The range of positions (in `order` / `xyz`) of the points in `cell`.
    pub(crate) fn cell_range(&self, cell: usize) -> std::ops::Range<usize> {
        self.cell_start[cell] as usize..self.cell_start[cell + 1] as usize
    }

    /// Integer coordinates of `cell`.
    #[cfg(test)]
    pub(crate) fn cell_coord(&self, cell: usize) -> CellCoord {
        self.cell_coord[cell]
    }

    /// Input indices of the points, cell after cell.
    pub(crate) fn order(&self) -> &[u32] {
        &self.order
    }

    /// Mutable input indices, to reorder points inside a cell (positions in `xyz` must follow).
    pub(crate) fn order_and_xyz_mut(&mut self) -> (&mut [u32], &mut [[f32; 3]]) {
        (&mut self.order, &mut self.xyz)
    }

    /// Positions of the points, cell after cell.
    pub(crate) fn xyz(&self) -> &[[f32; 3]] {
        &self.xyz
    }

    /// For every cell, the cells whose coordinates differ from its own by at most `reach`
    /// along each axis (itself included), ascending: cell `c`'s are
    /// `list[start[c]..start[c + 1]]`.
    pub(crate) fn neighbour_lists(
        &mut self,
        reach: i32,
        start: &mut Vec<u32>,
        list: &mut Vec<u32>,
    ) {
        start.clear();
        list.clear();
        let mut cursors = std::mem::take(&mut self.cursors);
        for column in 0..self.nx * self.ny {
            let first = self.column_cells[column] as usize;
            let last = self.column_cells[column + 1] as usize;
            if first == last {
                continue;
            }
            let (cx, cy) = ((column / self.ny) as i32, (column % self.ny) as i32);
            cursors.clear();
            for x in (cx - reach).max(0)..=(cx + reach).min(self.nx as i32 - 1) {
                for y in (cy - reach).max(0)..=(cy + reach).min(self.ny as i32 - 1) {
                    let other = x as usize * self.ny + y as usize;
                    let (a, b) = (self.column_cells[other], self.column_cells[other + 1]);
                    if a != b {
                        cursors.push((a as usize, b as usize));
                    }
                }
            }
            // The column's cells rise in z, so each cursor only moves forward.
            for cell in first..last {
                start.push(list.len() as u32);
                let cz = self.cell_coord[cell][2];
                for (next, end) in cursors.iter_mut() {
                    while *next < *end && self.cell_coord[*next][2] < cz - reach {
                        *next += 1;
                    }
                    let mut k = *next;
                    while k < *end && self.cell_coord[k][2] <= cz + reach {
                        list.push(k as u32);
                        k += 1;
                    }
                }
            }
        }
        start.push(list.len() as u32);
        self.cursors = cursors;
    }
}

/// Whether the point's coordinates are finite (intensity is not looked at).
pub(crate) fn finite_xyz(p: &Point) -> bool {
    p.x.is_finite() && p.y.is_finite() && p.z.is_finite()
}

/// Lower and upper corner of the finite points (zeros when there are none).
fn bounds(points: &[Point]) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in points.iter().filter(|p| finite_xyz(p)) {
        for (axis, v) in p.xyz().into_iter().enumerate() {
            // Plain comparisons: v is finite, f32::min's NaN handling is not needed.
            lo[axis] = if v < lo[axis] { v } else { lo[axis] };
            hi[axis] = if v > hi[axis] { v } else { hi[axis] };
        }
    }
    if lo[0] > hi[0] {
        return ([0.0; 3], [0.0; 3]);
    }
    (lo.map(f64::from), hi.map(f64::from))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid_of(points: &[Point], side: f64) -> CellGrid {
        let mut grid = CellGrid::default();
        grid.build(points, side);
        grid
    }

    #[test]
    fn every_finite_point_lands_in_the_cell_of_its_coordinates() {
        let points: Vec<Point> = (0..500)
            .map(|i| {
                let f = i as f32;
                Point::new(
                    (f * 0.37).sin() * 9.0,
                    (f * 0.11).cos() * 7.0,
                    f * 0.01,
                    0.0,
                )
            })
            .chain([Point::new(f32::NAN, 0.0, 0.0, 0.0)])
            .collect();
        let grid = grid_of(&points, 0.5);
        assert_eq!(grid.order().len(), 500);
        let finite = &points[..500];
        let min = |axis: usize| {
            finite
                .iter()
                .map(|p| p.xyz()[axis])
                .fold(f32::INFINITY, f32::min) as f64
        };
        let lo = [min(0), min(1), min(2)];
        let mut seen = vec![false; points.len()];
        for cell in 0..grid.cell_count() {
            let coord = grid.cell_coord(cell);
            for k in grid.cell_range(cell) {
                let i = grid.order()[k] as usize;
                seen[i] = true;
                assert_eq!(grid.xyz()[k], points[i].xyz());
                for axis in 0..3 {
                    let v = points[i].xyz()[axis] as f64;
                    let expected = (v / 0.5).floor() - (lo[axis] / 0.5).floor();
                    assert_eq!(expected as i32, coord[axis]);
                }
            }
        }
        assert!(seen[..500].iter().all(|&s| s));
        assert!(!seen[500]);
    }

    #[test]
    fn neighbour_lists_hold_exactly_the_cells_within_reach() {
        let points: Vec<Point> = (0..300)
            .map(|i| {
                let f = i as f32;
                Point::new(
                    (f * 0.7).sin() * 3.0,
                    (f * 0.3).cos() * 3.0,
                    (f * 0.9).sin(),
                    0.0,
                )
            })
            .collect();
        let mut grid = grid_of(&points, 0.4);
        let (mut start, mut list) = (Vec::new(), Vec::new());
        grid.neighbour_lists(2, &mut start, &mut list);
        assert_eq!(start.len(), grid.cell_count() + 1);
        for cell in 0..grid.cell_count() {
            let near = &list[start[cell] as usize..start[cell + 1] as usize];
            let a = grid.cell_coord(cell);
            let expected: Vec<u32> = (0..grid.cell_count())
                .filter(|&other| {
                    let b = grid.cell_coord(other);
                    (0..3).all(|k| (a[k] - b[k]).abs() <= 2)
                })
                .map(|c| c as u32)
                .collect();
            assert_eq!(near, &expected[..]);
        }
    }

    /// Every cell's points are in ascending index order, and a column's cells rise in z.
    fn assert_ordered(grid: &CellGrid) {
        for cell in 0..grid.cell_count() {
            let order = &grid.order()[grid.cell_range(cell)];
            assert!(order.windows(2).all(|w| w[0] < w[1]));
            if cell + 1 < grid.cell_count() {
                let (a, b) = (grid.cell_coord(cell), grid.cell_coord(cell + 1));
                assert!(a[..2] != b[..2] || a[2] < b[2], "{a:?} {b:?}");
            }
        }
    }

    #[test]
    fn columns_come_out_sorted_by_height_whether_short_or_tall() {
        let mut state = 5u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        // A scan-like cloud (a few dozen z-cells) and a tower taller than MAX_ZCELLS cells.
        for height in [8.0f32, 1.0e5] {
            let points: Vec<Point> = (0..3000)
                .map(|_| Point::new(next() * 4.0, next() * 4.0, next() * height, 0.0))
                .collect();
            let grid = grid_of(&points, 0.5);
            assert_eq!(grid.order().len(), points.len());
            assert_ordered(&grid);
        }
    }

    #[test]
    fn a_very_wide_cloud_gets_coarser_cells_instead_of_a_huge_table() {
        let points = [
            Point::new(-1.0e6, -1.0e6, 0.0, 0.0),
            Point::new(1.0e6, 1.0e6, 0.0, 0.0),
        ];
        let mut grid = CellGrid::default();
        let side = grid.build(&points, 0.1);
        assert!(side > 0.1);
        assert!(grid.nx * grid.ny <= MAX_COLUMNS);
        assert_eq!(grid.cell_count(), 2);
    }
}
