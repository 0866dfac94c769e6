//! A 3-D log-odds voxel map of the world, OctoMap's sensor model: each scan adds a hit to the
//! voxel of every obstacle point and a miss to every voxel its ray crossed, with clamping, so
//! space a moving object has left is cleared again instead of leaving a trail.
//!
//! Voxels live in dense 8×8×8 blocks found through a hash map (voxel hashing): a ray looks a
//! block up once per block it crosses, not once per voxel. Free space is recorded inside blocks
//! that hold something (never-occupied space far from any structure stays unknown), which
//! bounds memory; blocks far from the vehicle are dropped.

mod bev;
mod block;
mod octomap;
mod ray;

use nalgebra::Vector3;
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

use crate::Point;
pub use bev::{BevCell, BevGrid};
use block::{BLOCK_SIDE, Block, Voxel};
use ray::VoxelWalk;

/// The occupancy map's parameters (OctoMap's defaults where it has one).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OccupancyConfig {
    /// Voxel edge in metres.
    pub resolution: f64,
    /// Probability a hit adds to its voxel (OctoMap: 0.7).
    pub prob_hit: f64,
    /// Probability a traversing ray adds to a voxel (OctoMap: 0.4).
    pub prob_miss: f64,
    /// Lower clamping threshold (OctoMap: 0.1192).
    pub clamp_min: f64,
    /// Upper clamping threshold (OctoMap: 0.971).
    pub clamp_max: f64,
    /// Rays clear free space up to this distance from the sensor (metres).
    pub max_ray_range: f64,
    /// Ground points clear the space above the road through one ray per cell of this size
    /// (metres), which bounds the cost of a scan.
    pub ground_ray_cell: f64,
    /// Blocks farther than this from the vehicle are forgotten (metres).
    pub keep_radius: f64,
}

impl Default for OccupancyConfig {
    fn default() -> Self {
        Self {
            resolution: 0.25,
            prob_hit: 0.7,
            prob_miss: 0.4,
            clamp_min: 0.1192,
            clamp_max: 0.971,
            max_ray_range: 50.0,
            ground_ray_cell: 1.0,
            keep_radius: 120.0,
        }
    }
}

/// What the map knows of one voxel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoxelState {
    /// Occupancy probability.
    pub probability: f64,
    /// Consecutive scans the voxel has been occupied (0 when free).
    pub occupied_scans: u32,
}

/// The log-odds voxel map of one vehicle.
pub struct OccupancyMap {
    config: OccupancyConfig,
    log_hit: f32,
    log_miss: f32,
    log_min: f32,
    log_max: f32,
    blocks: Vec<Block>,
    index: FxHashMap<[i32; 3], u32>,
    scan: u32,
    hit_keys: Vec<[i32; 3]>,
    ground_cells: Vec<([i32; 2], usize)>,
}

/// Scans between two passes that drop far blocks.
const PRUNE_EVERY: u32 = 10;

fn log_odds(p: f64) -> f32 {
    (p / (1.0 - p)).ln() as f32
}

impl OccupancyMap {
    /// An empty map.
    pub fn new(config: OccupancyConfig) -> Self {
        Self {
            log_hit: log_odds(config.prob_hit),
            log_miss: log_odds(config.prob_miss),
            log_min: log_odds(config.clamp_min),
            log_max: log_odds(config.clamp_max),
            config,
            blocks: Vec::new(),
            index: FxHashMap::default(),
            scan: 0,
            hit_keys: Vec::new(),
            ground_cells: Vec::new(),
        }
    }

    /// The parameters in use.
    pub fn config(&self) -> &OccupancyConfig {
        &self.config
    }

    /// Scans integrated so far.
    pub fn scans(&self) -> u32 {
        self.scan
    }

    /// Voxels with a known state (occupied or free).
    pub fn known_voxels(&self) -> usize {
        self.blocks.iter().map(Block::known).sum()
    }

