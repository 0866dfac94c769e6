//! Voxel traversal along a ray (Amanatides & Woo) that can jump over a whole block at once.
//!
//! The parameter of the `j`-th boundary crossing along an axis is computed as
//! `first + j · delta` (not accumulated step by step), so that jumping over a block lands on
//! exactly the voxel stepping through it would reach.

use nalgebra::Vector3;

use super::block::BLOCK_SIDE;
use super::key::{floor_i32, local_index};

/// The voxels a segment (in voxel units) crosses, in order, the voxel holding its end
/// excluded. Where two boundaries are crossed at the same parameter the higher axis steps
/// first.
pub(super) struct VoxelWalk {
    key: [i32; 3],
    step: [i32; 3],
    /// Parameter of each axis' first boundary crossing (infinite along an axis not moved on).
    t_first: [f64; 3],
    /// Parameter between two boundary crossings of each axis.
    t_delta: [f64; 3],
    /// Boundary crossings made so far along each axis.
    crossed: [u32; 3],
    /// Parameter of each axis' next boundary crossing.
    t_next: [f64; 3],
    /// Voxels still to visit, the current one included.
    remaining: u32,
}

/// Where walks go (in voxel units) and the voxel holding it, found once for the many walks to
/// the same point.
pub(super) struct WalkTarget {
    point: Vector3<f64>,
    voxel: [i32; 3],
}

impl WalkTarget {
    /// The target `point`.
    pub fn new(point: Vector3<f64>) -> Self {
        let voxel = [floor_i32(point.x), floor_i32(point.y), floor_i32(point.z)];
        Self { point, voxel }
    }
}

impl VoxelWalk {
    /// A walk from the voxel holding `from` towards the voxel holding `to`.
    pub fn new(from: Vector3<f64>, to: &WalkTarget) -> Self {
        let key = [floor_i32(from.x), floor_i32(from.y), floor_i32(from.z)];
        let (end, to) = (to.voxel, to.point);
        let dir = to - from;
        let mut step = [0i32; 3];
        let mut t_first = [f64::INFINITY; 3];
        let mut t_delta = [f64::INFINITY; 3];
        for a in 0..3 {
            if dir[a] > 0.0 {
                step[a] = 1;
                t_first[a] = (f64::from(key[a]) + 1.0 - from[a]) / dir[a];
                t_delta[a] = 1.0 / dir[a];
            } else if dir[a] < 0.0 {
                step[a] = -1;
                t_first[a] = (f64::from(key[a]) - from[a]) / dir[a];
                t_delta[a] = -1.0 / dir[a];
            }
        }
        // The exact number of cell changes between the two ends bounds the walk, so rounding
        // can never make it run away.
        let remaining = (0..3).map(|a| key[a].abs_diff(end[a])).sum();
        Self {
            key,
            step,
            t_first,
            t_delta,
            crossed: [0; 3],
            t_next: t_first,
            remaining,
        }
    }

    /// The voxel the walk is at, `None` once it is over.
    pub fn current(&self) -> Option<[i32; 3]> {
        (self.remaining > 0).then_some(self.key)
    }

    /// Moves on to the next voxel of the walk.
    pub fn skip_voxel(&mut self) {
        if self.remaining > 0 {
            self.remaining -= 1;
            self.cross(first_axis(&self.t_next), 1);
        }
    }

    /// Calls `visit` with the slot (see [`local_index`]) of every voxel of the walk inside the
    /// current block, in order, and stops at the first voxel outside it (or at the end).
    /// When `visit` returns `false` the walk stops there instead, at the voxel just visited,
    /// and so does this, returning `false`.
    ///
    /// The walk's state lives in locals here, one variable per axis, so that the loop keeps
    /// it in registers: it is what most of a scan's ray casting runs through.
    pub fn through_block(&mut self, mut visit: impl FnMut(usize) -> bool) -> bool {
        let side = BLOCK_SIDE as i32;
        let [sx, sy, sz] = self.step;
        let [fx, fy, fz] = self.t_first;
        let [dx, dy, dz] = self.t_delta;
        let [mut kx, mut ky, mut kz] = self.key;
        let [mut cx, mut cy, mut cz] = self.crossed;
        let [mut tx, mut ty, mut tz] = self.t_next;
        let (mut lx, mut ly, mut lz) = (kx & (side - 1), ky & (side - 1), kz & (side - 1));
        let mut slot = local_index(self.key) as i32;
        let mut remaining = self.remaining;
        let mut go_on = true;
        while remaining > 0 {
            if !visit(slot as usize) {
                go_on = false;
                break;
            }
            remaining -= 1;
            // `first_axis(t_next)`, on the locals: the smallest parameter, ties to the higher
            // axis.
            let x_first = tx < ty && tx < tz;
            let y_first = ty <= tx && ty < tz;
            let inside = if x_first {
                kx += sx;
                cx += 1;
                tx = fx + f64::from(cx) * dx;
                lx += sx;
                slot += sx;
                (0..side).contains(&lx)
            } else if y_first {
                ky += sy;
                cy += 1;
                ty = fy + f64::from(cy) * dy;
                ly += sy;
                slot += sy * side;
                (0..side).contains(&ly)
            } else {
                kz += sz;
                cz += 1;
                tz = fz + f64::from(cz) * dz;
                lz += sz;
                slot += sz * side * side;
                (0..side).contains(&lz)
            };
            if !inside {
                break;
            }
        }
        self.key = [kx, ky, kz];
        self.crossed = [cx, cy, cz];
        self.t_next = [tx, ty, tz];
        self.remaining = remaining;
        go_on
    }

