//! The ground: a plane with an optional grade and gentle undulations, and where rays meet it.

use nalgebra::{Vector2, Vector3};
use rand::Rng;
use serde::{Deserialize, Serialize};

use crate::random::between;

/// Most undulations a terrain has.
pub const MAX_WAVES: usize = 4;

/// Which kind of ground a drive runs on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TerrainKind {
    /// Level ground at z = 0.
    Flat,
    /// A plane with a grade of 3–6 % (the road climbs; the vehicle tilts with it).
    Tilted,
    /// A grade plus hills (wavelengths of 60–200 m, slopes changing by a few per cent) and
    /// small bumps: the sensor sees the road ahead at another slope than its own.
    Undulating,
}

/// One sinusoidal undulation of the ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wave {
    /// Wave vector (radians per metre, pointing along the wave's travel).
    pub k: Vector2<f64>,
    /// Amplitude in metres.
    pub amplitude: f64,
    /// Phase in radians.
    pub phase: f64,
}

/// The ground height field z = base + grade · (x, y) + Σ waves.
#[derive(Clone, Debug, PartialEq)]
pub struct Terrain {
    /// Height at the world origin (metres).
    pub base: f64,
    /// Slope of the plane: dz/dx, dz/dy.
    pub grade: Vector2<f64>,
    /// Undulations added to the plane.
    pub waves: Vec<Wave>,
    /// Sum of the wave amplitudes: the most the ground departs from the plane.
    bound: f64,
}

impl Terrain {
    /// Level ground at z = 0.
    pub fn flat() -> Self {
        Self::new(0.0, Vector2::zeros(), Vec::new())
    }

    /// Ground of the given plane and undulations (at most [`MAX_WAVES`]; more are dropped).
    pub fn new(base: f64, grade: Vector2<f64>, mut waves: Vec<Wave>) -> Self {
        waves.truncate(MAX_WAVES);
        let bound = waves.iter().map(|w| w.amplitude.abs()).sum();
        Self {
            base,
            grade,
            waves,
            bound,
        }
    }

    /// A random ground of the given kind.
    pub fn random<R: Rng + ?Sized>(kind: TerrainKind, rng: &mut R) -> Self {
        match kind {
            TerrainKind::Flat => Self::flat(),
            TerrainKind::Tilted => Self::new(0.0, random_grade(rng, 0.03, 0.06), Vec::new()),
            TerrainKind::Undulating => {
                let mut waves = Vec::new();
                for (lambda, amp) in [((60.0, 120.0), (0.3, 0.8)), ((120.0, 200.0), (0.6, 1.2))] {
                    waves.push(random_wave(rng, lambda, amp));
                }
                waves.push(random_wave(rng, (12.0, 25.0), (0.02, 0.05)));
                Self::new(0.0, random_grade(rng, 0.01, 0.03), waves)
            }
        }
    }

    /// Ground height at a horizontal position.
    pub fn height(&self, p: Vector2<f64>) -> f64 {
        let waves: f64 = self
            .waves
            .iter()
            .map(|w| w.amplitude * sin(w.k.dot(&p) + w.phase))
            .sum();
        self.base + self.grade.dot(&p) + waves
    }

    /// Gradient of the height (dz/dx, dz/dy) at a horizontal position.
    pub fn gradient(&self, p: Vector2<f64>) -> Vector2<f64> {
        self.waves.iter().fold(self.grade, |g, w| {
            g + w.k * (w.amplitude * cos(w.k.dot(&p) + w.phase))
        })
    }

    /// Upward unit normal of the ground at a horizontal position.
    pub fn normal(&self, p: Vector2<f64>) -> Vector3<f64> {
        let g = self.gradient(p);
        Vector3::new(-g.x, -g.y, 1.0).normalize()
    }

