//! The IMU's rotation over one step.
//!
//! An OXTS packet carries the angular rate at one instant, once per scan (10 Hz). Integrating
//! two such samples (trapezoid) is exact while the rate changes smoothly, but a rate that
//! changes abruptly between them — a curb, a pothole, a steering step — leaves the integral
//! uncertain by about `|Δω|·dt/√12` (a step at an unknown instant of the interval). The packet's
//! own attitude, integrated by the unit at its internal rate, knows how far it turned: where
//! sampling leaves the integral uncertain, its attitude increment is weighted in, per axis,
//! by inverse variance. Where the rate is smooth the gyroscope dominates.

use nalgebra::{UnitQuaternion, Vector3};

/// The rotation of one step and what is known of its error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Turn {
    /// Rotation vector in the IMU frame at the start of the step, radians.
    pub rotation: Vector3<f64>,
    /// Per-axis variance of the rotation from sampling (beyond the gyroscope's white noise),
    /// rad².
    pub variance: Vector3<f64>,
    /// Per-axis share of the gyroscope in the rotation (1: all gyroscope, 0: all packet
    /// attitude); how much a gyroscope bias error affects it.
    pub gyro_share: Vector3<f64>,
}

/// Squared gate (in σ) beyond which the packet's attitude increment is taken as wrong.
const INCREMENT_GATE: f64 = 16.0;

/// The rotation from rate samples `from` and `to` (rad/s, bias-corrected) over `dt` seconds,
/// refined by the packet's attitude increment over the same step (with per-axis σ
/// `increment_sigma`, radians) when one is given. `gyro_step_sigma` is the gyroscope's own
/// noise over the step, radians, used to gate the increment.
pub(crate) fn turn(
    dt: f64,
    from: &Vector3<f64>,
    to: &Vector3<f64>,
    increment: Option<&UnitQuaternion<f64>>,
    increment_sigma: f64,
    gyro_step_sigma: f64,
) -> Turn {
    let integrated = (from + to) * (0.5 * dt);
    let sampling = (to - from).map(|d| (d * dt).powi(2) / 12.0);
    let imu_only = Turn {
        rotation: integrated,
        variance: sampling,
        gyro_share: Vector3::repeat(1.0),
    };
    let Some(increment) = increment else {
        return imu_only;
    };
    let packet_variance = increment_sigma * increment_sigma;
    if packet_variance <= 0.0 {
        return imu_only;
    }
    let residual =
        (UnitQuaternion::from_scaled_axis(integrated).inverse() * increment).scaled_axis();
    let gate_variance = sampling.add_scalar(packet_variance + gyro_step_sigma * gyro_step_sigma);
    let plausible = residual
        .iter()
        .zip(gate_variance.iter())
        .all(|(r, v)| r * r <= INCREMENT_GATE * v);
    if !plausible {
        return imu_only;
    }
    let packet_share = sampling.map(|s| s / (s + packet_variance));
    Turn {
        rotation: integrated + residual.component_mul(&packet_share),
        variance: sampling.map(|s| s * packet_variance / (s + packet_variance)),
        gyro_share: packet_share.map(|w| 1.0 - w),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_rates_are_the_gyroscope_s() {
        let w = Vector3::new(0.0, 0.0, 0.3);
        let packet = UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, 0.031));
        let t = turn(0.1, &w, &w, Some(&packet), 0.003, 1e-4);
        assert!((t.rotation - Vector3::new(0.0, 0.0, 0.03)).norm() < 1e-12);
        assert_eq!(t.variance, Vector3::zeros());
        assert_eq!(t.gyro_share, Vector3::repeat(1.0));
    }

    #[test]
    fn a_rate_step_takes_the_packet_s_increment() {
        // The yaw rate stepped from 0 to 0.5 rad/s 30 ms into a 100 ms step: it turned
        // 0.5 · 0.07 = 0.035 rad, the trapezoid says 0.025.
        let truth = 0.035;
        let packet = UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, truth));
        let (from, to) = (Vector3::zeros(), Vector3::new(0.0, 0.0, 0.5));
        let imu = turn(0.1, &from, &to, None, 0.003, 1e-4);
        assert!((imu.rotation.z - 0.025).abs() < 1e-12);
        assert!((imu.variance.z.sqrt() - 0.05 / 12f64.sqrt()).abs() < 1e-12);
        let fused = turn(0.1, &from, &to, Some(&packet), 0.003, 1e-4);
        assert!(
            (fused.rotation.z - truth).abs() < 0.0005,
            "{}",
            fused.rotation.z
        );
        assert!(fused.variance.z < 0.003 * 0.003);
        assert!(fused.gyro_share.z < 0.1);
    }

    #[test]
    fn an_implausible_increment_is_ignored() {
        let (from, to) = (Vector3::zeros(), Vector3::new(0.0, 0.0, 0.5));
        let packet = UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, 1.0));
        let t = turn(0.1, &from, &to, Some(&packet), 0.003, 1e-4);
        assert!((t.rotation.z - 0.025).abs() < 1e-12);
    }
}
