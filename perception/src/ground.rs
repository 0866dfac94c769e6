//! Stage 3: ground removal with RANSAC planes, in the sensor frame.
//!
//! A road is not one plane over 50 m (grades change, kerbs, crowns), so, as the concentric
//! zone model of Patchwork (Lim et al. 2021) does, the ground around the sensor is cut into
//! rings of horizontal range and azimuth sectors, and each zone gets its own plane:
//!
//! 1. a *near plane* is fitted by RANSAC to the points 3-15 m away (normal within
//!    `max_tilt_deg` of the sensor's z axis): the prior of the innermost ring;
//! 2. zone by zone, outwards, RANSAC fits a plane to the zone's points near its prior (the
//!    plane of the zone just inside it, along the same azimuth); the fit is refined by least
//!    squares (PCA) on its inliers and kept only if it is upright relative to the prior
//!    (`max_bend_deg`), does not step up or down more than `max_step` and has
//!    `min_zone_points` inliers; otherwise the zone inherits its prior, or, when no point lies
//!    near the prior at all, a plane at the near plane's slope meeting the prior at the
//!    zone's inner edge (with nothing to tell a zone's slope, a slope is not carried on);
//! 3. a point is ground when it lies at most `distance_threshold + threshold_growth · range`
//!    above its zone's plane (everything below it is ground too: reflections, kerb drops),
//!    unless its (x, y) column also holds points 0.25-0.6 m up: then it is the base of an
//!    obstacle (a wheel, a foot, the footing of a wall or pole) and stays with it.
//!
//! RANSAC stops early once `confidence` is reached for the best inlier ratio seen; every zone
//! draws from its own generator seeded from `seed`, so a scan always gives the same result.

use serde::{Deserialize, Serialize};

use crate::{
    Point,
    angle::fast_atan2_branchless,
    pca::{Moments, cross, dot, normalized, smallest_eigenvector},
};

/// Most points a zone's fit looks at: denser zones (near the sensor) are strided evenly.
const MAX_FIT_POINTS: usize = 2048;

/// One ring of the zone model.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ZoneRing {
    /// Outer edge of the ring, horizontal range in metres (the last ring reaches infinity).
    pub outer: f32,
    /// Azimuth sectors the ring is cut into (at least 1).
    pub sectors: usize,
}

/// Ground removal parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GroundConfig {
    /// RANSAC inlier distance and the height above its zone plane up to which a point is
    /// ground, near the sensor (metres). Default 0.2: kerbs and road noise stay ground, car
    /// sills and bumpers (≥ 0.25 m) do not.
    pub distance_threshold: f32,
    /// Extra ground tolerance per metre of horizontal range. Default 0.002 (+0.1 m at 50 m,
    /// where the beam footprint and a plane's extrapolation error grow).
    pub threshold_growth: f32,
    /// Most RANSAC iterations per plane. Default 100.
    pub max_iterations: usize,
    /// Stop RANSAC once a better plane would have been found with this probability.
    /// Default 0.999.
    pub confidence: f64,
    /// Most candidate points a RANSAC hypothesis is scored on (a deterministic subsample);
    /// the least-squares refit uses all candidates (at most 2048 per zone, evenly strided).
    /// Default 256.
    pub sample_size: usize,
    /// Seed of the RANSAC samples. Default 0x5eed.
    pub seed: u64,
    /// Largest angle between the near plane's normal and the sensor's z axis (degrees).
    /// Default 20 (the sensor rolls and pitches with the car, roads climb).
    pub max_tilt_deg: f64,
    /// Largest angle between a zone's plane and its prior (degrees). Default 10.
    pub max_bend_deg: f64,
    /// Largest height difference between a zone's plane and its prior at the zone's inliers
    /// (metres). Default 0.3.
    pub max_step: f32,
    /// Candidates of a zone's fit lie at most this far above its prior (metres). Default 0.5.
    pub band_above: f32,
    /// Candidates of a zone's fit lie at most this far below its prior (metres). Default 1.0.
    pub band_below: f32,
    /// Fewest inliers for a zone to get its own plane. Default 12.
    pub min_zone_points: usize,
    /// Horizontal range band of the points the near plane is fitted to (metres).
    /// Default [3, 15].
    pub near_band: [f32; 2],
    /// Height of the sensor above the road (metres): the ground plane assumed when the near
    /// range holds no plane at all. Default 1.73 (KITTI).
    pub sensor_height: f32,
    /// Edge of the square (x, y) columns of the obstacle-base test (metres; 0 turns it off).
    /// A column holding a point between `base_band[0]` and `base_band[1]` above its zone plane
    /// holds an obstacle that rises from the ground: its points under the ground threshold are
    /// the obstacle's base (wheels, feet, wall and pole footings), not ground. Default 0.1.
    pub base_cell: f32,
    /// Heights above the zone plane that mark a column as an obstacle's (metres): above kerbs,
    /// below car roofs and branches that overhang the ground. Default [0.25, 0.6].
    pub base_band: [f32; 2],
    /// The zone rings, inner to outer. Default: edges at 6, 12, 20, 30, 42 m, then to
    /// infinity, with 8, 16, 24, 32, 32, 32 sectors.
    pub rings: Vec<ZoneRing>,
}

