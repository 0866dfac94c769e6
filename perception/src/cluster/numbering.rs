//! Cluster numbers as scikit-learn gives them: clusters in the order of their lowest-index
//! core point.

use super::{NOISE, union_find::UnionFind};

/// Maps union-find sets of core points to cluster numbers; buffers reused between frames.
#[derive(Debug, Default)]
pub(crate) struct Numbering {
    /// Per set representative: the lowest input index among its core points.
    lowest: Vec<u32>,
    /// Per set representative: its cluster number.
    label: Vec<i32>,
    /// Scratch: (lowest input index, representative) of every set.
    sets: Vec<(u32, u32)>,
}

impl Numbering {
    /// Numbers the sets of `union` (over `0..n`) that hold core points; `core` yields each
    /// core point as (union-find element, input index).
    pub(crate) fn number(
        &mut self,
        union: &mut UnionFind,
        n: usize,
        core: impl Iterator<Item = (u32, u32)>,
    ) {
        self.lowest.clear();
        self.lowest.resize(n, u32::MAX);
        for (element, index) in core {
            let root = union.find(element) as usize;
            self.lowest[root] = self.lowest[root].min(index);
        }
        self.sets.clear();
        self.sets.extend(
            self.lowest
                .iter()
                .enumerate()
                .filter(|&(_, &lowest)| lowest != u32::MAX)
                .map(|(root, &lowest)| (lowest, root as u32)),
        );
        self.sets.sort_unstable();
        self.label.clear();
        self.label.resize(n, NOISE);
        for (number, &(_, root)) in self.sets.iter().enumerate() {
            self.label[root as usize] = number as i32;
        }
    }

    /// The cluster number of a core point's union-find element.
    pub(crate) fn label(&self, union: &mut UnionFind, element: u32) -> i32 {
        self.label[union.find(element) as usize]
    }
}
