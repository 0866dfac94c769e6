//! Voxel traversal along a ray (Amanatides & Woo), and the block lookup cache rays use.

use nalgebra::Vector3;
use rustc_hash::FxHashMap;

/// Calls `visit` with the index of every voxel the segment `from → to` (in voxel units)
/// crosses, in order, the voxel holding `to` excluded.
pub(super) fn traverse(from: Vector3<f64>, to: Vector3<f64>, mut visit: impl FnMut([i32; 3])) {
    let mut key = [
        from.x.floor() as i32,
        from.y.floor() as i32,
        from.z.floor() as i32,
    ];
    let end = [
        to.x.floor() as i32,
        to.y.floor() as i32,
        to.z.floor() as i32,
    ];
    let dir = to - from;
    let mut step = [0i32; 3];
    let mut t_max = [f64::INFINITY; 3];
    let mut t_delta = [f64::INFINITY; 3];
    for a in 0..3 {
        if dir[a] > 0.0 {
            step[a] = 1;
            t_max[a] = (f64::from(key[a]) + 1.0 - from[a]) / dir[a];
            t_delta[a] = 1.0 / dir[a];
        } else if dir[a] < 0.0 {
            step[a] = -1;
            t_max[a] = (f64::from(key[a]) - from[a]) / dir[a];
            t_delta[a] = -1.0 / dir[a];
        }
    }
    // The exact number of cell changes between the two ends bounds the walk, so rounding can
    // never make it run away.
    let steps: i32 = (0..3).map(|a| (end[a] - key[a]).abs()).sum();
    for _ in 0..steps {
        visit(key);
        let a = if t_max[0] < t_max[1] {
            if t_max[0] < t_max[2] { 0 } else { 2 }
        } else if t_max[1] < t_max[2] {
            1
        } else {
            2
        };
        key[a] += step[a];
        t_max[a] += t_delta[a];
    }
}

/// The last block looked up, so that a ray pays one hash lookup per block it crosses.
#[derive(Default)]
pub(super) struct BlockCache {
    last: Option<([i32; 3], Option<u32>)>,
}

impl BlockCache {
    /// The slot of block `key`, or `None` when the map has no such block.
    pub fn lookup(&mut self, key: [i32; 3], index: &FxHashMap<[i32; 3], u32>) -> Option<u32> {
        match self.last {
            Some((k, slot)) if k == key => slot,
            _ => {
                let slot = index.get(&key).copied();
                self.last = Some((key, slot));
                slot
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn walk(from: [f64; 3], to: [f64; 3]) -> Vec<[i32; 3]> {
        let mut cells = Vec::new();
        traverse(Vector3::from(from), Vector3::from(to), |k| cells.push(k));
        cells
    }

    #[test]
    fn axis_aligned_ray_visits_each_cell_once_and_stops_before_the_end() {
        let cells = walk([0.5, 0.5, 0.5], [4.5, 0.5, 0.5]);
        assert_eq!(cells, vec![[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]]);
    }

    #[test]
    fn negative_direction_and_diagonal_rays_are_face_connected() {
        let cells = walk([2.2, 3.7, -0.4], [-3.1, -1.2, 2.9]);
        assert_eq!(cells[0], [2, 3, -1]);
        for w in cells.windows(2) {
            let d: i32 = (0..3).map(|a| (w[1][a] - w[0][a]).abs()).sum();
            assert_eq!(d, 1, "{w:?}");
        }
        let last = *cells.last().unwrap();
        let d: i32 = (0..3).map(|a| (last[a] - [-4, -2, 2][a]).abs()).sum();
        assert_eq!(d, 1, "the walk ends next to the end cell");
    }

    #[test]
    fn a_ray_inside_one_cell_visits_nothing() {
        assert!(walk([0.1, 0.1, 0.1], [0.9, 0.8, 0.2]).is_empty());
    }
}