impl Default for GroundConfig {
    fn default() -> Self {
        let ring = |outer, sectors| ZoneRing { outer, sectors };
        Self {
            distance_threshold: 0.2,
            threshold_growth: 0.002,
            max_iterations: 100,
            confidence: 0.999,
            sample_size: 256,
            seed: 0x5eed,
            max_tilt_deg: 20.0,
            max_bend_deg: 10.0,
            max_step: 0.3,
            band_above: 0.5,
            band_below: 1.0,
            min_zone_points: 12,
            near_band: [3.0, 15.0],
            sensor_height: 1.73,
            base_cell: 0.1,
            base_band: [0.25, 0.6],
            rings: vec![
                ring(6.0, 8),
                ring(12.0, 16),
                ring(20.0, 24),
                ring(30.0, 32),
                ring(42.0, 32),
                ring(f32::INFINITY, 32),
            ],
        }
    }
}

/// A plane `normal · p + offset = 0`, with a unit normal pointing up (positive z).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plane {
    /// Unit normal, z component > 0.
    pub normal: [f64; 3],
    /// `-normal · q` for any point `q` on the plane: the height of the origin above it.
    pub offset: f64,
}

impl Plane {
    /// Signed height of `p` above the plane (metres, along the normal).
    pub fn height(&self, p: [f64; 3]) -> f64 {
        dot(self.normal, p) + self.offset
    }

    /// The plane's z above (x, y).
    pub fn z_at(&self, xy: [f64; 2]) -> f64 {
        -(self.normal[0] * xy[0] + self.normal[1] * xy[1] + self.offset) / self.normal[2]
    }

    /// The plane through `point` with `normal` (made unit and turned up), if the normal is
    /// not zero or horizontal.
    pub fn through(point: [f64; 3], normal: [f64; 3]) -> Option<Self> {
        let mut normal = normalized(normal)?;
        if normal[2] == 0.0 {
            return None;
        }
        if normal[2] < 0.0 {
            normal = normal.map(|c| -c);
        }
        Some(Self {
            normal,
            offset: -dot(normal, point),
        })
    }
}

/// The ground removal stage with its reusable buffers.
#[derive(Debug)]
pub struct GroundRemoval {
    config: GroundConfig,
    /// The rings (at least one, each with at least one sector), each one's first zone and
    /// its sectors per radian of azimuth.
    rings: Vec<ZoneRing>,
    first_zone: Vec<usize>,
    per_radian: Vec<f32>,
    /// Per input point: its zone and horizontal range.
    zone_of: Vec<u32>,
    range_of: Vec<f32>,
    /// Positions of the points of zone `z`: `by_zone[zone_start[z]..zone_start[z + 1]]`
    /// (copies, so that a zone's points are read in one sweep).
    zone_start: Vec<u32>,
    by_zone: Vec<[f32; 3]>,
    /// Per zone: its plane after the fit.
    zone_plane: Vec<Plane>,
    /// Scratch: candidate points of one fit, and the subsample hypotheses are scored on.
    candidates: Vec<[f64; 3]>,
    sample: Sample,
    /// Scratch: counting-sort cursors and ground flags.
    cursor: Vec<u32>,
    ground: Vec<bool>,
    /// Scratch: the zone planes in f32, the columns of the obstacle-base test holding an
    /// obstacle (one bit each: the table stays in cache), and the (x, y) bounds of the finite
    /// points.
    plane32: Vec<[f32; 4]>,
    obstacle_column: Vec<u64>,
    bounds: [f32; 4],
}

impl Default for GroundRemoval {
    fn default() -> Self {
        Self::new(GroundConfig::default())
    }
}

/// Where a zone's plane must meet its prior within `max_step`.
#[derive(Clone, Copy)]
enum StepCheck {
    /// Nowhere (the near plane has no prior but the sensor's axis).
    None,
    /// At the (x, y) of the centroid of the zone's inliers (the first ring, inside the near
    /// plane's own band).
    AtInliers,
    /// At this (x, y): the middle of the zone's inner edge, where the ground must be
    /// continuous with the ring inside.
    At([f64; 2]),
}

impl GroundRemoval {
    /// A ground removal stage with `config`.
    pub fn new(config: GroundConfig) -> Self {
        let mut rings: Vec<ZoneRing> = config
            .rings
            .iter()
            .map(|r| ZoneRing {
                outer: r.outer,
                sectors: r.sectors.max(1),
            })
            .collect();
        if rings.is_empty() {
            rings.push(ZoneRing {
                outer: f32::INFINITY,
                sectors: 1,
            });
        }
        let first_zone = rings
            .iter()
            .scan(0, |next, ring| {
                let first = *next;
                *next += ring.sectors;
                Some(first)
            })
            .collect();
        let per_radian = rings
            .iter()
            .map(|r| r.sectors as f32 / std::f32::consts::TAU)
            .collect();
        Self {
            config,
            rings,
            first_zone,
            per_radian,
            zone_of: Vec::new(),
            range_of: Vec::new(),
            zone_start: Vec::new(),
            by_zone: Vec::new(),
            zone_plane: Vec::new(),
            candidates: Vec::new(),
            sample: Sample::default(),
            cursor: Vec::new(),
            ground: Vec::new(),
            plane32: Vec::new(),
            obstacle_column: Vec::new(),
            bounds: [0.0; 4],
        }
    }

