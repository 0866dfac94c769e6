//! The error-state EKF: IMU-driven prediction and generic gated corrections.
//!
//! The nominal state ([`NavState`]) is integrated with the IMU; the filter tracks the
//! covariance of a 15-dimensional error state (see [`super::state`]) around it, linearised
//! each step, and folds each accepted correction back into the nominal state. Keeping the
//! attitude error a small 3-vector avoids the quaternion-covariance singularity and keeps the
//! linearisation accurate even over long dropouts.

use nalgebra::{Matrix3, SMatrix, SVector, UnitQuaternion, Vector3};

use super::{
    config::PoseConfig,
    gate,
    imu::ImuSample,
    state::{
        ACCEL_BIAS, ATTITUDE, Covariance, ERROR_STATE_DIM, GYRO_BIAS, NavState, POSITION, VELOCITY,
    },
    turn,
};

const N: usize = ERROR_STATE_DIM;

/// A linearised measurement of dimension `M`: residual `z − h(x)`, Jacobian `H` of `h` with
/// respect to the error state, and noise covariance `R`.
pub(crate) struct Measurement<const M: usize> {
    pub residual: SVector<f64, M>,
    pub jacobian: SMatrix<f64, M, N>,
    pub noise: SMatrix<f64, M, M>,
}

/// What a correction did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Correction {
    /// Folded into the state; the normalised innovation squared.
    Applied(f64),
    /// Outside the gate; the state is unchanged.
    Rejected(f64),
    /// The innovation covariance was not positive definite or the innovation not finite.
    Degenerate,
}

/// Nominal state plus error-state covariance.
#[derive(Clone, Debug)]
pub(crate) struct ErrorStateEkf {
    pub state: NavState,
    pub covariance: Covariance,
}

impl ErrorStateEkf {
    /// Integrates the IMU from one sample to the next over `dt` seconds (trapezoidal rates and
    /// specific forces, the rotation refined by the packet's attitude `increment` over the step
    /// where sampling leaves it uncertain, see [`super::turn`]; velocity rotated at the
    /// mid-point attitude) and propagates the covariance.
    pub fn predict(
        &mut self,
        dt: f64,
        from: &ImuSample,
        to: &ImuSample,
        increment: Option<&UnitQuaternion<f64>>,
        cfg: &PoseConfig,
    ) {
        let s = &mut self.state;
        let turn = turn::turn(
            dt,
            &(from.gyro - s.gyro_bias),
            &(to.gyro - s.gyro_bias),
            increment,
            cfg.packet_attitude_increment_sigma,
            cfg.gyro_noise_density * dt.sqrt(),
        );
        let accel = (from.accel + to.accel) * 0.5 - s.accel_bias;
        let gravity = Vector3::new(0.0, 0.0, -cfg.gravity);

        let rotation_step = UnitQuaternion::from_scaled_axis(turn.rotation);
        let mid = s.orientation * UnitQuaternion::from_scaled_axis(turn.rotation * 0.5);
        let rotation = mid.to_rotation_matrix().into_inner();
        let accel_world = rotation * accel + gravity;

        s.position += s.velocity * dt + accel_world * (0.5 * dt * dt);
        s.velocity += accel_world * dt;
        s.orientation *= rotation_step;
        s.orientation.renormalize_fast();

        let f = transition(dt, &rotation, &accel, &rotation_step, &turn.gyro_share);
        let mut q = process_noise(dt, cfg);
        for i in 0..3 {
            q[(ATTITUDE + i, ATTITUDE + i)] += turn.variance[i];
        }
        let p = f * self.covariance * f.transpose() + q;
        self.covariance = (p + p.transpose()) * 0.5;
    }