    /// Jumps to the first voxel of the walk outside the current block (or ends the walk, when
    /// it ends inside the block).
    pub fn leave_block(&mut self) {
        let side = BLOCK_SIDE as u32;
        // Crossings along each axis that take it out of the block, and when the last happens.
        let mut to_exit = [u32::MAX; 3];
        let mut exit_t = [f64::INFINITY; 3];
        for a in 0..3 {
            if self.step[a] != 0 {
                let local = (self.key[a] & (BLOCK_SIDE as i32 - 1)) as u32;
                to_exit[a] = if self.step[a] > 0 {
                    side - local
                } else {
                    local + 1
                };
                exit_t[a] = self.crossing_t(a, self.crossed[a] + to_exit[a] - 1);
            }
        }
        let exit = first_axis(&exit_t);
        let t_exit = exit_t[exit];
        let mut counts = [0u32; 3];
        for a in (0..3).filter(|&a| a != exit && self.step[a] != 0) {
            // Crossings along `a` that come before the exit, which stepping would have made
            // first: earlier, or at the same parameter on a higher axis.
            let before = |t: f64| t < t_exit || (t == t_exit && a > exit);
            while counts[a] + 1 < to_exit[a]
                && before(self.crossing_t(a, self.crossed[a] + counts[a]))
            {
                counts[a] += 1;
            }
        }
        counts[exit] = to_exit[exit];
        let steps: u32 = counts.iter().sum();
        if steps >= self.remaining {
            self.remaining = 0;
            return;
        }
        self.remaining -= steps;
        for (a, &n) in counts.iter().enumerate() {
            if n > 0 {
                self.cross(a, n);
            }
        }
    }

    /// Makes `n` more boundary crossings along axis `a`.
    fn cross(&mut self, a: usize, n: u32) {
        self.key[a] += self.step[a] * n as i32;
        self.crossed[a] += n;
        self.t_next[a] = self.crossing_t(a, self.crossed[a]);
    }

    /// The parameter of the `j`-th (0-based) boundary crossing along axis `a`.
    fn crossing_t(&self, a: usize, j: u32) -> f64 {
        self.t_first[a] + f64::from(j) * self.t_delta[a]
    }
}

/// The axis of the smallest parameter, ties to the higher axis.
fn first_axis(t: &[f64; 3]) -> usize {
    if t[0] < t[1] {
        if t[0] < t[2] { 0 } else { 2 }
    } else if t[1] < t[2] {
        1
    } else {
        2
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plain voxel-by-voxel walk.
    fn walk(from: [f64; 3], to: [f64; 3]) -> Vec<[i32; 3]> {
        let mut cells = Vec::new();
        let mut w = VoxelWalk::new(Vector3::from(from), &WalkTarget::new(Vector3::from(to)));
        while let Some(k) = w.current() {
            cells.push(k);
            w.skip_voxel();
        }
        cells
    }

    /// The voxel of slot `slot` in the block holding voxel `key`.
    fn voxel_of(key: [i32; 3], slot: usize) -> [i32; 3] {
        let side = BLOCK_SIDE as i32;
        let slot = slot as i32;
        let local = [slot % side, (slot / side) % side, slot / (side * side)];
        [0, 1, 2].map(|a| key[a].div_euclid(side) * side + local[a])
    }

    /// The walk with every block whose key `skip` says jumped over.
    fn walk_skipping(
        from: [f64; 3],
        to: [f64; 3],
        skip: impl Fn([i32; 3]) -> bool,
    ) -> Vec<[i32; 3]> {
        let side = BLOCK_SIDE as i32;
        let mut cells = Vec::new();
        let mut w = VoxelWalk::new(Vector3::from(from), &WalkTarget::new(Vector3::from(to)));
        while let Some(k) = w.current() {
            if skip(k.map(|v| v.div_euclid(side))) {
                w.leave_block();
                continue;
            }
            w.through_block(|slot| {
                cells.push(voxel_of(k, slot));
                true
            });
        }
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

    #[test]
    fn jumping_over_blocks_lands_where_stepping_does() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = |range: f64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 * range - range
        };
        for _ in 0..2000 {
            let from = [uniform(30.0), uniform(30.0), uniform(8.0)];
            // Rays of a sensor (voxel-centre ends) and arbitrary ones, axis-parallel included.
            let mut to = [uniform(200.0), uniform(200.0), uniform(20.0)];
            if uniform(1.0) > 0.0 {
                to = to.map(|v| v.floor() + 0.5);
            }
            if uniform(1.0) > 0.8 {
                to[2] = from[2];
            }
            let all = walk(from, to);
            // Every block present: block by block is voxel by voxel.
            assert_eq!(walk_skipping(from, to, |_| false), all);
            // A pseudo-random half of the blocks absent: what is left is what stepping gives
            // outside them.
            let absent = |b: [i32; 3]| (b[0] * 7 + b[1] * 13 + b[2] * 5).rem_euclid(3) == 0;
            let side = BLOCK_SIDE as i32;
            let expected: Vec<[i32; 3]> = all
                .iter()
                .copied()
                .filter(|k| !absent(k.map(|v| v.div_euclid(side))))
                .collect();
            assert_eq!(
                walk_skipping(from, to, absent),
                expected,
                "{from:?} -> {to:?}"
            );
        }
    }
}