    /// The configuration in use.
    pub fn config(&self) -> &GroundConfig {
        &self.config
    }

    /// The plane of every zone in the last run, ring after ring, sector after sector
    /// (sector 0 starts at azimuth -π).
    pub fn zone_planes(&self) -> &[Plane] {
        &self.zone_plane
    }

    /// Writes the points of `points` that are not ground into `out` (cleared first), in input
    /// order, and returns the near plane.
    pub fn remove(&mut self, points: &[Point], out: &mut Vec<Point>) -> Plane {
        let mut ground = std::mem::take(&mut self.ground);
        let plane = self.segment(points, &mut ground);
        out.clear();
        out.extend(
            points
                .iter()
                .zip(&ground)
                .filter(|&(_, &g)| !g)
                .map(|(p, _)| *p),
        );
        self.ground = ground;
        plane
    }

    /// Marks each point of `points` as ground or not in `is_ground` (overwritten) and returns
    /// the near plane. Non-finite points are marked ground (they are no obstacle).
    pub fn segment(&mut self, points: &[Point], is_ground: &mut Vec<bool>) -> Plane {
        self.assign_zones(points);
        let near = self.fit_near_plane(points);
        self.fit_zones(near);

        self.classify(points, is_ground);
        near
    }

    /// Marks ground: at most `distance_threshold + threshold_growth · range` above the zone's
    /// plane, and not the base of an obstacle (see [`GroundConfig::base_cell`]).
    fn classify(&mut self, points: &[Point], is_ground: &mut Vec<bool>) {
        let config = &self.config;
        // Zone planes in f32 (sensor-frame coordinates are small).
        self.plane32.clear();
        self.plane32.extend(self.zone_plane.iter().map(|p| {
            [
                p.normal[0] as f32,
                p.normal[1] as f32,
                p.normal[2] as f32,
                p.offset as f32,
            ]
        }));
        // Columns of the obstacle-base test: at most 4096 a side, wider clouds get wider ones.
        let [min_x, min_y, max_x, max_y] = self.bounds;
        let cell = config.base_cell;
        let base_test = cell > 0.0 && cell.is_finite() && min_x <= max_x;
        let (side, ny) = if base_test {
            let side = cell.max((max_x - min_x).max(max_y - min_y) / 4096.0);
            (side, ((max_y - min_y) / side) as usize + 1)
        } else {
            (1.0, 1)
        };
        let nx = if base_test {
            ((max_x - min_x) / side) as usize + 1
        } else {
            1
        };
        let inv = 1.0 / side;
        let [band_lo, band_hi] = config.base_band;
        let (limit, growth) = (config.distance_threshold, config.threshold_growth);
        let obstacle = &mut self.obstacle_column;
        obstacle.clear();
        obstacle.resize((nx * ny).div_ceil(64), 0);
        is_ground.clear();
        is_ground.resize(points.len(), true);
        let column_of = |p: &Point| {
            index_below((p.x - min_x) * inv, nx) * ny + index_below((p.y - min_y) * inv, ny)
        };
        let located = points.iter().zip(&self.zone_of).zip(&self.range_of);
        for (((p, &zone), &range), ground) in located.zip(is_ground.iter_mut()) {
            // Non-finite points stay ground, in no column.
            if zone == u32::MAX {
                continue;
            }
            let [a, b, c, d] = self.plane32[zone as usize];
            let h = a * p.x + b * p.y + c * p.z + d;
            *ground = h <= limit + growth * range;
            if base_test && h >= band_lo && h <= band_hi {
                let column = column_of(p);
                obstacle[column / 64] |= 1 << (column % 64);
            }
        }
        if base_test {
            let located = points.iter().zip(&self.zone_of);
            for ((p, &zone), g) in located.zip(is_ground.iter_mut()) {
                if *g && zone != u32::MAX {
                    let column = column_of(p);
                    if (obstacle[column / 64] >> (column % 64)) & 1 == 1 {
                        *g = false;
                    }
                }
            }
        }
    }

