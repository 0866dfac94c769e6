//! Comparing VFHs for tracking (the paper's Algorithm 1): the χ² distance between two
//! histograms, the CDF of a histogram ("volumetric integral") and the maximum deviation
//! between two CDFs (the MDT statistic, a Kolmogorov-Smirnov distance).

use super::{BINS, Vfh};

impl Vfh {
    /// The normalised cumulative sum of the 308 bins: `F[k] = Σ_{j ≤ k} h[j] / Σ h`, rising
    /// from `F[0]` to 1 (all zeros for an empty histogram).
    pub fn cdf(&self) -> [f32; BINS] {
        let total: f64 = self.bins.iter().map(|&b| b as f64).sum();
        let mut cdf = [0.0f32; BINS];
        if total <= 0.0 {
            return cdf;
        }
        let mut running = 0.0f64;
        for (slot, &b) in cdf.iter_mut().zip(&self.bins) {
            running += b as f64;
            *slot = (running / total) as f32;
        }
        cdf
    }
}

/// χ² distance between two histograms, each first scaled to unit mass:
/// `½ Σ (p - q)² / (p + q)` over the bins where `p + q > 0`. 0 for identical shapes, 1 for
/// histograms with no bin in common. An empty histogram is at distance 1 from anything.
pub fn chi_squared(a: &Vfh, b: &Vfh) -> f64 {
    let mass = |h: &Vfh| h.bins.iter().map(|&v| v as f64).sum::<f64>();
    let (ma, mb) = (mass(a), mass(b));
    if ma <= 0.0 || mb <= 0.0 {
        return 1.0;
    }
    let mut sum = 0.0;
    for (&x, &y) in a.bins.iter().zip(&b.bins) {
        let (p, q) = (x as f64 / ma, y as f64 / mb);
        if p + q > 0.0 {
            sum += (p - q) * (p - q) / (p + q);
        }
    }
    0.5 * sum
}

/// The largest absolute difference between two CDFs: `sup_k |F1[k] - F2[k]|`, in [0, 1].
pub fn max_deviation(a: &[f32; BINS], b: &[f32; BINS]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(&x, &y)| (x as f64 - y as f64).abs())
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn histogram(pairs: &[(usize, f32)]) -> Vfh {
        let mut bins = [0.0; BINS];
        for &(k, v) in pairs {
            bins[k] = v;
        }
        Vfh { bins }
    }

    #[test]
    fn cdf_rises_to_one() {
        let h = histogram(&[(0, 1.0), (10, 2.0), (307, 1.0)]);
        let cdf = h.cdf();
        assert_eq!(cdf[0], 0.25);
        assert_eq!(cdf[9], 0.25);
        assert_eq!(cdf[10], 0.75);
        assert_eq!(cdf[306], 0.75);
        assert_eq!(cdf[307], 1.0);
        assert!(cdf.windows(2).all(|w| w[0] <= w[1]));
        assert_eq!(Vfh { bins: [0.0; BINS] }.cdf(), [0.0; BINS]);
    }

    #[test]
    fn chi_squared_is_zero_for_the_same_shape_and_one_for_disjoint() {
        let a = histogram(&[(3, 10.0), (50, 30.0)]);
        let scaled = histogram(&[(3, 1.0), (50, 3.0)]);
        assert!(chi_squared(&a, &scaled).abs() < 1e-12);
        let b = histogram(&[(4, 10.0)]);
        assert!((chi_squared(&a, &b) - 1.0).abs() < 1e-12);
        let c = histogram(&[(3, 10.0), (51, 30.0)]);
        // Shares a quarter of its mass: ½ (0.75 + 0.75) = 0.75.
        assert!((chi_squared(&a, &c) - 0.75).abs() < 1e-12);
        assert_eq!(chi_squared(&a, &c), chi_squared(&c, &a));
    }

    #[test]
    fn max_deviation_is_the_largest_cdf_gap() {
        let a = histogram(&[(0, 1.0), (100, 1.0)]).cdf();
        let b = histogram(&[(50, 1.0), (100, 1.0)]).cdf();
        assert!((max_deviation(&a, &b) - 0.5).abs() < 1e-7);
        assert_eq!(max_deviation(&a, &a), 0.0);
    }
}