    /// Integrates one scan: `obstacles` (world frame) are hits, and every voxel on the rays from
    /// `sensor` to them, and to a thinned set of `ground` points, takes a miss. A voxel both hit
    /// and crossed in the same scan counts as hit, once, as in OctoMap.
    pub fn integrate(&mut self, sensor: Vector3<f64>, obstacles: &[Point], ground: &[Point]) {
        self.scan += 1;
        let scan = self.scan;
        let res = self.config.resolution;

        let mut hit_keys = std::mem::take(&mut self.hit_keys);
        hit_keys.clear();
        hit_keys.extend(
            obstacles
                .iter()
                .filter(|p| p.is_finite())
                .map(|p| self.key_of(p)),
        );
        hit_keys.sort_unstable();
        hit_keys.dedup();
        // Reserve the hit voxels first, so that rays of this scan do not clear them.
        for key in &hit_keys {
            self.voxel_mut_or_insert(*key).stamp = scan;
        }

        let max_range = self.config.max_ray_range;
        for key in &hit_keys {
            let end = Vector3::new(
                (f64::from(key[0]) + 0.5) * res,
                (f64::from(key[1]) + 0.5) * res,
                (f64::from(key[2]) + 0.5) * res,
            );
            self.clear_ray(&sensor, &end, max_range);
        }
        self.thin_ground(ground);
        let cells = std::mem::take(&mut self.ground_cells);
        for &(_, i) in &cells {
            let p = &ground[i];
            let end = Vector3::new(f64::from(p.x), f64::from(p.y), f64::from(p.z));
            self.clear_ray(&sensor, &end, max_range);
        }
        self.ground_cells = cells;

        for key in &hit_keys {
            let (log_hit, log_max) = (self.log_hit, self.log_max);
            let v = self.voxel_mut_or_insert(*key);
            let was_occupied = v.is_occupied();
            v.log_odds = (v.known_log_odds() + log_hit).min(log_max);
            if !was_occupied {
                v.since = scan;
            }
        }
        self.hit_keys = hit_keys;

        if scan.is_multiple_of(PRUNE_EVERY) {
            self.forget_far_blocks(&sensor);
        }
    }

    /// What the map knows of the voxel holding `p`; `None` while it is unknown.
    pub fn voxel(&self, p: &Vector3<f64>) -> Option<VoxelState> {
        let key = self.key_of_f64(p);
        let block = self.index.get(&block_key(key))?;
        let v = self.blocks[*block as usize].voxels[local_index(key)];
        v.is_known().then(|| VoxelState {
            probability: 1.0 - 1.0 / (1.0 + f64::from(v.log_odds).exp()),
            occupied_scans: if v.is_occupied() {
                self.scan - v.since + 1
            } else {
                0
            },
        })
    }

    /// The share of `points` (world frame) that lie in voxels occupied for at least
    /// `min_scans` consecutive scans: near 1 for long-standing structure, near 0 for something
    /// that just arrived.
    pub fn persistent_fraction(&self, points: &[Point], min_scans: u32) -> f64 {
        if points.is_empty() {
            return 0.0;
        }
        let persistent = points
            .iter()
            .filter(|p| {
                let q = Vector3::new(f64::from(p.x), f64::from(p.y), f64::from(p.z));
                self.voxel(&q)
                    .is_some_and(|v| v.occupied_scans >= min_scans)
            })
            .count();
        persistent as f64 / points.len() as f64
    }

    /// The map as an OctoMap binary tree file (`.bt`), readable by octovis and the octomap
    /// library: maximum-likelihood occupied/free leaves, pruned.
    pub fn to_bt(&self) -> Vec<u8> {
        let leaves: Vec<([i32; 3], bool)> =
            self.known().map(|(k, v)| (k, v.is_occupied())).collect();
        octomap::write_bt(self.config.resolution, &leaves)
    }

    /// A bird's-eye view of the square of half side `half_extent` metres around `center`:
    /// a cell is occupied when any voxel above it is, free when one is free and none occupied.
    pub fn bev(&self, center: [f64; 2], half_extent: f64) -> BevGrid {
        BevGrid::from_voxels(self.config.resolution, center, half_extent, self.known())
    }