    /// Computes each point's zone and buckets the points by zone (counting sort).
    fn assign_zones(&mut self, points: &[Point]) {
        let rings = &self.rings;
        let zones: usize = rings.iter().map(|r| r.sectors).sum();
        self.zone_start.clear();
        self.zone_start.resize(zones + 1, 0);
        self.bounds = [
            f32::INFINITY,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NEG_INFINITY,
        ];
        self.zone_of.clear();
        self.zone_of.resize(points.len(), u32::MAX);
        self.range_of.clear();
        self.range_of.resize(points.len(), 0.0);
        let mut bounds = self.bounds;
        // Points come ring by ring and azimuth by azimuth, so a zone's points come in runs:
        // counted in a register and added once a run ends, not one memory increment each.
        let (mut run_zone, mut run) = (0usize, 0u32);
        let inner = &rings[..rings.len() - 1];
        let mut chunk = ZoneChunk::default();
        let slots = self
            .zone_of
            .chunks_mut(CHUNK)
            .zip(self.range_of.chunks_mut(CHUNK));
        for (points, (zone_of, range_of)) in points.chunks(CHUNK).zip(slots) {
            chunk.measure(points, inner);
            for (k, p) in points.iter().enumerate() {
                // Non-finite points are in no zone.
                if !p.is_finite() {
                    continue;
                }
                let ring = chunk.ring[k] as usize;
                let sector =
                    sector_index(chunk.azimuth[k], self.per_radian[ring], rings[ring].sectors);
                // Plain comparisons: the point is finite, f32::min's NaN handling is not needed.
                bounds = [
                    if p.x < bounds[0] { p.x } else { bounds[0] },
                    if p.y < bounds[1] { p.y } else { bounds[1] },
                    if p.x > bounds[2] { p.x } else { bounds[2] },
                    if p.y > bounds[3] { p.y } else { bounds[3] },
                ];
                let zone = self.first_zone[ring] + sector;
                zone_of[k] = zone as u32;
                range_of[k] = chunk.range[k];
                if zone != run_zone {
                    self.zone_start[run_zone + 1] += run;
                    (run_zone, run) = (zone, 0);
                }
                run += 1;
            }
        }
        self.zone_start[run_zone + 1] += run;
        self.bounds = bounds;
        for z in 0..zones {
            self.zone_start[z + 1] += self.zone_start[z];
        }
        self.by_zone.clear();
        self.by_zone
            .resize(self.zone_start[zones] as usize, [0.0; 3]);
        self.cursor.clear();
        self.cursor.extend_from_slice(&self.zone_start[..zones]);
        for (p, &zone) in points.iter().zip(&self.zone_of) {
            if zone != u32::MAX {
                let slot = &mut self.cursor[zone as usize];
                self.by_zone[*slot as usize] = p.xyz();
                *slot += 1;
            }
        }
    }

    /// RANSAC on the points of the near band: the prior of the first ring.
    fn fit_near_plane(&mut self, points: &[Point]) -> Plane {
        let [lo, hi] = self.config.near_band;
        // The band holds half the scan; an evenly strided share is plenty for one plane.
        let stride = points.len().div_ceil(4 * MAX_FIT_POINTS).max(1);
        self.candidates.clear();
        self.candidates.extend(
            points
                .iter()
                .zip(&self.range_of)
                .step_by(stride)
                .filter(|&(p, &r)| p.is_finite() && r >= lo && r <= hi)
                .map(|(p, _)| widen(p)),
        );
        let up = Plane {
            normal: [0.0, 0.0, 1.0],
            offset: self.config.sensor_height as f64,
        };
        let fit = self.fit(&up, self.config.max_tilt_deg, StepCheck::None, u64::MAX);
        fit.unwrap_or(up)
    }

    /// Fits every zone, ring by ring outwards, each from the plane of the zone inside it.
    fn fit_zones(&mut self, near: Plane) {
        self.zone_plane.clear();
        let (band_above, band_below) =
            (self.config.band_above as f64, self.config.band_below as f64);
        for r in 0..self.rings.len() {
            let ring = self.rings[r];
            for sector in 0..ring.sectors {
                let zone = self.first_zone[r] + sector;
                let (prior, check) = if r == 0 {
                    (near, StepCheck::AtInliers)
                } else {
                    // The inner zone at this sector's middle azimuth, met at the inner edge.
                    let inner = self.rings[r - 1];
                    let middle = ((2 * sector + 1) * inner.sectors / (2 * ring.sectors))
                        .min(inner.sectors - 1);
                    let azimuth = -std::f64::consts::PI
                        + (sector as f64 + 0.5) * std::f64::consts::TAU / ring.sectors as f64;
                    let edge = inner.outer as f64;
                    (
                        self.zone_plane[self.first_zone[r - 1] + middle],
                        StepCheck::At([edge * azimuth.cos(), edge * azimuth.sin()]),
                    )
                };
                self.candidates.clear();
                let members = self.zone_start[zone] as usize..self.zone_start[zone + 1] as usize;
                let stride = members.len().div_ceil(MAX_FIT_POINTS).max(1);
                for q in self.by_zone[members].iter().step_by(stride) {
                    let p = q.map(f64::from);
                    let h = prior.height(p);
                    if h <= band_above && h >= -band_below {
                        self.candidates.push(p);
                    }
                }
                let fitted = self.fit(&prior, self.config.max_bend_deg, check, zone as u64);
                let plane = match (fitted, check) {
                    (Some(plane), _) => plane,
                    // No point near the prior at all: nothing tells this zone's slope, so the
                    // ground goes on from the inner edge at the near plane's. Carried on, a
                    // prior tilted by a bank or a kerb climbed metres within a few rings and
                    // took every object behind it for ground.
                    (None, StepCheck::At(xy)) if self.candidates.is_empty() => {
                        Plane::through([xy[0], xy[1], prior.z_at(xy)], near.normal).unwrap_or(prior)
                    }
                    (None, _) => prior,
                };
                self.zone_plane.push(plane);
            }
        }
    }

