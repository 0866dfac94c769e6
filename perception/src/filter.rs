//! Stage 2: keep the points the tracker cares about: a range band around the sensor, an
//! optional crop box, minus the ego vehicle's own returns, optionally voxel down-sampled.
//! Works in the sensor frame, before ground removal.

use serde::{Deserialize, Serialize};

use crate::{Point, voxel::VoxelGrid};

/// An axis-aligned box in the sensor frame (metres); a point on a face is inside.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Aabb {
    /// Lower corner (x, y, z).
    pub min: [f32; 3],
    /// Upper corner (x, y, z).
    pub max: [f32; 3],
}

impl Aabb {
    /// Whether `p` lies inside the box (faces included).
    pub fn contains(&self, p: &Point) -> bool {
        p.x >= self.min[0]
            && p.x <= self.max[0]
            && p.y >= self.min[1]
            && p.y <= self.max[1]
            && p.z >= self.min[2]
            && p.z <= self.max[2]
    }

    /// [`contains`](Self::contains), every comparison made.
    #[inline]
    fn contains_branch_free(&self, p: &Point) -> bool {
        (p.x >= self.min[0])
            & (p.x <= self.max[0])
            & (p.y >= self.min[1])
            & (p.y <= self.max[1])
            & (p.z >= self.min[2])
            & (p.z <= self.max[2])
    }
}

/// The KITTI recording car around its Velodyne: body, mirrors (|y| up to 1.45 m at
/// x ≈ -1 m) and bonnet (x up to 2.6 m) all return points in the raw scans.
pub const KITTI_EGO_BOX: Aabb = Aabb {
    min: [-2.8, -1.5, -1.9],
    max: [2.8, 1.5, 0.3],
};

/// What the filter keeps.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FilterConfig {
    /// Points nearer to the sensor than this are dropped (metres). Default 0.5 (also drops the
    /// all-zero "no return" points some KITTI scans hold).
    pub min_range: f32,
    /// Points farther than this are dropped (metres). Default 50: beyond, a car is a handful
    /// of points on a few rings, too sparse to cluster or describe.
    pub max_range: f32,
    /// Keep only points inside this box. Default: none.
    pub crop: Option<Aabb>,
    /// Drop points inside this box: the ego vehicle's own returns. Default [`KITTI_EGO_BOX`].
    pub ego_box: Option<Aabb>,
    /// Replace the points of each cubic voxel of this edge (metres) by their mean, as PCL's
    /// `VoxelGrid` does. Voxels are aligned to multiples of the edge. Default: none (every
    /// point kept).
    pub voxel_size: Option<f32>,
}

impl Default for FilterConfig {
    fn default() -> Self {
        Self {
            min_range: 0.5,
            max_range: 50.0,
            crop: None,
            ego_box: Some(KITTI_EGO_BOX),
            voxel_size: None,
        }
    }
}

impl FilterConfig {
    /// Whether a single point passes the range band, the crop and the ego box (the voxel step
    /// aside). Non-finite points never pass.
    pub fn keeps(&self, p: &Point) -> bool {
        let r2 = p.norm_squared();
        p.is_finite()
            && r2 >= self.min_range * self.min_range
            && r2 <= self.max_range * self.max_range
            && self.crop.is_none_or(|b| b.contains(p))
            && !self.ego_box.is_some_and(|b| b.contains(p))
    }

    /// [`keeps`](Self::keeps), every comparison made (no short cut): one branch-free
    /// expression the compiler can schedule freely.
    #[inline]
    fn keeps_branch_free(&self, p: &Point) -> bool {
        let r2 = p.norm_squared();
        let finite = p.x.is_finite() & p.y.is_finite() & p.z.is_finite();
        let finite = finite & p.intensity.is_finite();
        let in_band =
            (r2 >= self.min_range * self.min_range) & (r2 <= self.max_range * self.max_range);
        let cropped = self.crop.is_none_or(|b| b.contains_branch_free(p));
        let ego = self.ego_box.is_some_and(|b| b.contains_branch_free(p));
        finite & in_band & cropped & !ego
    }
}

/// Points whose tests run together, before their copies.
const CHUNK: usize = 64;

/// The filter stage with its reusable buffers.
#[derive(Debug, Default)]
pub struct Filter {
    config: FilterConfig,
    voxels: VoxelGrid,
}

impl Filter {
    /// A filter with `config`.
    pub fn new(config: FilterConfig) -> Self {
        Self {
            config,
            ..Default::default()
        }
    }

    /// The configuration in use.
    pub fn config(&self) -> &FilterConfig {
        &self.config
    }

