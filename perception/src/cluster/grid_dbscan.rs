//! Exact DBSCAN on a cell grid (after Gunawan 2013 and de Berg et al. 2017).
//!
//! Cells have edge just under `eps/√3`, so any two points of one cell are within `eps`: a cell
//! holding `min_points` points is all core without a single distance test, and the core points
//! of a cell always share a cluster, so clusters are joined cell to cell (one close pair is
//! enough) and a border point looks at one label per cell. Neighbours of a cell lie at most
//! two cells away along each axis. When the cloud is too wide for cells that small (see
//! [`CellGrid`]), the same phases run point by point.

use super::{
    Clustering, NOISE, Params, cell_grid::CellGrid, dist2, numbering::Numbering,
    union_find::UnionFind,
};
use crate::Point;

/// Above this many point pairs, two cells are first trimmed to the points that can reach the
/// other cell's box.
const TRIM_PAIRS: usize = 64;

/// Scratch of the grid DBSCAN, reused from frame to frame.
#[derive(Debug, Default)]
pub(crate) struct GridDbscan {
    grid: CellGrid,
    /// Cells are cliques (edge at most eps/√3): sets are kept per cell, not per point.
    clique: bool,
    /// Neighbour cells of cell `c`: `near[near_start[c]..near_start[c + 1]]`.
    near_start: Vec<u32>,
    near: Vec<u32>,
    /// Per grid position: whether the point is core.
    core: Vec<bool>,
    /// Per cell: how many core points it has (they come first in the cell after phase 1).
    core_count: Vec<u32>,
    /// Per cell: the box around its core points.
    core_box: Vec<Box3>,
    /// Per grid position: the point's cluster or noise.
    label: Vec<i32>,
    /// Sets of cells (clique cells) or of grid positions.
    union: UnionFind,
    numbering: Numbering,
    /// Scratch: points of two cells that can reach the other cell.
    trim_a: Vec<[f32; 3]>,
    trim_b: Vec<[f32; 3]>,
}

impl GridDbscan {
    /// Runs DBSCAN on `points` into `out.labels` / `out.core`.
    pub(crate) fn run(&mut self, points: &[Point], params: Params, out: &mut Clustering) {
        let clique_side = params.eps / 3f64.sqrt() * (1.0 - 1e-7);
        let side = self.grid.build(points, clique_side);
        self.clique = side <= clique_side;
        let reach = ((params.eps / side) * (1.0 + 1e-9)).floor() as i32 + 1;
        self.grid
            .neighbour_lists(reach, &mut self.near_start, &mut self.near);

        self.find_core(params);
        self.join_core(params);
        self.number_clusters();
        self.label_points(params);

        out.labels.clear();
        out.labels.resize(points.len(), NOISE);
        out.core.clear();
        out.core.resize(points.len(), false);
        for (k, &i) in self.grid.order().iter().enumerate() {
            out.labels[i as usize] = self.label[k];
            out.core[i as usize] = self.core[k];
        }
    }