    /// The first `t` in (0, `t_max`] where the ray `origin + t·dir` (unit `dir`) meets the
    /// ground, if the origin is above it.
    pub fn intersect(&self, origin: &Vector3<f64>, dir: &Vector3<f64>, t_max: f64) -> Option<f64> {
        // Height over the plane at t = 0 and its rate along the ray.
        let c = origin.z - self.base - self.grade.dot(&origin.xy());
        let s = dir.z - self.grade.dot(&dir.xy());
        if self.bound == 0.0 {
            let t = -c / s;
            return (s < 0.0 && t > 0.0 && t <= t_max).then_some(t);
        }
        // The ray is inside the waves' band (plane ± bound) between t_lo and t_hi.
        let t_lo = if c > self.bound {
            if s >= 0.0 {
                return None;
            }
            (c - self.bound) / -s
        } else {
            0.0
        };
        let t_hi = if s < 0.0 {
            (c + self.bound) / -s
        } else if s > 0.0 {
            (self.bound - c) / s
        } else {
            f64::INFINITY
        };
        let t_end = t_hi.min(t_max);
        if t_lo >= t_end {
            return None;
        }
        let ray = RayWaves::new(self, origin, dir, c, s);
        // March with steps the clearance cannot close (it falls at most `rate` per metre),
        // then refine the bracket.
        let mut t = t_lo;
        let mut f = ray.clearance(t);
        if f <= 0.0 {
            return None;
        }
        while t < t_end {
            let next = (t + (f / ray.rate).max(0.5)).min(t_end);
            let f_next = ray.clearance(next);
            if f_next <= 0.0 {
                return Some(ray.refine(t, f, next, f_next));
            }
            (t, f) = (next, f_next);
        }
        None
    }
}

/// The ground's clearance along one ray: c + s·t − Σ Aᵢ sin(αᵢ + βᵢ·t).
struct RayWaves {
    c: f64,
    s: f64,
    /// (amplitude, phase at t = 0, phase rate along the ray) per wave; `count` are used.
    waves: [(f64, f64, f64); MAX_WAVES],
    count: usize,
    /// Largest rate at which the clearance can fall (per metre along the ray).
    rate: f64,
}

impl RayWaves {
    fn new(terrain: &Terrain, origin: &Vector3<f64>, dir: &Vector3<f64>, c: f64, s: f64) -> Self {
        let mut waves = [(0.0, 0.0, 0.0); MAX_WAVES];
        for (slot, w) in waves.iter_mut().zip(&terrain.waves) {
            *slot = (
                w.amplitude,
                w.k.dot(&origin.xy()) + w.phase,
                w.k.dot(&dir.xy()),
            );
        }
        let rate = s.abs() + waves.iter().map(|(a, _, b)| (a * b).abs()).sum::<f64>() + 1e-9;
        Self {
            c,
            s,
            waves,
            count: terrain.waves.len(),
            rate,
        }
    }

    fn clearance(&self, t: f64) -> f64 {
        self.c + self.s * t
            - self.waves[..self.count]
                .iter()
                .map(|(a, p, b)| a * sin(p + b * t))
                .sum::<f64>()
    }

    /// A root in [lo, hi] (clearance `f_lo` > 0 ≥ `f_hi`) by regula falsi (Illinois).
    fn refine(&self, mut lo: f64, mut f_lo: f64, mut hi: f64, mut f_hi: f64) -> f64 {
        let mut side = 0;
        for _ in 0..30 {
            let t = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
            let f = self.clearance(t);
            if f.abs() < 1e-4 || hi - lo < 1e-4 {
                return t;
            }
            if f > 0.0 {
                (lo, f_lo) = (t, f);
                if side == 1 {
                    f_hi /= 2.0;
                }
                side = 1;
            } else {
                (hi, f_hi) = (t, f);
                if side == -1 {
                    f_lo /= 2.0;
                }
                side = -1;
            }
        }
        0.5 * (lo + hi)
    }
}

