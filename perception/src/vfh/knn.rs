//! Exact k-nearest-neighbour search over one cluster: a small static k-d tree (median splits
//! on the widest axis, leaves of at most [`LEAF`] points), queried point after point in tree
//! order so that consecutive queries touch the same leaves. For the k = 10 neighbourhoods of
//! normal estimation it is several times faster than a general-purpose tree, and it allocates
//! nothing once its buffers have grown.

/// Most points in a leaf.
const LEAF: usize = 12;

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
    /// Index of the right child.
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
            return;
        }
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for (p, _) in &self.items[start..end] {
            for axis in 0..3 {
                lo[axis] = lo[axis].min(p[axis]);
                hi[axis] = hi[axis].max(p[axis]);
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
            for position in start..end {
                let p = self.items[position as usize].0;
                let d = [p[0] - query[0], p[1] - query[1], p[2] - query[2]];
                let d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                self.offer(d2, position, k);
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
    #[inline]
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
    #[inline]
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