    /// Phase 1: core flags; then each cell's core points are moved to its front.
    fn find_core(&mut self, params: Params) {
        let n = self.grid.order().len();
        self.core.clear();
        self.core.resize(n, false);
        self.core_count.clear();
        self.core_count.resize(self.grid.cell_count(), 0);
        for cell in 0..self.grid.cell_count() {
            let range = self.grid.cell_range(cell);
            let own = range.len();
            if self.clique && own >= params.min_points {
                self.core[range].fill(true);
                self.core_count[cell] = own as u32;
                continue;
            }
            let xyz = self.grid.xyz();
            let near =
                &self.near[self.near_start[cell] as usize..self.near_start[cell + 1] as usize];
            for k in range.clone() {
                let a = xyz[k];
                let mut count = if self.clique { own } else { 0 };
                'search: for &other in near {
                    if self.clique && other as usize == cell {
                        continue;
                    }
                    for &b in &xyz[self.grid.cell_range(other as usize)] {
                        if dist2(a, b) <= params.eps2 {
                            count += 1;
                            if count >= params.min_points {
                                break 'search;
                            }
                        }
                    }
                }
                self.core[k] = count >= params.min_points;
            }
            // Core points first (order inside a cell does not matter).
            let (order, xyz) = self.grid.order_and_xyz_mut();
            let mut front = range.start;
            for k in range.clone() {
                if self.core[k] {
                    order.swap(front, k);
                    xyz.swap(front, k);
                    self.core.swap(front, k);
                    front += 1;
                }
            }
            self.core_count[cell] = (front - range.start) as u32;
        }
    }

    /// Phase 2: core points within eps of each other join one set.
    fn join_core(&mut self, params: Params) {
        let cells = self.grid.cell_count();
        self.core_box.clear();
        for cell in 0..cells {
            self.core_box
                .push(bounding_box(&self.grid.xyz()[self.core_range(cell)]));
        }
        self.union.reset(if self.clique {
            cells
        } else {
            self.grid.order().len()
        });
        for cell in 0..cells {
            if self.core_count[cell] == 0 {
                continue;
            }
            // Each pair once: the cells after this one (a clique cell's core points are
            // joined already), or from this one on. The list is ascending.
            let near = self.near_start[cell] as usize..self.near_start[cell + 1] as usize;
            let first = near.start
                + self.near[near.clone()]
                    .partition_point(|&other| other < cell as u32 + u32::from(self.clique));
            // The set of this cell, looked up again only after a union.
            let mut root = self.union.find(cell as u32);
            for i in first..near.end {
                let other = self.near[i] as usize;
                if self.clique {
                    if self.core_count[other] == 0 || root == self.union.find(other as u32) {
                        continue;
                    }
                    if self.cells_touch(cell, other, params) {
                        self.union.union(cell as u32, other as u32);
                        root = self.union.find(cell as u32);
                    }
                } else {
                    self.join_pairs(cell, other, params);
                }
            }
        }
    }

    /// Joins every core pair within eps between two cells, point by point (`a == b` allowed).
    fn join_pairs(&mut self, a: usize, b: usize, params: Params) {
        let xyz = self.grid.xyz();
        for i in self.core_range(a) {
            for j in self.core_range(b) {
                if dist2(xyz[i], xyz[j]) <= params.eps2 {
                    self.union.union(i as u32, j as u32);
                }
            }
        }
    }

    /// Whether some core point of `a` lies within eps of some core point of `b`.
    fn cells_touch(&mut self, a: usize, b: usize, params: Params) -> bool {
        let (box_a, box_b) = (self.core_box[a], self.core_box[b]);
        let reach2 = params.eps2 * (1.0 + 1e-9);
        if box_gap2(box_a, box_b) > reach2 {
            return false;
        }
        if box_span2(box_a, box_b) <= params.eps2 {
            // Every pair is within eps.
            return true;
        }
        let xyz = self.grid.xyz();
        let pa = &xyz[self.core_range(a)];
        let pb = &xyz[self.core_range(b)];
        if pa.len() * pb.len() <= TRIM_PAIRS {
            return any_pair_within(pa, pb, params.eps2);
        }
        // Keep only the points that can reach the other cell's core box.
        self.trim_a.clear();
        self.trim_a
            .extend(pa.iter().filter(|&&p| box_gap2([p, p], box_b) <= reach2));
        self.trim_b.clear();
        self.trim_b
            .extend(pb.iter().filter(|&&p| box_gap2([p, p], box_a) <= reach2));
        any_pair_within(&self.trim_a, &self.trim_b, params.eps2)
    }

    /// Phase 3: cluster numbers in the order of each cluster's lowest input index.
    fn number_clusters(&mut self) {
        let order = self.grid.order();
        let elements = if self.clique {
            self.grid.cell_count()
        } else {
            order.len()
        };
        let grid = &self.grid;
        let core_count = &self.core_count;
        let core_range = |cell: usize| {
            let start = grid.cell_range(cell).start;
            start..start + core_count[cell] as usize
        };
        if self.clique {
            // One element per cell: its lowest core index is all the numbering needs.
            let cells = (0..grid.cell_count()).filter_map(|cell| {
                let lowest = order[core_range(cell)].iter().min()?;
                Some((cell as u32, *lowest))
            });
            self.numbering.number(&mut self.union, elements, cells);
        } else {
            let points = (0..grid.cell_count())
                .flat_map(|cell| core_range(cell).map(|k| (k as u32, order[k])));
            self.numbering.number(&mut self.union, elements, points);
        }
    }

    /// Phase 4: every point's cluster; border points take the lowest-numbered cluster among
    /// the core points within eps.
    fn label_points(&mut self, params: Params) {
        self.label.clear();
        self.label.resize(self.grid.order().len(), NOISE);
        for cell in 0..self.grid.cell_count() {
            let cores = self.core_range(cell);
            if self.clique {
                if !cores.is_empty() {
                    let label = self.numbering.label(&mut self.union, cell as u32);
                    self.label[cores].fill(label);
                }
            } else {
                for k in cores {
                    self.label[k] = self.numbering.label(&mut self.union, k as u32);
                }
            }
        }
        let xyz = self.grid.xyz();
        for cell in 0..self.grid.cell_count() {
            let range = self.grid.cell_range(cell);
            let borders = range.start + self.core_count[cell] as usize..range.end;
            let near =
                &self.near[self.near_start[cell] as usize..self.near_start[cell + 1] as usize];
            for k in borders {
                let a = xyz[k];
                let mut best = i32::MAX;
                for &other in near {
                    let cores = self.core_range(other as usize);
                    if cores.is_empty() {
                        continue;
                    }
                    if self.clique {
                        let label = self.label[cores.start];
                        if label < best && xyz[cores].iter().any(|&b| dist2(a, b) <= params.eps2) {
                            best = label;
                        }
                    } else {
                        for q in cores {
                            if self.label[q] < best && dist2(a, xyz[q]) <= params.eps2 {
                                best = self.label[q];
                            }
                        }
                    }
                }
                if best != i32::MAX {
                    self.label[k] = best;
                }
            }
        }
    }

    /// Grid positions of the core points of `cell`.
    fn core_range(&self, cell: usize) -> std::ops::Range<usize> {
        let start = self.grid.cell_range(cell).start;
        start..start + self.core_count[cell] as usize
    }
}