/// sin(x) to about 1e-9, a few times faster than the C library's (the ground is evaluated
/// millions of times per scan). Heights and ray hits both use it, so they agree exactly.
fn sin(x: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};
    // Reduce to [-π, π], then to [-π/2, π/2] by sin(π − x) = sin(x).
    // Round to the nearest turn with a cast (inlined, unlike `f64::round`).
    let turns = x * (1.0 / TAU);
    let mut r = x - TAU * ((turns + 0.5f64.copysign(turns)) as i64 as f64);
    if r > FRAC_PI_2 {
        r = PI - r;
    } else if r < -FRAC_PI_2 {
        r = -PI - r;
    }
    let r2 = r * r;
    // Taylor series to x¹⁵: error below 1e-9 on [-π/2, π/2].
    let mut p = -1.0 / 1_307_674_368_000.0;
    for c in [
        1.0 / 6_227_020_800.0,
        -1.0 / 39_916_800.0,
        1.0 / 362_880.0,
        -1.0 / 5040.0,
        1.0 / 120.0,
        -1.0 / 6.0,
        1.0,
    ] {
        p = p * r2 + c;
    }
    p * r
}

/// cos(x) through [`sin`].
fn cos(x: f64) -> f64 {
    sin(x + std::f64::consts::FRAC_PI_2)
}

/// A plane grade of random direction and a magnitude in [lo, hi).
fn random_grade<R: Rng + ?Sized>(rng: &mut R, lo: f64, hi: f64) -> Vector2<f64> {
    let a = between(rng, -std::f64::consts::PI, std::f64::consts::PI);
    Vector2::new(a.cos(), a.sin()) * between(rng, lo, hi)
}

/// A wave of random direction, wavelength and amplitude in the given ranges.
fn random_wave<R: Rng + ?Sized>(rng: &mut R, lambda: (f64, f64), amp: (f64, f64)) -> Wave {
    let a = between(rng, -std::f64::consts::PI, std::f64::consts::PI);
    let k = std::f64::consts::TAU / between(rng, lambda.0, lambda.1);
    Wave {
        k: Vector2::new(a.cos(), a.sin()) * k,
        amplitude: between(rng, amp.0, amp.1),
        phase: between(rng, 0.0, std::f64::consts::TAU),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn flat_ground_is_hit_where_geometry_says() {
        let g = Terrain::flat();
        let o = Vector3::new(0.0, 0.0, 1.73);
        let el = -10f64.to_radians();
        let dir = Vector3::new(el.cos(), 0.0, el.sin());
        let t = g.intersect(&o, &dir, 120.0).unwrap();
        assert!((t - 1.73 / -el.sin()).abs() < 1e-9);
        assert!(g.intersect(&o, &Vector3::x(), 120.0).is_none());
        assert!(g.intersect(&o, &dir, 5.0).is_none());
    }

    #[test]
    fn hits_on_undulating_ground_lie_on_it_and_nothing_is_crossed_before() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let g = Terrain::random(TerrainKind::Undulating, &mut rng);
        let o = Vector3::new(10.0, -4.0, g.height(Vector2::new(10.0, -4.0)) + 1.73);
        let mut hits = 0;
        for i in 0..400 {
            let az = i as f64 * 0.157;
            let el = -(0.5 + (i % 40) as f64 * 0.6).to_radians();
            let dir = Vector3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin());
            if let Some(t) = g.intersect(&o, &dir, 120.0) {
                hits += 1;
                let p = o + dir * t;
                assert!((p.z - g.height(p.xy())).abs() < 1e-3);
                // Dense check that the ray stayed above the ground before the hit.
                let mut u = 0.0;
                while u < t - 0.05 {
                    let q = o + dir * u;
                    assert!(q.z > g.height(q.xy()) - 1e-6, "crossed at {u} before {t}");
                    u += 0.05;
                }
            }
        }
        assert!(hits > 300, "{hits}");
    }

    #[test]
    fn fast_sine_matches_the_library() {
        for i in -2000..2000 {
            let x = i as f64 * 0.0173 + 0.001;
            assert!((sin(x) - x.sin()).abs() < 1e-9, "{x}");
            assert!((cos(x) - x.cos()).abs() < 1e-9, "{x}");
        }
        assert!((sin(1.0e4) - 1.0e4f64.sin()).abs() < 1e-9);
    }

    #[test]
    fn normal_is_perpendicular_to_the_slope() {
        let g = Terrain::new(0.0, Vector2::new(0.05, 0.0), Vec::new());
        let n = g.normal(Vector2::zeros());
        assert!(n.dot(&Vector3::new(1.0, 0.0, 0.05)).abs() < 1e-12);
        assert!(n.z > 0.0);
    }
}