    /// Writes the kept points of `input` into `out` (cleared first): in input order, or, with
    /// voxels, one mean point per voxel in the order the voxels are first met. Allocates nothing once the buffers have
    /// grown to the scan size.
    pub fn run(&mut self, input: &[Point], out: &mut Vec<Point>) {
        out.clear();
        let voxel = self.config.voxel_size.filter(|v| v.is_finite() && *v > 0.0);
        let Some(voxel) = voxel else {
            let mut keep = [false; CHUNK];
            for points in input.chunks(CHUNK) {
                // Every test of every point first, without branches, then the copies.
                for (keep, p) in keep.iter_mut().zip(points) {
                    *keep = self.config.keeps_branch_free(p);
                }
                let kept = points.iter().zip(&keep).filter(|&(_, &keep)| keep);
                out.extend(kept.map(|(p, _)| *p));
            }
            return;
        };
        let config = &self.config;
        self.voxels.downsample(
            input.iter().copied().filter(|p| config.keeps(p)),
            voxel,
            input.len(),
            out,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(config: FilterConfig, input: &[Point]) -> Vec<Point> {
        let mut out = Vec::new();
        Filter::new(config).run(input, &mut out);
        out
    }

    #[test]
    fn range_band_keeps_order_and_drops_zeros_and_nan() {
        let input = [
            Point::new(0.0, 0.0, 0.0, 0.0),
            Point::new(10.0, 0.0, 0.0, 0.1),
            Point::new(0.3, 0.0, 0.0, 0.2),
            Point::new(0.0, -49.9, 0.0, 0.3),
            Point::new(60.0, 0.0, 0.0, 0.4),
            Point::new(f32::NAN, 5.0, 0.0, 0.5),
            Point::new(3.0, 4.0, 0.0, 0.6),
        ];
        let config = FilterConfig {
            ego_box: None,
            ..Default::default()
        };
        assert_eq!(run(config, &input), vec![input[1], input[3], input[6]]);
    }

    #[test]
    fn ego_box_and_crop() {
        let mirror = Point::new(-1.0, 1.4, -0.6, 0.0);
        let cyclist = Point::new(4.0, 1.4, -0.6, 0.0);
        let behind = Point::new(-20.0, 0.0, 0.0, 0.0);
        let defaults = run(FilterConfig::default(), &[mirror, cyclist, behind]);
        assert_eq!(defaults, vec![cyclist, behind]);
        let front = FilterConfig {
            crop: Some(Aabb {
                min: [0.0, -20.0, -3.0],
                max: [50.0, 20.0, 3.0],
            }),
            ..Default::default()
        };
        assert_eq!(run(front, &[mirror, cyclist, behind]), vec![cyclist]);
    }

    #[test]
    fn voxels_average_their_points() {
        let input = [
            Point::new(10.01, 0.01, 0.01, 0.2),
            Point::new(10.09, 0.09, 0.09, 0.4),
            Point::new(10.31, 0.01, 0.01, 1.0),
        ];
        let config = FilterConfig {
            voxel_size: Some(0.1),
            ..Default::default()
        };
        let mut out = run(config, &input);
        out.sort_by(|a, b| a.x.total_cmp(&b.x));
        assert_eq!(out.len(), 2);
        assert!((out[0].x - 10.05).abs() < 1e-5 && (out[0].y - 0.05).abs() < 1e-6);
        assert!((out[0].intensity - 0.3).abs() < 1e-6);
        assert_eq!(out[1], input[2]);
    }

    #[test]
    fn branch_free_tests_keep_what_keeps_keeps() {
        let values = [
            f32::NAN,
            f32::NEG_INFINITY,
            -60.0,
            -2.8,
            -1.5,
            -0.4,
            0.0,
            0.3,
            1.5,
            2.8,
            49.9,
            f32::INFINITY,
        ];
        let crop = Some(Aabb {
            min: [-1.5, -2.8, -0.4],
            max: [49.9, 1.5, 2.8],
        });
        for config in [
            FilterConfig::default(),
            FilterConfig {
                crop,
                ego_box: None,
                ..Default::default()
            },
        ] {
            for &x in &values {
                for &y in &values {
                    for &z in &values {
                        for intensity in [0.5, f32::NAN] {
                            let p = Point::new(x, y, z, intensity);
                            assert_eq!(config.keeps_branch_free(&p), config.keeps(&p), "{p:?}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn warm_runs_do_not_reallocate() {
        let input: Vec<Point> = (0..1000)
            .map(|i| Point::new(5.0 + (i % 37) as f32 * 0.1, (i / 37) as f32 * 0.1, 0.0, 0.0))
            .collect();
        for voxel_size in [None, Some(0.2)] {
            let mut filter = Filter::new(FilterConfig {
                voxel_size,
                ..Default::default()
            });
            let mut out = Vec::new();
            filter.run(&input, &mut out);
            let (capacity, pointer) = (out.capacity(), out.as_ptr());
            filter.run(&input, &mut out);
            assert_eq!((out.capacity(), out.as_ptr()), (capacity, pointer));
        }
    }
}
