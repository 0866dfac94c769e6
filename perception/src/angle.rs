//! A fast arctangent for the per-point loops (ground removal's sectors, the range image's
//! cells): libm's `atan2` costs more than the rest of their work per point together.

/// `y.atan2(x)` to within 1e-5 rad: an odd polynomial of the arctangent on [0, 1] and the
/// octant symmetries; 0 for (0, 0). Selects only, no branches: a loop over arrays of points
/// runs it on whole SIMD registers.
#[inline]
pub(crate) fn fast_atan2_branchless(y: f32, x: f32) -> f32 {
    use std::f32::consts::{FRAC_PI_2, PI};
    let (ax, ay) = (x.abs(), y.abs());
    let (low, high) = (ax.min(ay), ax.max(ay));
    let mut a = atan_unit(if high > 0.0 { low / high } else { 0.0 });
    a = if ay > ax { FRAC_PI_2 - a } else { a };
    a = if x < 0.0 { PI - a } else { a };
    if y < 0.0 { -a } else { a }
}

/// `atan(t)` for `t` in [0, 1]: a least-squares odd polynomial (error below 7e-6 rad).
#[inline]
fn atan_unit(t: f32) -> f32 {
    let t2 = t * t;
    t * (0.999_968
        + t2 * (-0.332_549_57
            + t2 * (0.193_520_28
                + t2 * (-0.117_020_03 + t2 * (0.053_742_84 - t2 * 0.012_269_506)))))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn is_close_to_libm() {
        for i in 0..10_000 {
            let a = (i as f32 / 10_000.0 - 0.5) * std::f32::consts::TAU;
            for r in [0.1f32, 7.0, 80.0] {
                let (y, x) = (r * a.sin(), r * a.cos());
                assert!(
                    (fast_atan2_branchless(y, x) - y.atan2(x)).abs() < 2e-5,
                    "{x} {y}"
                );
            }
        }
        assert_eq!(fast_atan2_branchless(0.0, 0.0), 0.0);
        assert_eq!(fast_atan2_branchless(-0.0, -0.0), 0.0);
    }
}