/// Whether some point of `a` lies within `sqrt(eps2)` of some point of `b`.
fn any_pair_within(a: &[[f32; 3]], b: &[[f32; 3]], eps2: f64) -> bool {
    a.iter().any(|&p| b.iter().any(|&q| dist2(p, q) <= eps2))
}

/// An axis-aligned box: lower and upper corner.
type Box3 = [[f32; 3]; 2];

/// The box around some points (inverted, i.e. empty, when there are none).
fn bounding_box(points: &[[f32; 3]]) -> Box3 {
    let mut b = [[f32::INFINITY; 3], [f32::NEG_INFINITY; 3]];
    for p in points {
        for axis in 0..3 {
            // Plain comparisons (one minss/maxss each; f32::min adds NaN handling).
            b[0][axis] = if p[axis] < b[0][axis] {
                p[axis]
            } else {
                b[0][axis]
            };
            b[1][axis] = if p[axis] > b[1][axis] {
                p[axis]
            } else {
                b[1][axis]
            };
        }
    }
    b
}

/// Squared distance between the farthest corners of two boxes, computed as [`dist2`]
/// computes it: never less than the squared distance it computes between a point of one and
/// a point of the other (rounding is monotonic).
fn box_span2(a: Box3, b: Box3) -> f64 {
    let mut d2 = 0.0;
    for axis in 0..3 {
        let span =
            (b[1][axis] as f64 - a[0][axis] as f64).max(a[1][axis] as f64 - b[0][axis] as f64);
        d2 += span * span;
    }
    d2
}

/// Squared gap between two boxes (0 when they overlap): never more than the squared distance
/// [`dist2`] computes between a point of one and a point of the other.
fn box_gap2(a: Box3, b: Box3) -> f64 {
    let mut d2 = 0.0;
    for axis in 0..3 {
        let gap = (b[0][axis] as f64 - a[1][axis] as f64)
            .max(a[0][axis] as f64 - b[1][axis] as f64)
            .max(0.0);
        d2 += gap * gap;
    }
    d2
}
