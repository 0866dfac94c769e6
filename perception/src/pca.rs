//! Principal axes of small point sets: the covariance of a few points and the eigenvector of
//! its smallest eigenvalue, i.e. the normal of the best-fitting plane in the least-squares
//! (orthogonal distance) sense. Closed-form (Smith's trigonometric eigenvalues, eigenvector
//! from cross products of rows, as PCL's `eigen33` does), so it costs tens of nanoseconds.

/// Mean and covariance of a set of points, accumulated in `f64` around a shift (the first
/// point) so that far-from-origin coordinates lose no precision.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Moments {
    shift: [f64; 3],
    count: usize,
    sum: [f64; 3],
    /// xx, xy, xz, yy, yz, zz.
    products: [f64; 6],
}

impl Moments {
    /// Adds one point.
    #[inline]
    pub(crate) fn add(&mut self, p: [f64; 3]) {
        if self.count == 0 {
            self.shift = p;
        }
        let d = [
            p[0] - self.shift[0],
            p[1] - self.shift[1],
            p[2] - self.shift[2],
        ];
        self.count += 1;
        for (sum, v) in self.sum.iter_mut().zip(d) {
            *sum += v;
        }
        self.products[0] += d[0] * d[0];
        self.products[1] += d[0] * d[1];
        self.products[2] += d[0] * d[2];
        self.products[3] += d[1] * d[1];
        self.products[4] += d[1] * d[2];
        self.products[5] += d[2] * d[2];
    }

    /// Number of points added.
    pub(crate) fn count(&self) -> usize {
        self.count
    }

    /// The mean of the points (the origin when there are none).
    pub(crate) fn mean(&self) -> [f64; 3] {
        if self.count == 0 {
            return [0.0; 3];
        }
        let n = self.count as f64;
        [0, 1, 2].map(|axis| self.shift[axis] + self.sum[axis] / n)
    }

    /// The covariance matrix (divided by the number of points).
    pub(crate) fn covariance(&self) -> [[f64; 3]; 3] {
        if self.count == 0 {
            return [[0.0; 3]; 3];
        }
        let n = self.count as f64;
        let m = [self.sum[0] / n, self.sum[1] / n, self.sum[2] / n];
        let c = |k: usize, a: usize, b: usize| self.products[k] / n - m[a] * m[b];
        let (xx, xy, xz, yy, yz, zz) = (
            c(0, 0, 0),
            c(1, 0, 1),
            c(2, 0, 2),
            c(3, 1, 1),
            c(4, 1, 2),
            c(5, 2, 2),
        );
        [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]
    }
}