    /// Folds a measurement into the state if its normalised innovation squared is within
    /// `gate` (Joseph-form covariance update).
    pub fn correct<const M: usize>(&mut self, m: &Measurement<M>, gate: f64) -> Correction {
        let s = gate::innovation_covariance(&m.jacobian, &self.covariance, &m.noise);
        let Some(s_chol) = s.cholesky() else {
            return Correction::Degenerate;
        };
        let Some(nis) = gate::normalised_innovation_squared(&m.residual, &s_chol) else {
            return Correction::Degenerate;
        };
        if !gate::passes(nis, gate) {
            return Correction::Rejected(nis);
        }
        // K = P Hᵀ S⁻¹, computed as (S⁻¹ H P)ᵀ since S and P are symmetric.
        let gain: SMatrix<f64, N, M> = s_chol.solve(&(m.jacobian * self.covariance)).transpose();
        let dx = gain * m.residual;
        let i_kh = Covariance::identity() - gain * m.jacobian;
        let p = i_kh * self.covariance * i_kh.transpose() + gain * m.noise * gain.transpose();
        self.covariance = (p + p.transpose()) * 0.5;
        self.state.inject(&dx);
        Correction::Applied(nis)
    }

    /// Forgets what the filter believed about one 3-block of the error state (its variance
    /// becomes `sigma²`, its correlations zero): the next measurement of it is taken nearly
    /// as is. Used when a measurement has been gated out for too long to be an outlier.
    pub fn forget_block(&mut self, first: usize, sigma: f64) {
        for i in first..first + 3 {
            self.covariance.row_mut(i).fill(0.0);
            self.covariance.column_mut(i).fill(0.0);
            self.covariance[(i, i)] = sigma * sigma;
        }
    }
}

/// The error-state transition over `dt` with the mid-point rotation, bias-corrected specific
/// force, the step's rotation and the gyroscope's per-axis share in it.
fn transition(
    dt: f64,
    rotation: &Matrix3<f64>,
    accel: &Vector3<f64>,
    turn: &UnitQuaternion<f64>,
    gyro_share: &Vector3<f64>,
) -> Covariance {
    let mut f = Covariance::identity();
    let r_ax = rotation * accel.cross_matrix();
    f.fixed_view_mut::<3, 3>(POSITION, VELOCITY)
        .copy_from(&(Matrix3::identity() * dt));
    f.fixed_view_mut::<3, 3>(POSITION, ATTITUDE)
        .copy_from(&(-r_ax * (0.5 * dt * dt)));
    f.fixed_view_mut::<3, 3>(POSITION, ACCEL_BIAS)
        .copy_from(&(-rotation * (0.5 * dt * dt)));
    f.fixed_view_mut::<3, 3>(VELOCITY, ATTITUDE)
        .copy_from(&(-r_ax * dt));
    f.fixed_view_mut::<3, 3>(VELOCITY, ACCEL_BIAS)
        .copy_from(&(-rotation * dt));
    f.fixed_view_mut::<3, 3>(ATTITUDE, ATTITUDE)
        .copy_from(&turn.inverse().to_rotation_matrix().into_inner());
    f.fixed_view_mut::<3, 3>(ATTITUDE, GYRO_BIAS)
        .copy_from(&Matrix3::from_diagonal(&(gyro_share * -dt)));
    f
}

