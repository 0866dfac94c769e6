//! Measurement models: what each observation predicts from the nominal state, and how it
//! depends on the error state.

use nalgebra::{Matrix2, Matrix3, SMatrix, UnitQuaternion, Vector1, Vector2, Vector3};

use super::{
    ekf::Measurement,
    gps::{PositionFix, VelocityFix},
    state::{ATTITUDE, ERROR_STATE_DIM, NavState, POSITION, VELOCITY},
};

const N: usize = ERROR_STATE_DIM;

/// A GPS position: the IMU's world position, σ east/north and σ up.
pub(crate) fn position(state: &NavState, fix: &PositionFix) -> Measurement<3> {
    let mut jacobian = SMatrix::<f64, 3, N>::zeros();
    jacobian
        .fixed_view_mut::<3, 3>(0, POSITION)
        .fill_with_identity();
    Measurement {
        residual: fix.position - state.position,
        jacobian,
        noise: Matrix3::from_diagonal(&Vector3::new(
            fix.sigma.powi(2),
            fix.sigma.powi(2),
            fix.sigma_up.powi(2),
        )),
    }
}

/// A GPS velocity: the IMU's world velocity, per-axis σ.
pub(crate) fn velocity(state: &NavState, fix: &VelocityFix) -> Measurement<3> {
    let mut jacobian = SMatrix::<f64, 3, N>::zeros();
    jacobian
        .fixed_view_mut::<3, 3>(0, VELOCITY)
        .fill_with_identity();
    Measurement {
        residual: fix.velocity - state.velocity,
        jacobian,
        noise: Matrix3::identity() * fix.sigma.powi(2),
    }
}

/// The non-holonomic constraint: the velocity in the IMU frame has no left or up component
/// (a car rolls forward). Measured value zero, σ `sigma`.
///
/// With `v_b = Rᵀ v`, a true orientation `R·Exp(δθ)` and velocity `v + δv` give
/// `v_b + Rᵀ δv + [v_b]× δθ`.
pub(crate) fn nonholonomic(state: &NavState, sigma: f64) -> Measurement<2> {
    let r_t = state
        .orientation
        .to_rotation_matrix()
        .into_inner()
        .transpose();
    let v_body = r_t * state.velocity;
    let skew = v_body.cross_matrix();
    let mut jacobian = SMatrix::<f64, 2, N>::zeros();
    jacobian
        .fixed_view_mut::<2, 3>(0, VELOCITY)
        .copy_from(&r_t.fixed_rows::<2>(1));
    jacobian
        .fixed_view_mut::<2, 3>(0, ATTITUDE)
        .copy_from(&skew.fixed_rows::<2>(1));
    Measurement {
        residual: -Vector2::new(v_body.y, v_body.z),
        jacobian,
        noise: Matrix2::identity() * sigma.powi(2),
    }
}

/// The attitude error as a rotation vector in the world frame, `Log(measured · estimated⁻¹)`;
/// since `R·Exp(δθ) = Exp(R δθ)·R` its Jacobian is `R`. Its z component is exactly the yaw
/// error; x and y are the tilt (roll and pitch) errors turned by the heading.
fn world_attitude_error(
    state: &NavState,
    measured: &UnitQuaternion<f64>,
) -> (Vector3<f64>, Matrix3<f64>) {
    let error = (measured * state.orientation.inverse()).scaled_axis();
    (error, state.orientation.to_rotation_matrix().into_inner())
}

/// The packet's roll and pitch (the tilt of the IMU), σ `sigma` each.
pub(crate) fn roll_pitch(
    state: &NavState,
    measured: &UnitQuaternion<f64>,
    sigma: f64,
) -> Measurement<2> {
    let (error, rotation) = world_attitude_error(state, measured);
    let mut jacobian = SMatrix::<f64, 2, N>::zeros();
    jacobian
        .fixed_view_mut::<2, 3>(0, ATTITUDE)
        .copy_from(&rotation.fixed_rows::<2>(0));
    Measurement {
        residual: error.xy(),
        jacobian,
        noise: Matrix2::identity() * sigma.powi(2),
    }
}

/// The packet's yaw (heading), σ `sigma`.
pub(crate) fn yaw(state: &NavState, measured: &UnitQuaternion<f64>, sigma: f64) -> Measurement<1> {
    let (error, rotation) = world_attitude_error(state, measured);
    let mut jacobian = SMatrix::<f64, 1, N>::zeros();
    jacobian
        .fixed_view_mut::<1, 3>(0, ATTITUDE)
        .copy_from(&rotation.fixed_rows::<1>(2));
    Measurement {
        residual: Vector1::new(error.z),
        jacobian,
        noise: SMatrix::<f64, 1, 1>::new(sigma.powi(2)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::SVector;

    fn state() -> NavState {
        NavState {
            position: Vector3::new(1.0, 2.0, 3.0),
            velocity: Vector3::new(3.0, 4.0, 0.5),
            orientation: UnitQuaternion::from_euler_angles(0.05, -0.03, 0.9),
            accel_bias: Vector3::zeros(),
            gyro_bias: Vector3::zeros(),
        }
    }

    /// Checks a Jacobian against finite differences of `h` over the error state.
    fn check_jacobian<const M: usize>(
        h: impl Fn(&NavState) -> SVector<f64, M>,
        jacobian: &SMatrix<f64, M, N>,
    ) {
        let base = state();
        let eps = 1e-6;
        for j in 0..N {
            let mut dx = SVector::<f64, N>::zeros();
            dx[j] = eps;
            let mut moved = base;
            moved.inject(&dx);
            let column = (h(&moved) - h(&base)) / eps;
            for i in 0..M {
                assert!(
                    (column[i] - jacobian[(i, j)]).abs() < 1e-4,
                    "d h{i} / d x{j}: numeric {} analytic {}",
                    column[i],
                    jacobian[(i, j)]
                );
            }
        }
    }

    #[test]
    fn nonholonomic_jacobian_matches_finite_differences() {
        let m = nonholonomic(&state(), 0.1);
        // residual = 0 − h(x), so h(x) = −residual.
        check_jacobian(|s| -nonholonomic(s, 0.1).residual, &m.jacobian);
    }

    #[test]
    fn attitude_jacobians_match_finite_differences() {
        // The Jacobian is exact where the residual vanishes (the filter's operating point).
        let measured = state().orientation;
        // residual = Log(z · h⁻¹): moving the state by +δ moves the residual by −H δ.
        let rp = roll_pitch(&state(), &measured, 0.01);
        check_jacobian(|s| -roll_pitch(s, &measured, 0.01).residual, &rp.jacobian);
        let y = yaw(&state(), &measured, 0.01);
        check_jacobian(|s| -yaw(s, &measured, 0.01).residual, &y.jacobian);
    }

    #[test]
    fn yaw_residual_is_the_heading_difference() {
        let s = state();
        let (r, p, y) = s.orientation.euler_angles();
        let measured = UnitQuaternion::from_euler_angles(r, p, y + 0.1);
        assert!((yaw(&s, &measured, 0.01).residual[0] - 0.1).abs() < 1e-9);
        assert!(roll_pitch(&s, &measured, 0.01).residual.norm() < 1e-9);
    }
}