/// The unit eigenvector of the smallest eigenvalue of a symmetric 3×3 matrix, and that
/// eigenvalue. A matrix with a repeated smallest eigenvalue (points on a line, or a single
/// point) gets some unit vector of that eigenspace, chosen deterministically.
pub(crate) fn smallest_eigenvector(m: [[f64; 3]; 3]) -> (f64, [f64; 3]) {
    let scale = m.iter().flatten().fold(0.0f64, |s, v| s.max(v.abs()));
    if scale == 0.0 || !scale.is_finite() {
        return (0.0, [0.0, 0.0, 1.0]);
    }
    let a = m.map(|row| row.map(|v| v / scale));
    let spectrum = Spectrum::of(a);
    let smallest = spectrum.smallest();
    let vector = eigenvector(a, smallest).unwrap_or_else(|| {
        // Two (or three) eigenvalues equal the smallest: any unit vector orthogonal to the
        // largest eigenvalue's eigenvector will do.
        let axis = eigenvector(a, spectrum.largest()).unwrap_or([0.0, 0.0, 1.0]);
        let helper = if axis[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        normalized(cross(axis, helper)).unwrap_or([0.0, 0.0, 1.0])
    });
    (smallest * scale, vector)
}

/// The eigenvalues of a symmetric 3×3 matrix in Smith's (1961) trigonometric form
/// `q + 2p·cos(φ + 2πj/3)`, each evaluated only when asked for.
#[derive(Clone, Copy, Debug)]
enum Spectrum {
    /// All three eigenvalues equal this.
    Repeated(f64),
    /// `q`, `p` and `φ` of Smith's form.
    Trigonometric { q: f64, p: f64, phi: f64 },
}

impl Spectrum {
    /// The spectrum of `a` (symmetric, entries of order 1).
    fn of(a: [[f64; 3]; 3]) -> Self {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        let q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
        let diag = [a[0][0] - q, a[1][1] - q, a[2][2] - q];
        let p2 = diag[0] * diag[0] + diag[1] * diag[1] + diag[2] * diag[2] + 2.0 * off;
        if p2 <= 0.0 {
            return Self::Repeated(q);
        }
        let p = (p2 / 6.0).sqrt();
        let b = |i: usize, j: usize| (a[i][j] - if i == j { q } else { 0.0 }) / p;
        let det = b(0, 0) * (b(1, 1) * b(2, 2) - b(1, 2) * b(2, 1))
            - b(0, 1) * (b(1, 0) * b(2, 2) - b(1, 2) * b(2, 0))
            + b(0, 2) * (b(1, 0) * b(2, 1) - b(1, 1) * b(2, 0));
        let phi = (det / 2.0).clamp(-1.0, 1.0).acos() / 3.0;
        Self::Trigonometric { q, p, phi }
    }

    /// The smallest eigenvalue.
    fn smallest(self) -> f64 {
        match self {
            Self::Repeated(q) => q,
            Self::Trigonometric { q, p, phi } => {
                q + 2.0 * p * (phi + 2.0 * std::f64::consts::FRAC_PI_3).cos()
            }
        }
    }

    /// The largest eigenvalue.
    fn largest(self) -> f64 {
        match self {
            Self::Repeated(q) => q,
            Self::Trigonometric { q, p, phi } => q + 2.0 * p * phi.cos(),
        }
    }
}

/// The unit eigenvector for a simple eigenvalue: the longest cross product of two rows of
/// `a - λI`. `None` when all are (numerically) zero, i.e. λ is repeated.
fn eigenvector(a: [[f64; 3]; 3], lambda: f64) -> Option<[f64; 3]> {
    let mut r = a;
    for (i, row) in r.iter_mut().enumerate() {
        row[i] -= lambda;
    }
    let candidates = [cross(r[0], r[1]), cross(r[0], r[2]), cross(r[1], r[2])];
    let best = candidates
        .into_iter()
        .max_by(|u, v| dot(*u, *u).total_cmp(&dot(*v, *v)))?;
    if dot(best, best) <= 1e-20 {
        return None;
    }
    normalized(best)
}

/// Cross product.
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Dot product.
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `v / |v|`, or `None` for a zero or non-finite vector.
pub(crate) fn normalized(v: [f64; 3]) -> Option<[f64; 3]> {
    let norm = dot(v, v).sqrt();
    (norm > 0.0 && norm.is_finite()).then(|| v.map(|c| c / norm))
}

#[cfg(test)]
mod tests {
    use nalgebra::{Matrix3, SymmetricEigen};

    use super::*;

    fn check_against_nalgebra(m: [[f64; 3]; 3]) {
        let (value, vector) = smallest_eigenvector(m);
        let eigen = SymmetricEigen::new(Matrix3::from_fn(|i, j| m[i][j]));
        let k = eigen.eigenvalues.imin();
        let expected = eigen.eigenvalues[k];
        let scale = m.iter().flatten().fold(1e-300f64, |s, v| s.max(v.abs()));
        assert!(
            (value - expected).abs() <= 1e-9 * scale,
            "{value} vs {expected}"
        );
        // A·v = λ·v and |v| = 1.
        let mv = [0, 1, 2].map(|i| dot(m[i], vector));
        for i in 0..3 {
            assert!(
                (mv[i] - value * vector[i]).abs() <= 1e-7 * scale,
                "{m:?}: {mv:?} vs {vector:?}"
            );
        }
        assert!((dot(vector, vector) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn matches_nalgebra_on_covariances() {
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for _ in 0..2000 {
            let mut moments = Moments::default();
            let flatness = next().abs() * 0.1;
            for _ in 0..10 {
                moments.add([
                    next() * 3.0 + 40.0,
                    next() * 2.0 - 7.0,
                    next() * flatness + 1.0,
                ]);
            }
            check_against_nalgebra(moments.covariance());
        }
    }

    #[test]
    fn plane_normal_of_a_tilted_plane() {
        let mut moments = Moments::default();
        for i in 0..10 {
            for j in 0..10 {
                let (x, y) = (i as f64, j as f64);
                moments.add([x, y, 0.05 * x - 0.02 * y + 3.0]);
            }
        }
        let (value, n) = smallest_eigenvector(moments.covariance());
        assert!(value.abs() < 1e-9);
        let expected = normalized([-0.05, 0.02, 1.0]).unwrap();
        assert!((dot(n, expected).abs() - 1.0).abs() < 1e-12);
        let mean = moments.mean();
        assert!(
            (mean[0] - 4.5).abs() < 1e-12
                && (mean[2] - (0.05 * 4.5 - 0.02 * 4.5 + 3.0)).abs() < 1e-12
        );
    }

    #[test]
    fn degenerate_sets_still_give_a_unit_vector() {
        // Points on a line along x: any normal orthogonal to x is right.
        let mut line = Moments::default();
        for i in 0..5 {
            line.add([i as f64, 0.0, 0.0]);
        }
        let (_, n) = smallest_eigenvector(line.covariance());
        assert!(n[0].abs() < 1e-12 && (dot(n, n) - 1.0).abs() < 1e-12);
        // One point, or nothing.
        let mut one = Moments::default();
        one.add([1.0, 2.0, 3.0]);
        assert_eq!(
            smallest_eigenvector(one.covariance()),
            (0.0, [0.0, 0.0, 1.0])
        );
        assert_eq!(Moments::default().count(), 0);
    }
}