/// Discrete process noise over `dt` from the configured densities (white acceleration noise
/// integrated into velocity and position, white rate noise into attitude, random-walk biases).
fn process_noise(dt: f64, cfg: &PoseConfig) -> Covariance {
    let mut q = Covariance::zeros();
    let qa = cfg.accel_noise_density.powi(2);
    let qg = cfg.gyro_noise_density.powi(2);
    let block = |q: &mut Covariance, r: usize, c: usize, v: f64| {
        for i in 0..3 {
            q[(r + i, c + i)] = v;
        }
    };
    block(&mut q, POSITION, POSITION, qa * dt.powi(3) / 3.0);
    block(&mut q, POSITION, VELOCITY, qa * dt.powi(2) / 2.0);
    block(&mut q, VELOCITY, POSITION, qa * dt.powi(2) / 2.0);
    block(&mut q, VELOCITY, VELOCITY, qa * dt);
    block(&mut q, ATTITUDE, ATTITUDE, qg * dt);
    block(
        &mut q,
        ACCEL_BIAS,
        ACCEL_BIAS,
        cfg.accel_bias_walk.powi(2) * dt,
    );
    block(
        &mut q,
        GYRO_BIAS,
        GYRO_BIAS,
        cfg.gyro_bias_walk.powi(2) * dt,
    );
    q
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at_rest(gravity: f64) -> ImuSample {
        ImuSample {
            accel: Vector3::new(0.0, 0.0, gravity),
            gyro: Vector3::zeros(),
        }
    }

    fn filter() -> ErrorStateEkf {
        ErrorStateEkf {
            state: NavState {
                position: Vector3::zeros(),
                velocity: Vector3::new(10.0, 0.0, 0.0),
                orientation: UnitQuaternion::identity(),
                accel_bias: Vector3::zeros(),
                gyro_bias: Vector3::zeros(),
            },
            covariance: Covariance::identity() * 0.01,
        }
    }

    #[test]
    fn level_constant_velocity_is_a_straight_line() {
        let cfg = PoseConfig::default();
        let mut ekf = filter();
        let imu = at_rest(cfg.gravity);
        for _ in 0..10 {
            ekf.predict(0.1, &imu, &imu, None, &cfg);
        }
        assert!((ekf.state.position - Vector3::new(10.0, 0.0, 0.0)).norm() < 1e-9);
        assert!((ekf.state.velocity - Vector3::new(10.0, 0.0, 0.0)).norm() < 1e-9);
        // uncertainty grows
        assert!(ekf.covariance[(0, 0)] > 0.01);
    }

    #[test]
    fn a_constant_turn_rate_turns_the_velocity() {
        let cfg = PoseConfig::default();
        let mut ekf = filter();
        // 10 m/s on a circle of radius 20 m: rate 0.5 rad/s, centripetal 5 m/s² to the left.
        let imu = ImuSample {
            accel: Vector3::new(0.0, 5.0, cfg.gravity),
            gyro: Vector3::new(0.0, 0.0, 0.5),
        };
        for _ in 0..(std::f64::consts::PI / 0.5 / 0.01).round() as usize {
            ekf.predict(0.01, &imu, &imu, None, &cfg);
        }
        // Half a circle: heading west, 40 m north of the start.
        assert!((ekf.state.velocity - Vector3::new(-10.0, 0.0, 0.0)).norm() < 0.05);
        assert!((ekf.state.position - Vector3::new(0.0, 40.0, 0.0)).norm() < 0.2);
    }

    #[test]
    fn a_measurement_pulls_the_state_and_shrinks_the_covariance() {
        let mut ekf = filter();
        let mut jacobian = SMatrix::<f64, 3, N>::zeros();
        jacobian
            .fixed_view_mut::<3, 3>(0, POSITION)
            .fill_with_identity();
        let m = Measurement {
            residual: Vector3::new(1.0, 0.0, 0.0),
            jacobian,
            noise: Matrix3::identity() * 0.01,
        };
        let before = ekf.covariance[(0, 0)];
        assert!(matches!(
            ekf.correct(&m, f64::INFINITY),
            Correction::Applied(_)
        ));
        assert!((ekf.state.position.x - 0.5).abs() < 1e-9);
        assert!(ekf.covariance[(0, 0)] < before);
    }

    #[test]
    fn a_gated_measurement_changes_nothing() {
        let mut ekf = filter();
        let mut jacobian = SMatrix::<f64, 3, N>::zeros();
        jacobian
            .fixed_view_mut::<3, 3>(0, POSITION)
            .fill_with_identity();
        let m = Measurement {
            residual: Vector3::new(10.0, 0.0, 0.0),
            jacobian,
            noise: Matrix3::identity() * 0.01,
        };
        let before = ekf.clone();
        assert!(matches!(ekf.correct(&m, 16.27), Correction::Rejected(nis) if nis > 16.27));
        assert_eq!(ekf.state, before.state);
        assert_eq!(ekf.covariance, before.covariance);
    }
}
