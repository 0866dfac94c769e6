//! A bird's-eye-view raster of one cluster, and the connected groups of its marked cells.

use crate::Point;

/// Label of a cell in no group.
pub(crate) const UNLABELLED: u32 = u32::MAX;
/// Label of a marked cell not yet given a group.
pub(crate) const MARKED: u32 = u32::MAX - 1;

/// Square cells over a cluster's ground-plane bounds, row by row.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Raster {
    /// Lower corner (x, y) of the first cell.
    pub(crate) min: [f32; 2],
    /// Cell edge (m).
    pub(crate) cell: f32,
    pub(crate) columns: usize,
    pub(crate) rows: usize,
}

impl Raster {
    /// The raster with cells of `cell` metres over the bounds `min`..`max`.
    pub(crate) fn over(min: [f32; 2], max: [f32; 2], cell: f32) -> Self {
        Self {
            min,
            cell,
            columns: ((max[0] - min[0]) / cell) as usize + 1,
            rows: ((max[1] - min[1]) / cell) as usize + 1,
        }
    }

    /// Number of cells.
    pub(crate) fn len(&self) -> usize {
        self.columns * self.rows
    }

    /// The cell holding `p` (points outside the bounds go to the nearest edge cell).
    pub(crate) fn cell_of(&self, p: &Point) -> usize {
        let c = (((p.x - self.min[0]) / self.cell) as usize).min(self.columns - 1);
        let r = (((p.y - self.min[1]) / self.cell) as usize).min(self.rows - 1);
        r * self.columns + c
    }

    /// The cell holding `p`, if it lies within the bounds.
    pub(crate) fn cell_inside(&self, p: &Point) -> Option<usize> {
        let (c, r) = (
            (p.x - self.min[0]) / self.cell,
            (p.y - self.min[1]) / self.cell,
        );
        let inside =
            (0.0..self.columns as f32).contains(&c) && (0.0..self.rows as f32).contains(&r);
        inside.then(|| r as usize * self.columns + c as usize)
    }

    /// Gives the [`MARKED`] cells of `labels` (one per cell) the numbers 0, 1, … of their
    /// connected groups (8-neighbours), numbered in the order of their first cell; returns
    /// how many groups there are. `stack` is scratch.
    pub(crate) fn label_groups(&self, labels: &mut [u32], stack: &mut Vec<u32>) -> u32 {
        self.label_groups_from(0..self.len(), labels, stack)
    }

    /// [`label_groups`](Self::label_groups) visiting only `cells` (which must hold every
    /// marked cell), numbering the groups in the order of their first cell there: a sparse
    /// raster is labelled without a pass over all its cells.
    pub(crate) fn label_groups_from(
        &self,
        cells: impl IntoIterator<Item = usize>,
        labels: &mut [u32],
        stack: &mut Vec<u32>,
    ) -> u32 {
        let mut count = 0u32;
        for start in cells {
            if labels[start] != MARKED {
                continue;
            }
            labels[start] = count;
            stack.clear();
            stack.push(start as u32);
            while let Some(c) = stack.pop() {
                let (r, col) = (c as usize / self.columns, c as usize % self.columns);
                for nr in r.saturating_sub(1)..=(r + 1).min(self.rows - 1) {
                    for nc in col.saturating_sub(1)..=(col + 1).min(self.columns - 1) {
                        let n = nr * self.columns + nc;
                        if labels[n] == MARKED {
                            labels[n] = count;
                            stack.push(n as u32);
                        }
                    }
                }
            }
            count += 1;
        }
        count
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn marked_cells_touching_at_a_corner_form_one_group() {
        // 4 x 3 cells: a diagonal pair, a lone cell, an unmarked rest.
        let raster = Raster::over([0.0, 0.0], [0.35, 0.25], 0.1);
        assert_eq!((raster.columns, raster.rows), (4, 3));
        assert_eq!(raster.cell_of(&Point::new(0.25, 0.15, 0.0, 0.0)), 6);
        assert_eq!(raster.cell_of(&Point::new(9.0, -1.0, 0.0, 0.0)), 3);
        let (m, u) = (MARKED, UNLABELLED);
        let mut labels = vec![u, m, u, u, u, u, m, u, m, u, u, u];
        assert_eq!(raster.label_groups(&mut labels, &mut Vec::new()), 2);
        assert_eq!(labels, vec![u, 0, u, u, u, u, 0, u, 1, u, u, u]);
    }
}
