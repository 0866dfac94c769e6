//! Principal axes of small point sets: the covariance of a few points and the eigenvector of
//! its smallest eigenvalue, i.e. the normal of the best-fitting plane in the least-squares
//! (orthogonal distance) sense. The eigenvalues are the roots of the characteristic cubic,
//! found by Halley's method from a closed-form start (no trigonometric calls); the eigenvector
//! comes from cross products of rows, as PCL's `eigen33` computes it. Tens of nanoseconds.

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
    let inverse = 1.0 / scale;
    let a = m.map(|row| row.map(|v| v * inverse));
    let roots = eigenvalue_roots(a);
    let smallest = roots.smallest();
    let vector = eigenvector(a, smallest).unwrap_or_else(|| {
        // Two (or three) eigenvalues equal the smallest: any unit vector orthogonal to the
        // largest eigenvalue's eigenvector will do.
        let axis = eigenvector(a, roots.largest()).unwrap_or([0.0, 0.0, 1.0]);
        let helper = if axis[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        normalized(cross(axis, helper)).unwrap_or([0.0, 0.0, 1.0])
    });
    (smallest * scale, vector)
}

/// `2/√3`: the slope of the smallest root of `x³ - 3x = r` against `sqrt((2 - r) / 4)` at
/// the double root `r = 2`.
const ROOT_SLOPE: f64 = 1.154_700_538_379_251_5;

/// The eigenvalues of a symmetric 3×3 matrix (see [`eigenvalue_roots`]): the smallest, and
/// what the largest follows from.
#[derive(Clone, Copy)]
struct Roots {
    smallest: f64,
    /// `q + p·y` is the largest for the largest root `y`; `p` is `None` for a multiple of
    /// the identity, whose eigenvalues all equal `q`.
    q: f64,
    p: Option<f64>,
    /// The smallest root of `x³ - 3x = r`.
    x: f64,
}

impl Roots {
    /// The smallest eigenvalue.
    fn smallest(self) -> f64 {
        self.smallest
    }

    /// The largest eigenvalue: the other two roots solve `y² + x·y + x² - 3 = 0`.
    fn largest(self) -> f64 {
        let Some(p) = self.p else {
            return self.q;
        };
        let x = self.x;
        let largest = -0.5 * x + (3.0 - 0.75 * x * x).max(0.0).sqrt();
        self.q + p * largest
    }
}

/// The eigenvalues of a symmetric 3×3 matrix `a` (entries of order 1). With `q` the mean
/// eigenvalue and `p² = tr((a - qI)²) / 6`, the eigenvalues are `q + p·x` for the three roots
/// `x` of `x³ - 3x = r`, `r = det((a - qI) / p)` in [-2, 2] (Smith 1961). The smallest root
/// lies in [-2, -1]: `-1 - δ` with `δ ≈ (2/√3)·s - (2/√3 - 1)·s²`, `s = sqrt((2 - r) / 4)`,
/// which is exact at both ends and within 1 % between; two Halley steps (cubic convergence)
/// take it to rounding level. The largest root follows from it only when asked for.
fn eigenvalue_roots(a: [[f64; 3]; 3]) -> Roots {
    let q = (a[0][0] + a[1][1] + a[2][2]) * (1.0 / 3.0);
    let d = [a[0][0] - q, a[1][1] - q, a[2][2] - q];
    let (xy, xz, yz) = (a[0][1], a[0][2], a[1][2]);
    let p2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 2.0 * (xy * xy + xz * xz + yz * yz);
    if p2 <= 0.0 {
        // A multiple of the identity: every eigenvalue is q.
        return Roots {
            smallest: q,
            q,
            p: None,
            x: 0.0,
        };
    }
    let p = (p2 * (1.0 / 6.0)).sqrt();
    let det =
        d[0] * (d[1] * d[2] - yz * yz) - xy * (xy * d[2] - yz * xz) + xz * (xy * yz - d[1] * xz);
    let r = (det / (p * p * p)).clamp(-2.0, 2.0);
    let s = ((2.0 - r) * 0.25).sqrt();
    let mut x = -1.0 - s * (ROOT_SLOPE - (ROOT_SLOPE - 1.0) * s);
    for _ in 0..2 {
        let g = x * x * x - 3.0 * x - r;
        let slope = 3.0 * x * x - 3.0;
        let denominator = 2.0 * slope * slope - 6.0 * g * x;
        if denominator != 0.0 {
            x -= 2.0 * g * slope / denominator;
        }
    }
    Roots {
        smallest: q + p * x,
        q,
        p: Some(p),
        x,
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
    let lengths2 = candidates.map(|c| dot(c, c));
    // The last of the longest, as `Iterator::max_by` picks it.
    let mut best = 0;
    for i in 1..3 {
        if lengths2[best].total_cmp(&lengths2[i]).is_le() {
            best = i;
        }
    }
    if lengths2[best] <= 1e-20 {
        return None;
    }
    // `normalized`, with the squared length already at hand.
    let norm = lengths2[best].sqrt();
    (norm > 0.0 && norm.is_finite()).then(|| candidates[best].map(|c| c / norm))
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

    /// `value_tolerance`: relative error allowed on the eigenvalue.
    fn check_against_nalgebra(m: [[f64; 3]; 3], value_tolerance: f64) {
        let (value, vector) = smallest_eigenvector(m);
        let eigen = SymmetricEigen::new(Matrix3::from_fn(|i, j| m[i][j]));
        let k = eigen.eigenvalues.imin();
        let expected = eigen.eigenvalues[k];
        let scale = m.iter().flatten().fold(1e-300f64, |s, v| s.max(v.abs()));
        assert!(
            (value - expected).abs() <= value_tolerance * scale,
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
            check_against_nalgebra(moments.covariance(), 1e-9);
        }
    }

    #[test]
    fn matches_nalgebra_near_repeated_eigenvalues() {
        // Rotated diagonals with two eigenvalues close or equal: both ends of the root's
        // range, r = 2 (smallest repeated) and r = -2 (largest repeated). At a double root
        // the cubic's coefficients fix the root to half the digits only (sqrt of the
        // rounding error), with any solver (the trigonometric form included).
        let (c, s) = (0.6f64, 0.8f64);
        let rotate = |diag: [f64; 3]| {
            let r = [
                [c, -s, 0.0],
                [s * 0.6, c * 0.6, 0.8],
                [-s * 0.8, -c * 0.8, 0.6],
            ];
            let mut m = [[0.0; 3]; 3];
            for (i, row) in m.iter_mut().enumerate() {
                for (j, v) in row.iter_mut().enumerate() {
                    *v = (0..3).map(|k| r[i][k] * diag[k] * r[j][k]).sum();
                }
            }
            m
        };
        for gap in [0.0, 1e-12, 1e-8, 1e-4, 0.1, 0.5] {
            check_against_nalgebra(rotate([gap, 1.0, 1.0]), 1e-12);
            check_against_nalgebra(rotate([0.0, gap, 1.0]), 1e-7);
            check_against_nalgebra(rotate([2.0, 2.0 + gap, 7.0]), 1e-7);
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
