//! Exact k-nearest-neighbour search over one cluster: a small static k-d tree (median splits
//! on the widest axis, leaves of at most [`LEAF`] points), queried point after point in tree
//! order so that consecutive queries touch the same leaves. For the k = 10 neighbourhoods of
//! normal estimation it is several times faster than a general-purpose tree, and it allocates
//! nothing once its buffers have grown.
//!
//! Each leaf's coordinates are also kept axis by axis in a block of [`LEAF`] slots, so the
//! distances to a whole leaf are computed in one fixed-length loop the compiler turns into
//! SIMD; the candidates are then offered one by one in the leaf's order, exactly as a plain
//! point-by-point scan would offer them.
//!
//! The leaf scan's helpers are always inlined into the search: left to the compiler, whether
//! they were inlined depended on unrelated code elsewhere in the crate, and the VFH stage of
//! `trackd bench` took 5.3 ms instead of 4.6 when they were not.

/// Most points in a leaf, and the slots of a leaf's coordinate block.
const LEAF: usize = 12;

/// The coordinates of one leaf's points, axis by axis (unused slots hold zeros).
#[derive(Clone, Copy, Debug, Default)]
struct LeafBlock {
    x: [f32; LEAF],
    y: [f32; LEAF],
    z: [f32; LEAF],
}

impl LeafBlock {
    /// Squared distances `dx² + dy² + dz²` (in `f32`, summed in that order) from `query` to
    /// every slot.
    #[inline(always)]
    fn dist2(&self, query: [f32; 3]) -> [f32; LEAF] {
        let mut d2 = [0.0f32; LEAF];
        for (j, out) in d2.iter_mut().enumerate() {
            let d = [
                self.x[j] - query[0],
                self.y[j] - query[1],
                self.z[j] - query[2],
            ];
            *out = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        }
        d2
    }
}

/// A node of the tree; the left child of a split node is the next node.
#[derive(Clone, Copy, Debug)]
struct Node {
    /// Range of the node's points in tree order.
    start: u32,
    end: u32,
    /// Split axis, or `LEAF_AXIS` for a leaf.
    axis: u8,
    /// Split value: left points have `p[axis] <= split`, right points `>= split`.
    split: f32,
    /// Index of the right child of a split node; the coordinate block of a leaf.
    right: u32,
}

/// `Node::axis` of a leaf.
const LEAF_AXIS: u8 = 3;

/// A k-d tree over a point set, with its buffers.
#[derive(Debug, Default)]
pub(crate) struct KnnTree {
    /// The points with their input index, in tree order.
    items: Vec<([f32; 3], u32)>,
    nodes: Vec<Node>,
    /// The leaves' coordinates, one block per leaf.
    blocks: Vec<LeafBlock>,
    /// Scratch: the current best neighbours (squared distance, tree position), unordered,
    /// and the farthest of them once there are k.
    best: Vec<(f32, u32)>,
    worst: f32,
    worst_at: usize,
    /// Scratch: their positions.
    neighbours: Vec<[f32; 3]>,
}

impl KnnTree {
    /// Rebuilds the tree over `points`.
    pub(crate) fn build(&mut self, points: &[[f32; 3]]) {
        self.items.clear();
        self.items
            .extend(points.iter().enumerate().map(|(i, p)| (*p, i as u32)));
        self.nodes.clear();
        self.blocks.clear();
        if !points.is_empty() {
            self.build_node(0, points.len());
        }
    }

    fn build_node(&mut self, start: usize, end: usize) {
        let id = self.nodes.len();
        self.nodes.push(Node {
            start: start as u32,
            end: end as u32,
            axis: LEAF_AXIS,
            split: 0.0,
            right: 0,
        });
        if end - start <= LEAF {
            let mut block = LeafBlock::default();
            for (j, (p, _)) in self.items[start..end].iter().enumerate() {
                (block.x[j], block.y[j], block.z[j]) = (p[0], p[1], p[2]);
            }
            self.nodes[id].right = self.blocks.len() as u32;
            self.blocks.push(block);
            return;
        }
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for (p, _) in &self.items[start..end] {
            for axis in 0..3 {
                // Plain comparisons (one minss/maxss each; f32::min adds NaN handling).
                lo[axis] = if p[axis] < lo[axis] {
                    p[axis]
                } else {
                    lo[axis]
                };
                hi[axis] = if p[axis] > hi[axis] {
                    p[axis]
                } else {
                    hi[axis]
                };
            }
        }
        let axis = (0..3)
            .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
            .unwrap_or(0);
        let mid = (start + end) / 2;
        self.items[start..end]
            .select_nth_unstable_by(mid - start, |a, b| a.0[axis].total_cmp(&b.0[axis]));
        let split = self.items[mid].0[axis];
        self.build_node(start, mid);
        let right = self.nodes.len() as u32;
        self.build_node(mid, end);
        let node = &mut self.nodes[id];
        node.axis = axis as u8;
        node.split = split;
        node.right = right;
    }

