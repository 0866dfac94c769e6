//! Global one-to-one assignment of clusters to tracks: the Hungarian method (shortest
//! augmenting paths with potentials, O(n²m)) on each connected component of the gated
//! track–cluster graph.
//!
//! Every track may also stay unmatched at its own miss cost; a pair costing more than that is
//! never chosen. Splitting the sparse graph into components keeps scenes with hundreds of
//! tracks cheap: a component is usually one to three tracks.

/// A feasible (gated) pairing of track `row` with cluster `col` at `cost`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pair {
    /// Track index.
    pub row: usize,
    /// Cluster index.
    pub col: usize,
    /// Cost of the pairing (lower is better).
    pub cost: f64,
}

/// Cost standing for "not allowed" inside the dense sub-problems.
const FORBIDDEN: f64 = 1e12;

/// Reusable buffers of the assignment.
#[derive(Debug, Default)]
pub struct Assigner {
    row_component: Vec<usize>,
    col_component: Vec<usize>,
    parent: Vec<usize>,
    members_rows: Vec<Vec<usize>>,
    members_cols: Vec<Vec<usize>>,
    local_row: Vec<usize>,
    local_col: Vec<usize>,
    root_component: Vec<usize>,
    dense: Vec<f64>,
}

impl Assigner {
    /// Assigns `cols` clusters to the tracks (one per entry of `miss_costs`) minimising the
    /// total cost of the chosen `pairs` plus `miss_costs[t]` per unmatched track `t`. Returns
    /// the cluster of each track.
    pub fn assign(
        &mut self,
        cols: usize,
        pairs: &[Pair],
        miss_costs: &[f64],
    ) -> Vec<Option<usize>> {
        let rows = miss_costs.len();
        let mut result = vec![None; rows];
        // Union–find over rows (0..rows) and columns (rows..rows+cols).
        self.parent.clear();
        self.parent.extend(0..rows + cols);
        for p in pairs.iter().filter(|p| p.cost < miss_costs[p.row]) {
            let a = find(&mut self.parent, p.row);
            let b = find(&mut self.parent, rows + p.col);
            if a != b {
                self.parent[a] = b;
            }
        }
        // Number the components that hold at least one feasible pair.
        self.row_component.clear();
        self.row_component.resize(rows, usize::MAX);
        self.col_component.clear();
        self.col_component.resize(cols, usize::MAX);
        self.root_component.clear();
        self.root_component.resize(rows + cols, usize::MAX);
        let mut count = 0;
        for p in pairs.iter().filter(|p| p.cost < miss_costs[p.row]) {
            let root = find(&mut self.parent, p.row);
            if self.root_component[root] == usize::MAX {
                self.root_component[root] = count;
                count += 1;
            }
            self.row_component[p.row] = self.root_component[root];
            self.col_component[p.col] = self.root_component[root];
        }
        self.members_rows.iter_mut().for_each(Vec::clear);
        self.members_cols.iter_mut().for_each(Vec::clear);
        self.members_rows
            .resize_with(count.max(self.members_rows.len()), Vec::new);
        self.members_cols
            .resize_with(count.max(self.members_cols.len()), Vec::new);
        for (r, &c) in self.row_component.iter().enumerate() {
            if c != usize::MAX {
                self.members_rows[c].push(r);
            }
        }
        for (k, &c) in self.col_component.iter().enumerate() {
            if c != usize::MAX {
                self.members_cols[c].push(k);
            }
        }
        self.local_row.clear();
        self.local_row.resize(rows, usize::MAX);
        self.local_col.clear();
        self.local_col.resize(cols, usize::MAX);
        for component in 0..count {
            self.solve_component(component, pairs, miss_costs, &mut result);
        }
        result
    }

    /// Solves one component densely: its tracks × (its clusters + one private "miss" column
    /// per track).
    fn solve_component(
        &mut self,
        component: usize,
        pairs: &[Pair],
        miss_costs: &[f64],
        result: &mut [Option<usize>],
    ) {
        let rows = &self.members_rows[component];
        let cols = &self.members_cols[component];
        let (n, m) = (rows.len(), cols.len() + rows.len());
        for (i, &r) in rows.iter().enumerate() {
            self.local_row[r] = i;
        }
        for (j, &c) in cols.iter().enumerate() {
            self.local_col[c] = j;
        }
        self.dense.clear();
        self.dense.resize(n * m, FORBIDDEN);
        for (i, &r) in rows.iter().enumerate() {
            self.dense[i * m + cols.len() + i] = miss_costs[r];
        }
        for p in pairs.iter().filter(|p| p.cost < miss_costs[p.row]) {
            if self.row_component[p.row] == component {
                let i = self.local_row[p.row];
                let j = self.local_col[p.col];
                let cell = &mut self.dense[i * m + j];
                *cell = cell.min(p.cost);
            }
        }
        let assignment = hungarian(&self.dense, n, m);
        for (i, &j) in assignment.iter().enumerate() {
            if j < cols.len() && self.dense[i * m + j] < miss_costs[rows[i]] {
                result[rows[i]] = Some(cols[j]);
            }
        }
    }
}