    /// RANSAC + least-squares refit on `self.candidates`: a plane within `max_angle_deg` of
    /// `prior`'s normal, meeting `prior` within `max_step` where `check` says, with at least
    /// `min_zone_points` inliers. `stream` picks the random stream.
    fn fit(
        &mut self,
        prior: &Plane,
        max_angle_deg: f64,
        check: StepCheck,
        stream: u64,
    ) -> Option<Plane> {
        let config = &self.config;
        let min_inliers = config.min_zone_points.max(3);
        if self.candidates.len() < min_inliers {
            return None;
        }
        let threshold = config.distance_threshold as f64;
        let min_cos = max_angle_deg.to_radians().cos();
        // Score hypotheses on an evenly strided subsample.
        let stride = self.candidates.len().div_ceil(config.sample_size.max(3));
        self.sample
            .fill(self.candidates.iter().step_by(stride).copied());
        let n = self.sample.len();
        let mut rng = SplitMix64::new(config.seed ^ stream.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        let mut best: Option<(Plane, i64, usize)> = None;
        let mut needed = config.max_iterations;
        let mut iteration = 0;
        while iteration < needed.min(config.max_iterations) {
            iteration += 1;
            let (a, b, c) = rng.three_distinct(n);
            let (pa, pb, pc) = (self.sample.get(a), self.sample.get(b), self.sample.get(c));
            let normal = cross(sub(pb, pa), sub(pc, pa));
            let Some(plane) = Plane::through(pa, normal) else {
                continue;
            };
            if dot(plane.normal, prior.normal) < min_cos {
                continue;
            }
            let to_beat = best.map(|(_, s, _)| s);
            let Some((score, inliers)) = self.sample.score(&plane, threshold, to_beat) else {
                continue;
            };
            best = Some((plane, score, inliers));
            let ratio = inliers as f64 / n as f64;
            needed = iterations_needed(ratio, config.confidence, config.max_iterations);
        }
        let (hypothesis, _, _) = best?;

        // Least-squares (orthogonal) refit on all candidates within the threshold.
        let mut moments = Moments::default();
        for &p in &self.candidates {
            if hypothesis.height(p).abs() <= threshold {
                moments.add(p);
            }
        }
        if moments.count() < min_inliers {
            return None;
        }
        let (_, normal) = smallest_eigenvector(moments.covariance());
        let mean = moments.mean();
        let refit = Plane::through(mean, normal)
            .filter(|p| dot(p.normal, prior.normal) >= min_cos)
            .unwrap_or(hypothesis);
        let anchor = match check {
            StepCheck::None => return Some(refit),
            StepCheck::AtInliers => [mean[0], mean[1]],
            StepCheck::At(xy) => xy,
        };
        let step = refit.z_at(anchor) - prior.z_at(anchor);
        (step.abs() <= config.max_step as f64).then_some(refit)
    }
}

/// The subsample RANSAC hypotheses are scored on, coordinate by coordinate so that the
/// scoring loop runs over plain arrays.
#[derive(Debug, Default)]
struct Sample {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
}

/// Points scored between two checks of whether a hypothesis can still win.
const SCORE_CHUNK: usize = 32;

impl Sample {
    /// Replaces the points.
    fn fill(&mut self, points: impl Iterator<Item = [f64; 3]>) {
        self.x.clear();
        self.y.clear();
        self.z.clear();
        for [x, y, z] in points {
            self.x.push(x);
            self.y.push(y);
            self.z.push(z);
        }
    }

    /// Number of points.
    fn len(&self) -> usize {
        self.x.len()
    }

    /// Point `i`.
    fn get(&self, i: usize) -> [f64; 3] {
        [self.x[i], self.y[i], self.z[i]]
    }