    fn known(&self) -> impl Iterator<Item = ([i32; 3], Voxel)> + '_ {
        self.index.iter().flat_map(move |(bkey, &b)| {
            let block = &self.blocks[b as usize];
            block
                .voxels
                .iter()
                .enumerate()
                .filter(|(_, v)| v.is_known())
                .map(move |(i, v)| {
                    let s = BLOCK_SIDE as i32;
                    let i = i as i32;
                    (
                        [
                            bkey[0] * s + i % s,
                            bkey[1] * s + (i / s) % s,
                            bkey[2] * s + i / (s * s),
                        ],
                        *v,
                    )
                })
        })
    }

    fn key_of(&self, p: &Point) -> [i32; 3] {
        let inv = 1.0 / self.config.resolution;
        [
            (f64::from(p.x) * inv).floor() as i32,
            (f64::from(p.y) * inv).floor() as i32,
            (f64::from(p.z) * inv).floor() as i32,
        ]
    }

    fn key_of_f64(&self, p: &Vector3<f64>) -> [i32; 3] {
        let inv = 1.0 / self.config.resolution;
        [
            (p.x * inv).floor() as i32,
            (p.y * inv).floor() as i32,
            (p.z * inv).floor() as i32,
        ]
    }

    fn voxel_mut_or_insert(&mut self, key: [i32; 3]) -> &mut Voxel {
        let next = self.blocks.len() as u32;
        let b = *self.index.entry(block_key(key)).or_insert(next);
        if b == next {
            self.blocks.push(Block::default());
        }
        &mut self.blocks[b as usize].voxels[local_index(key)]
    }

    /// One miss for every voxel of an existing block crossed on the way from `from` to `to`
    /// (the end voxel excluded), at most once per scan. Blocks the map does not hold are
    /// jumped over whole.
    fn clear_ray(&mut self, from: &Vector3<f64>, to: &Vector3<f64>, max_range: f64) {
        let (scan, log_miss, log_min) = (self.scan, self.log_miss, self.log_min);
        let delta = to - from;
        let length = delta.norm();
        let end = if length > max_range {
            from + delta * (max_range / length)
        } else {
            *to
        };
        let res = self.config.resolution;
        let mut walk = VoxelWalk::new(from / res, end / res);
        while let Some(key) = walk.current() {
            let Some(&b) = self.index.get(&block_key(key)) else {
                walk.leave_block();
                continue;
            };
            let voxels = &mut self.blocks[b as usize].voxels;
            let mut next = Some(key);
            while let Some(key) = next {
                let v = &mut voxels[local_index(key)];
                if v.stamp != scan {
                    v.stamp = scan;
                    v.log_odds = (v.known_log_odds() + log_miss).max(log_min);
                }
                next = walk.advance();
            }
        }
    }

    /// Keeps one ground point per `ground_ray_cell` square (the first in scan order).
    fn thin_ground(&mut self, ground: &[Point]) {
        let inv = 1.0 / self.config.ground_ray_cell;
        self.ground_cells.clear();
        self.ground_cells.extend(
            ground
                .iter()
                .enumerate()
                .filter(|(_, p)| p.is_finite())
                .map(|(i, p)| {
                    (
                        [
                            (p.x as f64 * inv).floor() as i32,
                            (p.y as f64 * inv).floor() as i32,
                        ],
                        i,
                    )
                }),
        );
        self.ground_cells.sort_unstable();
        self.ground_cells.dedup_by_key(|(cell, _)| *cell);
    }

    fn forget_far_blocks(&mut self, sensor: &Vector3<f64>) {
        let side = self.config.resolution * BLOCK_SIDE as f64;
        let keep2 = self.config.keep_radius * self.config.keep_radius;
        let is_near = |k: &[i32; 3]| {
            let dx = (f64::from(k[0]) + 0.5) * side - sensor.x;
            let dy = (f64::from(k[1]) + 0.5) * side - sensor.y;
            dx * dx + dy * dy <= keep2
        };
        if self.index.keys().all(is_near) {
            return;
        }
        let mut old: Vec<Option<Block>> = std::mem::take(&mut self.blocks)
            .into_iter()
            .map(Some)
            .collect();
        let old_index = std::mem::take(&mut self.index);
        for (key, b) in old_index {
            if let (true, Some(block)) = (is_near(&key), old[b as usize].take()) {
                self.index.insert(key, self.blocks.len() as u32);
                self.blocks.push(block);
            }
        }
    }
}

fn block_key(key: [i32; 3]) -> [i32; 3] {
    let s = BLOCK_SIDE.trailing_zeros();
    [key[0] >> s, key[1] >> s, key[2] >> s]
}

fn local_index(key: [i32; 3]) -> usize {
    let m = BLOCK_SIDE as i32 - 1;
    let s = BLOCK_SIDE;
    (key[0] & m) as usize + (key[1] & m) as usize * s + (key[2] & m) as usize * s * s
}

#[cfg(test)]
mod tests;