/// Root of `x` in the union–find forest, with path halving.
fn find(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

/// Minimum-cost assignment of each of `n` rows to a distinct one of `m ≥ n` columns of the
/// row-major `cost` matrix. Returns the column of each row.
pub fn hungarian(cost: &[f64], n: usize, m: usize) -> Vec<usize> {
    debug_assert!(n <= m && cost.len() == n * m);
    // 1-based potentials and matching, column 0 is the virtual start.
    let mut u = vec![0.0; n + 1];
    let mut v = vec![0.0; m + 1];
    let mut row_of_col = vec![0usize; m + 1];
    let mut way = vec![0usize; m + 1];
    let mut min_to = vec![0.0; m + 1];
    let mut used = vec![false; m + 1];
    for i in 1..=n {
        row_of_col[0] = i;
        let mut j0 = 0;
        min_to.iter_mut().for_each(|x| *x = f64::INFINITY);
        used.iter_mut().for_each(|x| *x = false);
        loop {
            used[j0] = true;
            let i0 = row_of_col[j0];
            let mut delta = f64::INFINITY;
            let mut j1 = 0;
            for j in 1..=m {
                if used[j] {
                    continue;
                }
                let reduced = cost[(i0 - 1) * m + (j - 1)] - u[i0] - v[j];
                if reduced < min_to[j] {
                    min_to[j] = reduced;
                    way[j] = j0;
                }
                if min_to[j] < delta {
                    delta = min_to[j];
                    j1 = j;
                }
            }
            for j in 0..=m {
                if used[j] {
                    u[row_of_col[j]] += delta;
                    v[j] -= delta;
                } else {
                    min_to[j] -= delta;
                }
            }
            j0 = j1;
            if row_of_col[j0] == 0 {
                break;
            }
        }
        loop {
            let j1 = way[j0];
            row_of_col[j0] = row_of_col[j1];
            j0 = j1;
            if j0 == 0 {
                break;
            }
        }
    }
    let mut col_of_row = vec![0; n];
    for j in 1..=m {
        if row_of_col[j] != 0 {
            col_of_row[row_of_col[j] - 1] = j - 1;
        }
    }
    col_of_row
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute_force(cost: &[f64], n: usize, m: usize) -> f64 {
        fn go(cost: &[f64], n: usize, m: usize, i: usize, used: &mut Vec<bool>) -> f64 {
            if i == n {
                return 0.0;
            }
            let mut best = f64::INFINITY;
            for j in 0..m {
                if !used[j] {
                    used[j] = true;
                    best = best.min(cost[i * m + j] + go(cost, n, m, i + 1, used));
                    used[j] = false;
                }
            }
            best
        }
        go(cost, n, m, 0, &mut vec![false; m])
    }

    #[test]
    fn hungarian_matches_brute_force() {
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as f64 / (1u64 << 31) as f64
        };
        for (n, m) in [(1, 1), (2, 3), (3, 3), (4, 6), (5, 5), (3, 7)] {
            for _ in 0..20 {
                let cost: Vec<f64> = (0..n * m).map(|_| (next() * 100.0).round()).collect();
                let a = hungarian(&cost, n, m);
                let total: f64 = a.iter().enumerate().map(|(i, &j)| cost[i * m + j]).sum();
                let mut cols = a.clone();
                cols.sort_unstable();
                cols.dedup();
                assert_eq!(cols.len(), n, "columns must be distinct");
                assert!((total - brute_force(&cost, n, m)).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn greedy_would_fail_but_global_assignment_does_not() {
        // Track 0 is slightly nearer to cluster 0, but track 1 can only take cluster 0.
        let pairs = [
            Pair {
                row: 0,
                col: 0,
                cost: 1.0,
            },
            Pair {
                row: 0,
                col: 1,
                cost: 1.5,
            },
            Pair {
                row: 1,
                col: 0,
                cost: 1.2,
            },
        ];
        let a = Assigner::default().assign(2, &pairs, &[10.0; 2]);
        assert_eq!(a, vec![Some(1), Some(0)]);
    }

    #[test]
    fn a_pair_dearer_than_a_miss_is_never_taken() {
        let pairs = [
            Pair {
                row: 0,
                col: 0,
                cost: 1.0,
            },
            Pair {
                row: 1,
                col: 0,
                cost: 2.0,
            },
            Pair {
                row: 1,
                col: 1,
                cost: 50.0,
            },
        ];
        let a = Assigner::default().assign(2, &pairs, &[10.0; 2]);
        assert_eq!(a, vec![Some(0), None]);
    }

    #[test]
    fn no_cluster_goes_to_two_tracks_across_components() {
        let mut pairs = Vec::new();
        // Three separate groups of two tracks competing for one or two clusters.
        for g in 0..3 {
            pairs.push(Pair {
                row: 2 * g,
                col: 2 * g,
                cost: 1.0,
            });
            pairs.push(Pair {
                row: 2 * g + 1,
                col: 2 * g,
                cost: 0.5,
            });
            if g != 1 {
                pairs.push(Pair {
                    row: 2 * g,
                    col: 2 * g + 1,
                    cost: 3.0,
                });
            }
        }
        let a = Assigner::default().assign(6, &pairs, &[5.0; 6]);
        assert_eq!(a, vec![Some(1), Some(0), None, Some(2), Some(5), Some(4)]);
    }

    #[test]
    fn reuses_buffers_between_calls() {
        let mut assigner = Assigner::default();
        let pairs = [Pair {
            row: 0,
            col: 2,
            cost: 1.0,
        }];
        assert_eq!(assigner.assign(3, &pairs, &[2.0]), vec![Some(2)]);
        let pairs = [Pair {
            row: 1,
            col: 0,
            cost: 1.0,
        }];
        assert_eq!(assigner.assign(1, &pairs, &[2.0; 2]), vec![None, Some(0)]);
    }
}