    /// The score of `plane` (inliers within `threshold`, less two for each point more than
    /// `2 · threshold` below it: ground is the lowest surface, so a plane with points well
    /// below it, a strip of a car's side or a low wall top, is penalised) and its inliers;
    /// `None` when it cannot beat `to_beat`. Counting stops as soon as the points left could
    /// not lift the score above `to_beat` even if all were inliers, which never changes
    /// which hypothesis wins.
    fn score(&self, plane: &Plane, threshold: f64, to_beat: Option<i64>) -> Option<(i64, usize)> {
        let n = self.len();
        let ([a, b, c], d) = (plane.normal, plane.offset);
        let far_below = -2.0 * threshold;
        let (mut inliers, mut below) = (0usize, 0usize);
        for start in (0..n).step_by(SCORE_CHUNK) {
            if let Some(to_beat) = to_beat {
                let reachable = inliers as i64 - 2 * below as i64 + (n - start) as i64;
                if reachable <= to_beat {
                    return None;
                }
            }
            let end = (start + SCORE_CHUNK).min(n);
            let (xs, ys, zs) = (
                &self.x[start..end],
                &self.y[start..end],
                &self.z[start..end],
            );
            for ((&x, &y), &z) in xs.iter().zip(ys).zip(zs) {
                // Plane::height, operation for operation.
                let h = a * x + b * y + c * z + d;
                inliers += usize::from(h.abs() <= threshold);
                below += usize::from(h < far_below);
            }
        }
        let score = inliers as i64 - 2 * below as i64;
        match to_beat {
            Some(to_beat) if score <= to_beat => None,
            _ => Some((score, inliers)),
        }
    }
}

/// RANSAC iterations needed to draw an all-inlier triple with probability `confidence` when
/// a fraction `ratio` of the points are inliers.
fn iterations_needed(ratio: f64, confidence: f64, max: usize) -> usize {
    let all_inliers = ratio.powi(3);
    if all_inliers >= 1.0 {
        return 1;
    }
    if all_inliers <= 0.0 {
        return max;
    }
    let n = (1.0 - confidence.clamp(0.0, 1.0 - 1e-12)).ln() / (1.0 - all_inliers).ln();
    if n.is_finite() {
        (n.ceil() as usize).clamp(1, max)
    } else {
        max
    }
}

/// Points whose range, azimuth and ring are computed together, in loops over arrays that
/// the compiler turns into SIMD.
const CHUNK: usize = 64;

/// The horizontal range, azimuth and ring of up to [`CHUNK`] points.
struct ZoneChunk {
    x: [f32; CHUNK],
    y: [f32; CHUNK],
    range: [f32; CHUNK],
    azimuth: [f32; CHUNK],
    ring: [u32; CHUNK],
}

impl Default for ZoneChunk {
    fn default() -> Self {
        Self {
            x: [0.0; CHUNK],
            y: [0.0; CHUNK],
            range: [0.0; CHUNK],
            azimuth: [0.0; CHUNK],
            ring: [0; CHUNK],
        }
    }
}

impl ZoneChunk {
    /// Measures `points` (at most [`CHUNK`]; the slots after them hold the last chunk's
    /// values): the ring of a point is the first of `inner` whose outer edge lies beyond its
    /// range, or the last ring (`inner.len()`).
    fn measure(&mut self, points: &[Point], inner: &[ZoneRing]) {
        for (k, p) in points.iter().enumerate() {
            (self.x[k], self.y[k]) = (p.x, p.y);
        }
        for k in 0..CHUNK {
            let (x, y) = (self.x[k], self.y[k]);
            self.range[k] = (x * x + y * y).sqrt();
            self.azimuth[k] = fast_atan2_branchless(y, x);
        }
        self.ring = [0; CHUNK];
        let mut inside = [false; CHUNK];
        for ring in inner {
            let lanes = inside.iter_mut().zip(&self.range).zip(&mut self.ring);
            for ((inside, &range), index) in lanes {
                *inside |= range < ring.outer;
                *index += u32::from(!*inside);
            }
        }
    }
}

/// The azimuth sector of `azimuth` (from [`fast_atan2_branchless`]) among `sectors` equal sectors,
/// sector 0 starting at -π; `per_radian` is `sectors as f32 / 2π`.
#[inline]
fn sector_index(azimuth: f32, per_radian: f32, sectors: usize) -> usize {
    index_below((azimuth + std::f32::consts::PI) * per_radian, sectors)
}

/// `(v as usize).min(n - 1)` (n ≥ 1, at most 2³¹) through a cheaper `i32` conversion: both
/// truncate, and give 0 for NaN and negative `v`, and `n - 1` for `v` at or above 2³¹.
#[inline]
fn index_below(v: f32, n: usize) -> usize {
    ((v as i32).max(0) as usize).min(n - 1)
}

/// `a - b`.
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// A point's position in `f64`.
fn widen(p: &Point) -> [f64; 3] {
    [p.x as f64, p.y as f64, p.z as f64]
}

/// SplitMix64 (Steele et al. 2014): a tiny, fast, fully determined random stream.
struct SplitMix64(u64);

impl SplitMix64 {
    fn new(seed: u64) -> Self {
        Self(seed)
    }

    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// An index below `n` (n > 0).
    fn below(&mut self, n: usize) -> usize {
        (((self.next() >> 32) * n as u64) >> 32) as usize
    }