    /// Calls `visit(input index, neighbours)` for every point, in tree order, with the input
    /// positions of its `k` nearest neighbours (all points when there are fewer), itself
    /// included, in no particular order (ties broken arbitrarily).
    pub(crate) fn for_each_knn(&mut self, k: usize, mut visit: impl FnMut(u32, &[[f32; 3]])) {
        let k = k.min(self.items.len());
        if k == 0 {
            return;
        }
        for position in 0..self.items.len() {
            let (query, index) = self.items[position];
            self.best.clear();
            self.search(0, query, k);
            self.neighbours.clear();
            self.neighbours
                .extend(self.best.iter().map(|&(_, pos)| self.items[pos as usize].0));
            visit(index, &self.neighbours);
        }
    }

    fn search(&mut self, node: usize, query: [f32; 3], k: usize) {
        let Node {
            start,
            end,
            axis,
            split,
            right,
        } = self.nodes[node];
        if axis == LEAF_AXIS {
            let d2 = self.blocks[right as usize].dist2(query);
            for (&d2, position) in d2[..(end - start) as usize].iter().zip(start..) {
                // What offer would ignore is skipped here already.
                if self.best.len() < k || d2 < self.worst {
                    self.offer(d2, position, k);
                }
            }
            return;
        }
        let diff = query[axis as usize] - split;
        let (near, far) = if diff <= 0.0 {
            (node + 1, right as usize)
        } else {
            (right as usize, node + 1)
        };
        self.search(near, query, k);
        if self.best.len() < k || diff * diff < self.worst {
            self.search(far, query, k);
        }
    }

    /// Keeps (d2, position) if it is among the k best so far.
    #[inline(always)]
    fn offer(&mut self, d2: f32, position: u32, k: usize) {
        if self.best.len() < k {
            self.best.push((d2, position));
            if self.best.len() == k {
                self.find_worst();
            }
        } else if d2 < self.worst {
            self.best[self.worst_at] = (d2, position);
            self.find_worst();
        }
    }

    /// Locates the farthest of the k best (they are kept unordered).
    #[inline(always)]
    fn find_worst(&mut self) {
        let (mut at, mut worst) = (0, self.best[0].0);
        for (i, &(d2, _)) in self.best.iter().enumerate().skip(1) {
            if d2 > worst {
                (at, worst) = (i, d2);
            }
        }
        self.worst_at = at;
        self.worst = worst;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equals_brute_force() {
        let mut state = 99u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        for n in [1usize, 5, 13, 100, 1000] {
            // Coarse coordinates: many ties and duplicates.
            let points: Vec<[f32; 3]> = (0..n)
                .map(|_| {
                    [
                        (next() * 20.0).round() * 0.1,
                        (next() * 20.0).round() * 0.1,
                        next(),
                    ]
                })
                .collect();
            let mut tree = KnnTree::default();
            tree.build(&points);
            for k in [1usize, 3, 10, 2000] {
                let mut seen = 0;
                tree.for_each_knn(k, |index, neighbours| {
                    seen += 1;
                    let q = points[index as usize];
                    let d2 = |p: &[f32; 3]| {
                        let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
                        d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
                    };
                    let mut all: Vec<f32> = points.iter().map(d2).collect();
                    all.sort_by(f32::total_cmp);
                    let mut got: Vec<f32> = neighbours.iter().map(d2).collect();
                    got.sort_by(f32::total_cmp);
                    assert_eq!(got, all[..k.min(n)].to_vec(), "n {n} k {k}");
                });
                assert_eq!(seen, n);
            }
        }
    }
}
