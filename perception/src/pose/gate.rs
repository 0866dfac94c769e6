//! The innovation gate: a measurement too far from the prediction, in the metric of their
//! combined uncertainty, is an outlier (a GPS jump), not information.

use nalgebra::{Cholesky, SMatrix, SVector};

/// The squared Mahalanobis distance (normalised innovation squared) of an innovation `y` with
/// covariance `s`, using the Cholesky factor of `s`; `None` when it is not finite.
pub(crate) fn normalised_innovation_squared<const M: usize>(
    y: &SVector<f64, M>,
    s_chol: &Cholesky<f64, nalgebra::Const<M>>,
) -> Option<f64> {
    let nis = y.dot(&s_chol.solve(y));
    nis.is_finite().then_some(nis)
}

/// Whether an innovation with this normalised squared distance passes a gate; a gate of
/// `f64::INFINITY` lets everything finite through.
pub(crate) fn passes(nis: f64, gate: f64) -> bool {
    nis <= gate
}

/// Innovation covariance `H P Hᵀ + R`, symmetrised against rounding.
pub(crate) fn innovation_covariance<const M: usize, const N: usize>(
    h: &SMatrix<f64, M, N>,
    p: &SMatrix<f64, N, N>,
    r: &SMatrix<f64, M, M>,
) -> SMatrix<f64, M, M> {
    let s = h * p * h.transpose() + r;
    (s + s.transpose()) * 0.5
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, Vector3};

    #[test]
    fn distance_is_in_units_of_sigma() {
        let s = Matrix3::from_diagonal(&Vector3::new(0.25, 0.25, 1.0));
        let chol = s.cholesky().unwrap();
        // 1 m east with σ = 0.5 m is 2 σ → 4.
        let nis = normalised_innovation_squared(&Vector3::new(1.0, 0.0, 0.0), &chol).unwrap();
        assert!((nis - 4.0).abs() < 1e-12);
        assert!(passes(nis, 16.27));
        // an 8 m jump is 16 σ.
        let nis = normalised_innovation_squared(&Vector3::new(8.0, 0.0, 0.0), &chol).unwrap();
        assert!(!passes(nis, 16.27));
    }

    #[test]
    fn nan_never_passes() {
        assert!(!passes(f64::NAN, f64::INFINITY));
    }
}