    /// Three distinct indices below `n` (n >= 3).
    fn three_distinct(&mut self, n: usize) -> (usize, usize, usize) {
        let a = self.below(n);
        let mut b = self.below(n - 1);
        if b >= a {
            b += 1;
        }
        let (lo, hi) = (a.min(b), a.max(b));
        let mut c = self.below(n - 2);
        if c >= lo {
            c += 1;
        }
        if c >= hi {
            c += 1;
        }
        (a, b, c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The (ring, step, x, y) of a ring-like scan's returns on the ground: 60 rings from 3 m
    /// out, spreading with range, 720 steps a ring.
    fn rings() -> impl Iterator<Item = (usize, usize, f32, f32)> {
        (0..60).flat_map(|ring| {
            let r = 3.0 + ring as f32 * ring as f32 * 0.013 + ring as f32 * 0.2;
            (0..720).map(move |step| {
                let a = step as f32 * std::f32::consts::TAU / 720.0;
                (ring, step, r * a.cos(), r * a.sin())
            })
        })
    }

    /// A ring-like scan of a ground `z = f(x, y)` plus a box-shaped obstacle from 0.3 m to
    /// 1.5 m above the ground at (12, 4) hiding the ground below it, as (points, is ground).
    fn scene(ground: impl Fn(f32, f32) -> f32) -> (Vec<Point>, Vec<bool>) {
        let mut points = Vec::new();
        let mut truth = Vec::new();
        for (ring, step, x, y) in rings() {
            if (10.8..13.3).contains(&x) && (2.8..4.8).contains(&y) {
                continue;
            }
            // A little deterministic noise, ±2 cm.
            let noise = ((step * 7 + ring * 13) % 9) as f32 * 0.005 - 0.02;
            points.push(Point::new(x, y, ground(x, y) + noise, 0.0));
            truth.push(true);
        }
        for i in 0..30 {
            for j in 0..25 {
                let (x, y) = (11.0 + i as f32 * 0.07, 3.0 + (j % 5) as f32 * 0.4);
                let z = ground(x, y) + 0.3 + (j / 5) as f32 * 0.3;
                points.push(Point::new(x, y, z, 0.0));
                truth.push(false);
            }
        }
        (points, truth)
    }

    fn check(points: &[Point], truth: &[bool]) {
        let mut removal = GroundRemoval::default();
        let mut ground = Vec::new();
        removal.segment(points, &mut ground);
        let wrong: Vec<usize> = (0..points.len())
            .filter(|&i| ground[i] != truth[i])
            .collect();
        assert!(
            wrong.is_empty(),
            "{} misclassified, e.g. {:?}",
            wrong.len(),
            &points[wrong[0]]
        );
        // Deterministic: the same scan gives the same answer.
        let mut again = Vec::new();
        removal.segment(points, &mut again);
        assert_eq!(ground, again);
    }

    #[test]
    fn flat_ground_goes_and_the_obstacle_stays() {
        let (points, truth) = scene(|_, _| -1.73);
        check(&points, &truth);
    }

    #[test]
    fn a_tilted_road_with_a_grade_change_is_followed_zone_by_zone() {
        // 3 % up along x, rolled 2 % along y, and 6 % more beyond x = 20 m.
        let (points, truth) =
            scene(|x, y| -1.73 + 0.03 * x + 0.02 * y + 0.06 * (x - 20.0).max(0.0));
        check(&points, &truth);
    }

    #[test]
    fn a_slope_is_not_carried_on_over_zones_without_ground() {
        // Flat road, but to the left a bank rises 8° from y = 11 m to y = 19 m onto a level
        // that returns nothing, with a car on it 35 m away: its body 0.6-1.5 m up.
        let bank = |y: f32| -1.73 + (y.clamp(11.0, 19.0) - 11.0) * 8f32.to_radians().tan();
        let mut points: Vec<Point> = rings()
            .filter(|&(_, _, _, y)| y < 19.0)
            .map(|(_, _, x, y)| Point::new(x, y, bank(y), 0.0))
            .collect();
        let car = points.len();
        for i in 0..40 {
            for j in 0..4 {
                let z = bank(19.0) + 0.6 + j as f32 * 0.3;
                points.push(Point::new(-2.0 + i as f32 * 0.1, 34.0, z, 0.0));
            }
        }
        let mut ground = Vec::new();
        GroundRemoval::default().segment(&points, &mut ground);
        let lost = ground[car..].iter().filter(|&&g| g).count();
        assert_eq!(lost, 0, "{lost} of the car's 160 points taken for ground");
        // The bank itself is ground where it is seen straight on.
        let bank_missed = (0..car)
            .filter(|&i| points[i].y > 12.0 && points[i].x.abs() < 3.0 && !ground[i])
            .count();
        assert_eq!(bank_missed, 0);
    }

    #[test]
    fn the_base_of_a_pole_stays_with_the_pole() {
        let (mut points, mut truth) = scene(|_, _| -1.73);
        // A pole 8 m ahead: a point every 5 cm from the ground up to 2 m.
        let base = points.len();
        for k in 0..40 {
            points.push(Point::new(8.0, 0.02, -1.73 + k as f32 * 0.05, 0.0));
            truth.push(false);
        }
        let mut ground = Vec::new();
        GroundRemoval::default().segment(&points, &mut ground);
        assert!(
            ground[base..].iter().all(|&g| !g),
            "the pole's foot was taken for ground"
        );
        let wrong = (0..base).filter(|&i| ground[i] != truth[i]).count();
        assert!(wrong <= 4, "{wrong} ground points lost around the pole");
        // Without the test the foot is ground.
        let config = GroundConfig {
            base_cell: 0.0,
            ..Default::default()
        };
        GroundRemoval::new(config).segment(&points, &mut ground);
        assert!(ground[base] && ground[base + 1] && !ground[base + 6]);
    }

    #[test]
    fn remove_keeps_the_other_points_in_order() {
        let (points, truth) = scene(|_, _| -1.73);
        let mut out = Vec::new();
        let near = GroundRemoval::default().remove(&points, &mut out);
        let expected: Vec<Point> = points
            .iter()
            .zip(&truth)
            .filter(|(_, g)| !**g)
            .map(|(p, _)| *p)
            .collect();
        assert!(
            out == expected,
            "{} kept, {} expected",
            out.len(),
            expected.len()
        );
        assert!((near.normal[2] - 1.0).abs() < 1e-3 && (near.offset - 1.73).abs() < 0.02);
    }

    #[test]
    fn hypothesis_scores_stop_early_only_when_they_cannot_win() {
        let mut rng = SplitMix64::new(7);
        let mut unit = || (rng.next() >> 11) as f64 / (1u64 << 53) as f64;
        let points: Vec<[f64; 3]> = (0..300)
            .map(|_| [unit() * 20.0, unit() * 20.0 - 10.0, unit() * 0.8 - 2.0])
            .collect();
        let mut sample = Sample::default();
        sample.fill(points.iter().copied());
        for _ in 0..200 {
            let normal = [unit() * 0.2 - 0.1, unit() * 0.2 - 0.1, 1.0];
            let plane = Plane::through([0.0, 0.0, -1.7 + unit() * 0.4], normal).unwrap();
            let (mut inliers, mut below) = (0usize, 0usize);
            for &p in &points {
                let h = plane.height(p);
                inliers += usize::from(h.abs() <= 0.2);
                below += usize::from(h < -0.4);
            }
            let score = inliers as i64 - 2 * below as i64;
            assert_eq!(sample.score(&plane, 0.2, None), Some((score, inliers)));
            for to_beat in [score - 1, score, score + 1, -1000, 300] {
                let expected = (score > to_beat).then_some((score, inliers));
                assert_eq!(sample.score(&plane, 0.2, Some(to_beat)), expected);
            }
        }
    }

    #[test]
    fn chunked_rings_are_the_first_ring_reaching_beyond_the_range() {
        let mut rng = SplitMix64::new(3);
        let mut unit = || (rng.next() >> 40) as f32 / (1u64 << 24) as f32;
        // Edges in order, out of order and repeated: the first that reaches beyond counts.
        for edges in [vec![6.0, 12.0, 20.0], vec![15.0, 5.0, 30.0, 5.0], vec![]] {
            let inner: Vec<ZoneRing> = edges
                .iter()
                .map(|&outer| ZoneRing { outer, sectors: 4 })
                .collect();
            let points: Vec<Point> = (0..150)
                .map(|_| Point::new(unit() * 80.0 - 40.0, unit() * 80.0 - 40.0, 0.0, 0.0))
                .collect();
            let mut chunk = ZoneChunk::default();
            for points in points.chunks(CHUNK) {
                chunk.measure(points, &inner);
                for (k, p) in points.iter().enumerate() {
                    let range = (p.x * p.x + p.y * p.y).sqrt();
                    let ring = inner
                        .iter()
                        .position(|r| range < r.outer)
                        .unwrap_or(inner.len());
                    assert_eq!(chunk.ring[k] as usize, ring, "{edges:?} {p:?}");
                    assert_eq!(chunk.range[k], range);
                    assert_eq!(chunk.azimuth[k], fast_atan2_branchless(p.y, p.x));
                }
            }
        }
    }

    #[test]
    fn index_below_equals_the_usize_cast() {
        for v in [
            -1e10f32, -3.0, -0.5, -0.0, 0.0, 0.7, 5.0, 6.99, 7.0, 1e9, 3e9, 1e30,
        ] {
            for n in [1usize, 7, 4096] {
                assert_eq!(index_below(v, n), (v as usize).min(n - 1), "{v} {n}");
            }
        }
        assert_eq!(index_below(f32::NAN, 5), 0);
        assert_eq!(index_below(f32::INFINITY, 5), 4);
    }

    #[test]
    fn ransac_iterations_follow_the_inlier_ratio() {
        assert_eq!(iterations_needed(1.0, 0.99, 100), 1);
        assert_eq!(iterations_needed(0.0, 0.99, 100), 100);
        // 0.5³ = 1/8: ln(0.01) / ln(7/8) = 34.5.
        assert_eq!(iterations_needed(0.5, 0.99, 100), 35);
        let mut rng = SplitMix64::new(1);
        for _ in 0..1000 {
            let (a, b, c) = rng.three_distinct(3);
            assert!(a != b && b != c && a != c && a < 3 && b < 3 && c < 3);
        }
    }
}
