//! Exact DBSCAN on a kiddo immutable k-d tree: one radius query per point for the core test,
//! one per core point to join clusters, one per non-core point to find its cluster.
//!
//! kiddo's own distance may round differently from scikit-learn's, so the tree is asked for a
//! hair more than eps and every candidate is re-tested with [`dist2`].

use kiddo::{ImmutableKdTree, SquaredEuclidean};

use super::cell_grid::finite_xyz;
use super::{
    ClusterError, Clustering, NOISE, Params, dist2, numbering::Numbering, union_find::UnionFind,
};
use crate::Point;

/// Scratch of the k-d tree DBSCAN (the tree itself is rebuilt per run).
#[derive(Debug, Default)]
pub(crate) struct KdTreeDbscan {
    /// Input index of each finite point.
    index: Vec<u32>,
    /// The finite points as given.
    xyz: Vec<[f32; 3]>,
    /// The finite points widened for the tree.
    xyz64: Vec<[f64; 3]>,
    core: Vec<bool>,
    label: Vec<i32>,
    union: UnionFind,
    numbering: Numbering,
}

impl KdTreeDbscan {
    /// Runs DBSCAN on `points` into `out.labels` / `out.core`.
    pub(crate) fn run(
        &mut self,
        points: &[Point],
        params: Params,
        out: &mut Clustering,
    ) -> Result<(), ClusterError> {
        self.index.clear();
        self.xyz.clear();
        self.xyz64.clear();
        for (i, p) in points.iter().enumerate().filter(|(_, p)| finite_xyz(p)) {
            self.index.push(i as u32);
            self.xyz.push(p.xyz());
            self.xyz64.push(p.xyz().map(f64::from));
        }
        out.labels.clear();
        out.labels.resize(points.len(), NOISE);
        out.core.clear();
        out.core.resize(points.len(), false);
        let n = self.xyz.len();
        if n == 0 {
            return Ok(());
        }
        let tree: ImmutableKdTree<f64, 3> =
            ImmutableKdTree::new_from_slice(&self.xyz64).map_err(|_| {
                ClusterError::TooManyPoints {
                    got: n,
                    max: u32::MAX as usize - 1,
                }
            })?;
        let radius = params.eps2 * (1.0 + 1e-9);
        let xyz = &self.xyz;
        let eps2 = params.eps2;
        // Visits the points within eps of point `i`, exactly as scikit-learn decides.
        let within = |i: usize, visit: &mut dyn FnMut(usize)| {
            tree.query(&self.xyz64[i])
                .within::<SquaredEuclidean<f64>>(radius)
                .unsorted()
                .visit(|found| {
                    let j = found.item as usize;
                    if dist2(xyz[i], xyz[j]) <= eps2 {
                        visit(j);
                    }
                });
        };

        self.core.clear();
        for i in 0..n {
            let mut count = 0;
            within(i, &mut |_| count += 1);
            self.core.push(count >= params.min_points);
        }

        self.union.reset(n);
        for i in (0..n).filter(|&i| self.core[i]) {
            let core = &self.core;
            let union = &mut self.union;
            within(i, &mut |j| {
                if j > i && core[j] {
                    union.union(i as u32, j as u32);
                }
            });
        }

        let core = &self.core;
        let index = &self.index;
        self.numbering.number(
            &mut self.union,
            n,
            (0..n).filter(|&i| core[i]).map(|i| (i as u32, index[i])),
        );
        self.label.clear();
        self.label.resize(n, NOISE);
        for i in (0..n).filter(|&i| self.core[i]) {
            self.label[i] = self.numbering.label(&mut self.union, i as u32);
        }
        for i in (0..n).filter(|&i| !self.core[i]) {
            let mut best = i32::MAX;
            let label = &self.label;
            within(i, &mut |j| {
                if core[j] {
                    best = best.min(label[j]);
                }
            });
            if best != i32::MAX {
                self.label[i] = best;
            }
        }

        for (k, &i) in self.index.iter().enumerate() {
            out.labels[i as usize] = self.label[k];
            out.core[i as usize] = self.core[k];
        }
        Ok(())
    }
}
