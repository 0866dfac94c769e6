//! Voxel down-sampling as PCL's `VoxelGrid` does it: every point of a cubic voxel (aligned to
//! multiples of the edge) is replaced by their mean. Voxels are found with an open-addressing
//! hash table; consecutive points of one voxel (a LiDAR ring crossing it) are summed before
//! the lookup, so a scan costs far fewer lookups than points. Output order: the order in which
//! voxels are first met, so the result is deterministic.

use crate::Point;

/// Key of the empty hash slot (no voxel packs to it: coordinates are offset into 21 bits).
const EMPTY: u64 = u64::MAX;

/// Voxel coordinates are kept within ±2^20 (a million voxels from the origin each way);
/// points beyond are clamped into the outermost voxels.
const HALF_RANGE: f64 = (1u64 << 20) as f64;

/// Running sums of one voxel.
#[derive(Clone, Copy, Debug, Default)]
struct Sums {
    x: f64,
    y: f64,
    z: f64,
    intensity: f64,
    count: u32,
}

impl Sums {
    fn add(&mut self, other: &Sums) {
        self.x += other.x;
        self.y += other.y;
        self.z += other.z;
        self.intensity += other.intensity;
        self.count += other.count;
    }

    fn of(p: &Point) -> Self {
        Self {
            x: p.x as f64,
            y: p.y as f64,
            z: p.z as f64,
            intensity: p.intensity as f64,
            count: 1,
        }
    }

    fn mean(&self) -> Point {
        let n = self.count as f64;
        Point::new(
            (self.x / n) as f32,
            (self.y / n) as f32,
            (self.z / n) as f32,
            (self.intensity / n) as f32,
        )
    }
}

/// A reusable voxel grid.
#[derive(Debug, Default)]
pub(crate) struct VoxelGrid {
    /// Hash table: per slot, a voxel key and the voxel's index in `voxels`.
    table: Vec<(u64, u32)>,
    /// The voxels' sums, in the order they were first met.
    voxels: Vec<Sums>,
}

impl VoxelGrid {
    /// Appends to `out` the mean of the points of `points` in each voxel of edge `size`
    /// (> 0; non-finite points are skipped).
    pub(crate) fn downsample(
        &mut self,
        points: impl Iterator<Item = Point>,
        size: f32,
        expected: usize,
        out: &mut Vec<Point>,
    ) {
        let capacity = (2 * expected.max(8)).next_power_of_two();
        self.table.clear();
        self.table.resize(capacity, (EMPTY, 0));
        self.voxels.clear();
        let inv = 1.0 / size as f64;
        let mut run: Option<(u64, Sums)> = None;
        for p in points.filter(|p| p.x.is_finite() && p.y.is_finite() && p.z.is_finite()) {
            let key = pack(&p, inv);
            match &mut run {
                Some((k, sums)) if *k == key => sums.add(&Sums::of(&p)),
                _ => {
                    if let Some((k, sums)) = run.take() {
                        self.insert(k, &sums);
                    }
                    run = Some((key, Sums::of(&p)));
                }
            }
        }
        if let Some((k, sums)) = run {
            self.insert(k, &sums);
        }
        out.extend(self.voxels.iter().map(Sums::mean));
    }

    /// Adds `sums` to voxel `key`, growing the table when it gets half full.
    fn insert(&mut self, key: u64, sums: &Sums) {
        if 2 * (self.voxels.len() + 1) > self.table.len() {
            self.grow();
        }
        let mask = self.table.len() - 1;
        let mut slot = hash(key) & mask;
        loop {
            let (k, index) = self.table[slot];
            if k == key {
                self.voxels[index as usize].add(sums);
                return;
            }
            if k == EMPTY {
                self.table[slot] = (key, self.voxels.len() as u32);
                self.voxels.push(*sums);
                return;
            }
            slot = (slot + 1) & mask;
        }
    }

    /// Doubles the table and re-inserts the voxels met so far.
    fn grow(&mut self) {
        let old = std::mem::take(&mut self.table);
        self.table.resize(old.len() * 2, (EMPTY, 0));
        let mask = self.table.len() - 1;
        for (key, index) in old.into_iter().filter(|(k, _)| *k != EMPTY) {
            let mut slot = hash(key) & mask;
            while self.table[slot].0 != EMPTY {
                slot = (slot + 1) & mask;
            }
            self.table[slot] = (key, index);
        }
    }
}

/// The voxel of `p` packed into 63 bits (21 per axis).
#[inline]
fn pack(p: &Point, inv: f64) -> u64 {
    // Shifted by 2^20 the cell index is >= 0, where truncation is floor (libm's floor is a
    // function call without SSE4.1).
    let cell = |v: f32| ((v as f64) * inv + HALF_RANGE).clamp(0.0, 2.0 * HALF_RANGE - 1.0) as u64;
    (cell(p.x) << 42) | (cell(p.y) << 21) | cell(p.z)
}

/// Fibonacci hashing of a voxel key.
#[inline]
fn hash(key: u64) -> usize {
    (key.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 20) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute_force(points: &[Point], size: f32) -> Vec<(u64, Point)> {
        let mut groups: Vec<(u64, Sums)> = Vec::new();
        for p in points {
            let key = pack(p, 1.0 / size as f64);
            match groups.iter_mut().find(|(k, _)| *k == key) {
                Some((_, s)) => s.add(&Sums::of(p)),
                None => groups.push((key, Sums::of(p))),
            }
        }
        groups.into_iter().map(|(k, s)| (k, s.mean())).collect()
    }

    #[test]
    fn equals_grouping_by_voxel_in_first_met_order() {
        let points: Vec<Point> = (0..3000)
            .map(|i| {
                let f = i as f32;
                Point::new(
                    (f * 0.011).sin() * 3.0,
                    (f * 0.007).cos() * 2.0 - 1.0,
                    (f * 0.13).sin(),
                    f,
                )
            })
            .collect();
        let mut grid = VoxelGrid::default();
        let mut out = Vec::new();
        // A deliberately small expected size exercises the growth path.
        grid.downsample(points.iter().copied(), 0.2, 10, &mut out);
        let expected = brute_force(&points, 0.2);
        assert_eq!(out.len(), expected.len());
        for (got, (_, want)) in out.iter().zip(&expected) {
            for (a, b) in got.xyz().iter().zip(want.xyz()) {
                assert!((a - b).abs() < 1e-5);
            }
            assert!((got.intensity - want.intensity).abs() < 1e-2);
        }
    }

    #[test]
    fn negative_coordinates_use_floor_and_far_points_are_clamped() {
        let inv = 1.0 / 0.5;
        let a = pack(&Point::new(-0.1, 0.0, 0.0, 0.0), inv);
        let b = pack(&Point::new(0.1, 0.0, 0.0, 0.0), inv);
        assert_ne!(a, b);
        let far = pack(&Point::new(1e30, -1e30, 0.0, 0.0), inv);
        assert_ne!(far, EMPTY);
    }
}
