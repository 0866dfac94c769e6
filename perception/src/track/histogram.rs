//! Histogram comparisons used by the association (placeholder until the VFH stage lands).

/// χ² distance between two histograms, each normalised to unit sum: Σ (a−b)²/(a+b), in [0, 2].
pub fn chi2_distance(a: &[f32], b: &[f32]) -> f64 {
    let sa: f64 = a.iter().map(|&v| v as f64).sum::<f64>().max(1e-12);
    let sb: f64 = b.iter().map(|&v| v as f64).sum::<f64>().max(1e-12);
    a.iter()
        .zip(b)
        .map(|(&x, &y)| {
            let (x, y) = (x as f64 / sa, y as f64 / sb);
            if x + y > 0.0 {
                (x - y).powi(2) / (x + y)
            } else {
                0.0
            }
        })
        .sum()
}

/// Maximum absolute deviation between two CDFs.
pub fn max_cdf_deviation(a: &[f32], b: &[f32]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(&x, &y)| (x as f64 - y as f64).abs())
        .fold(0.0, f64::max)
}
