//! Disjoint sets over `0..n` (path halving, union by size), reused from frame to frame.

/// Disjoint sets over `0..n`.
#[derive(Debug, Default)]
pub(crate) struct UnionFind {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl UnionFind {
    /// Makes `n` singleton sets, reusing the buffers.
    pub(crate) fn reset(&mut self, n: usize) {
        self.parent.clear();
        self.parent.extend(0..n as u32);
        self.size.clear();
        self.size.resize(n, 1);
    }

    /// The representative of `x`'s set.
    pub(crate) fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let grandparent = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = grandparent;
            x = grandparent;
        }
        x
    }

    /// Merges the sets of `a` and `b`.
    pub(crate) fn union(&mut self, a: u32, b: u32) {
        let (mut a, mut b) = (self.find(a), self.find(b));
        if a == b {
            return;
        }
        if self.size[a as usize] < self.size[b as usize] {
            std::mem::swap(&mut a, &mut b);
        }
        self.parent[b as usize] = a;
        self.size[a as usize] += self.size[b as usize];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unions_are_transitive_and_nothing_else_is_joined() {
        let mut sets = UnionFind::default();
        sets.reset(6);
        sets.union(0, 2);
        sets.union(4, 2);
        sets.union(1, 5);
        assert_eq!(sets.find(0), sets.find(4));
        assert_eq!(sets.find(1), sets.find(5));
        assert_ne!(sets.find(0), sets.find(1));
        assert_ne!(sets.find(3), sets.find(0));
        sets.reset(2);
        assert_ne!(sets.find(0), sets.find(1));
    }
}
