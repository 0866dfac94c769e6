//! Randomness that stays deterministic when work is split across threads.
//!
//! Scenario layouts and OXTS noise draw from one seeded `ChaCha8Rng` in a fixed order. The
//! per-ray noise of a scan cannot (rays are cast in parallel), so it comes from [`RayRng`], a
//! small counter-based generator seeded by hashing the run seed with the ray's coordinates.

use rand::Rng;

/// SplitMix64's finaliser: a fast, well-mixed 64-bit hash.
pub fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Hashes several values into one seed.
pub fn hash_seed(parts: &[u64]) -> u64 {
    parts
        .iter()
        .fold(0x2545_F491_4F6C_DD1D, |h, &p| mix64(h ^ mix64(p)))
}

/// A SplitMix64 stream: cheap to seed, so one can be made per ray.
#[derive(Clone, Debug)]
pub struct RayRng {
    state: u64,
}

impl RayRng {
    /// A stream seeded by `seed`.
    pub fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        mix64(self.state)
    }

    /// A uniform value in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A standard normal value (Box–Muller).
    pub fn gauss(&mut self) -> f64 {
        box_muller(self.uniform(), self.uniform())
    }
}

/// A uniform value in [0, 1) from any generator.
pub fn uniform<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// A uniform value in [lo, hi) from any generator.
pub fn between<R: Rng + ?Sized>(rng: &mut R, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * uniform(rng)
}

/// A standard normal value from any generator (Box–Muller).
pub fn gauss<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    box_muller(uniform(rng), uniform(rng))
}

/// A uniform index in 0..n (n > 0).
pub fn pick<R: Rng + ?Sized>(rng: &mut R, n: usize) -> usize {
    ((uniform(rng) * n as f64) as usize).min(n.saturating_sub(1))
}

/// `true` with probability `p`.
pub fn chance<R: Rng + ?Sized>(rng: &mut R, p: f64) -> bool {
    uniform(rng) < p
}

/// One normal value from two uniforms in [0, 1).
fn box_muller(u1: f64, u2: f64) -> f64 {
    let r = (-2.0 * (1.0 - u1).ln()).sqrt();
    r * (std::f64::consts::TAU * u2).cos()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_has_unit_spread() {
        let mut rng = RayRng::new(7);
        let n = 20_000;
        let xs: Vec<f64> = (0..n).map(|_| rng.gauss()).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        assert!(mean.abs() < 0.03, "mean {mean}");
        assert!((var - 1.0).abs() < 0.05, "variance {var}");
    }

    #[test]
    fn hash_depends_on_every_part() {
        assert_ne!(hash_seed(&[1, 2, 3]), hash_seed(&[1, 2, 4]));
        assert_ne!(hash_seed(&[1, 2, 3]), hash_seed(&[2, 1, 3]));
        assert_eq!(hash_seed(&[1, 2, 3]), hash_seed(&[1, 2, 3]));
    }
}
