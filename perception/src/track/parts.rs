//! Writing a split cluster out: its points grouped by the part each was given to.

use std::ops::Range;

use crate::Point;

/// Reusable buffers of [`PartWriter::write`].
#[derive(Debug, Default)]
pub(crate) struct PartWriter {
    starts: Vec<usize>,
    scratch: Vec<Point>,
}

impl PartWriter {
    /// Reorders `points` by `owner` (one entry per point, each below `owners`), keeping their
    /// order within a part, and appends to `parts` the range of every part that holds points,
    /// in owner order; returns how many it appended.
    pub(crate) fn write(
        &mut self,
        points: &mut [Point],
        owner: &[u32],
        owners: usize,
        parts: &mut Vec<Range<usize>>,
    ) -> usize {
        self.starts.clear();
        self.starts.resize(owners + 1, 0);
        for &o in owner {
            self.starts[o as usize + 1] += 1;
        }
        for k in 1..=owners {
            self.starts[k] += self.starts[k - 1];
        }
        let before = parts.len();
        parts.extend(
            self.starts
                .windows(2)
                .map(|w| w[0]..w[1])
                .filter(|r| !r.is_empty()),
        );
        self.scratch.clear();
        self.scratch.resize(points.len(), Point::default());
        for (p, &o) in points.iter().zip(owner) {
            let slot = &mut self.starts[o as usize];
            self.scratch[*slot] = *p;
            *slot += 1;
        }
        points.copy_from_slice(&self.scratch);
        parts.len() - before
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_points_by_owner_in_order_and_skips_empty_parts() {
        let mut points: Vec<Point> = (0..6)
            .map(|i| Point::new(i as f32, 0.0, 0.0, 0.0))
            .collect();
        let owner = [2, 0, 2, 0, 3, 2];
        // Appended after what `parts` held already.
        let mut parts = vec![7..9, 9..10];
        let written = PartWriter::default().write(&mut points, &owner, 4, &mut parts);
        assert_eq!(written, 3);
        assert_eq!(parts, vec![7..9, 9..10, 0..2, 2..5, 5..6]);
        let xs: Vec<f32> = points.iter().map(|p| p.x).collect();
        assert_eq!(xs, vec![1.0, 3.0, 0.0, 2.0, 5.0, 4.0]);
    }
}
