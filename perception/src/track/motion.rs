//! The motion model of one track: an extended Kalman filter on the paper's state
//! `[x, y, z, vx, vy, θ]` in the world frame, with a constant-velocity process model.
//!
//! Velocity is zero at birth with a large, class-dependent uncertainty, so the first
//! association after birth admits any plausible jump (a car at 30 m/s moves 3 m between
//! scans) while the next ones are gated tightly around the predicted position. The heading θ
//! follows a random walk and is measured from the fitted box, whose yaw is only known modulo
//! π: the measurement is flipped to the nearest of `yaw` and `yaw + π` before the update.

use std::f64::consts::PI;

use nalgebra::{Matrix2, Matrix4, Matrix4x6, Matrix6, Vector2, Vector3, Vector4, Vector6};

/// Index of the heading in the state.
const YAW: usize = 5;

/// Process noise of the constant-velocity model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProcessNoise {
    /// White-noise acceleration in the ground plane, m/s².
    pub accel: f64,
    /// Random walk of the height, m/√s.
    pub z_walk: f64,
    /// Random walk of the heading, rad/√s.
    pub yaw_walk: f64,
}

/// Standard deviations of one box measurement `[x, y, z, θ]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeasurementNoise {
    /// Horizontal position, m.
    pub position: f64,
    /// Height, m.
    pub z: f64,
    /// Heading, rad.
    pub yaw: f64,
}

/// Wraps an angle into (−π, π].
pub fn wrap_angle(a: f64) -> f64 {
    let w = (a + PI).rem_euclid(2.0 * PI) - PI;
    if w <= -PI { w + 2.0 * PI } else { w }
}

/// The EKF of one track.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionModel {
    /// State `[x, y, z, vx, vy, θ]`.
    x: Vector6<f64>,
    /// State covariance.
    p: Matrix6<f64>,
}

/// The measured position of a track's prediction: mean and covariance of `[x, y]` including
/// the measurement noise (the innovation covariance of the horizontal position).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PredictedPosition {
    /// Predicted horizontal position, m.
    pub mean: Vector2<f64>,
    /// Innovation covariance of the horizontal position, m².
    pub covariance: Matrix2<f64>,
}

impl PredictedPosition {
    /// Squared Mahalanobis distance of `p` from the prediction (∞ if the covariance is
    /// singular).
    pub fn mahalanobis_squared(&self, p: &Vector2<f64>) -> f64 {
        let d = p - self.mean;
        match self.covariance.try_inverse() {
            Some(inv) => (d.transpose() * inv * d)[0],
            None => f64::INFINITY,
        }
    }

    /// Negative log-likelihood of `p` under the prediction, up to a constant:
    /// `d² + ln det S`. Unlike `d²` alone it compares fairly between predictions of different
    /// uncertainty.
    pub fn negative_log_likelihood(&self, p: &Vector2<f64>) -> f64 {
        self.mahalanobis_squared(p) + self.covariance.determinant().max(1e-12).ln()
    }
}

impl MotionModel {
    /// A track born at `position` with heading `yaw`, at rest, with standard deviations
    /// `noise` on the position and heading and `velocity_sigma` (m/s) on each velocity
    /// component.
    pub fn new(
        position: Vector3<f64>,
        yaw: f64,
        noise: &MeasurementNoise,
        velocity_sigma: f64,
    ) -> Self {
        let x = Vector6::new(
            position.x,
            position.y,
            position.z,
            0.0,
            0.0,
            wrap_angle(yaw),
        );
        let p = Matrix6::from_diagonal(&Vector6::new(
            noise.position.powi(2),
            noise.position.powi(2),
            noise.z.powi(2),
            velocity_sigma.powi(2),
            velocity_sigma.powi(2),
            noise.yaw.powi(2),
        ));
        Self { x, p }
    }

    /// The state `[x, y, z, vx, vy, θ]`.
    pub fn state(&self) -> &Vector6<f64> {
        &self.x
    }

    /// The state covariance.
    pub fn covariance(&self) -> &Matrix6<f64> {
        &self.p
    }

    /// Position `[x, y, z]`.
    pub fn position(&self) -> Vector3<f64> {
        Vector3::new(self.x[0], self.x[1], self.x[2])
    }

    /// Velocity over ground `[vx, vy]`.
    pub fn velocity(&self) -> Vector2<f64> {
        Vector2::new(self.x[3], self.x[4])
    }

    /// Heading θ.
    pub fn yaw(&self) -> f64 {
        self.x[YAW]
    }

    /// Standard deviation of the speed estimate along its largest axis, m/s.
    pub fn velocity_sigma(&self) -> f64 {
        self.p
            .fixed_view::<2, 2>(3, 3)
            .symmetric_eigenvalues()
            .max()
            .max(0.0)
            .sqrt()
    }

    /// Transition matrix of the constant-velocity model over `dt` (also its Jacobian).
    fn transition(dt: f64) -> Matrix6<f64> {
        let mut f = Matrix6::identity();
        f[(0, 3)] = dt;
        f[(1, 4)] = dt;
        f
    }

    /// Process noise over `dt`: white acceleration for x/y, random walks for z and θ.
    fn process_noise(dt: f64, q: &ProcessNoise) -> Matrix6<f64> {
        let a2 = q.accel * q.accel;
        let mut m = Matrix6::zeros();
        for (pos, vel) in [(0, 3), (1, 4)] {
            m[(pos, pos)] = a2 * dt.powi(4) / 4.0;
            m[(pos, vel)] = a2 * dt.powi(3) / 2.0;
            m[(vel, pos)] = a2 * dt.powi(3) / 2.0;
            m[(vel, vel)] = a2 * dt * dt;
        }
        m[(2, 2)] = q.z_walk * q.z_walk * dt;
        m[(YAW, YAW)] = q.yaw_walk * q.yaw_walk * dt;
        m
    }

    /// Sets the velocity to zero: the object stands still.
    pub fn stop(&mut self) {
        self.x[3] = 0.0;
        self.x[4] = 0.0;
    }

    /// Moves the state `dt` seconds ahead.
    pub fn predict(&mut self, dt: f64, noise: &ProcessNoise) {
        let dt = dt.max(0.0);
        let f = Self::transition(dt);
        self.x = f * self.x;
        self.x[YAW] = wrap_angle(self.x[YAW]);
        self.p = f * self.p * f.transpose() + Self::process_noise(dt, noise);
    }

    /// Where a box measurement of this (already predicted) track is expected.
    pub fn predicted_position(&self, noise: &MeasurementNoise) -> PredictedPosition {
        let r = noise.position * noise.position;
        PredictedPosition {
            mean: Vector2::new(self.x[0], self.x[1]),
            covariance: self.p.fixed_view::<2, 2>(0, 0).into_owned() + Matrix2::identity() * r,
        }
    }

    /// The heading measurement `yaw` (known modulo π) turned to the nearest of `yaw`,
    /// `yaw + π` from the current heading.
    pub fn nearest_heading(&self, yaw: f64) -> f64 {
        let d = wrap_angle(yaw - self.x[YAW]);
        let d = if d > PI / 2.0 {
            d - PI
        } else if d < -PI / 2.0 {
            d + PI
        } else {
            d
        };
        wrap_angle(self.x[YAW] + d)
    }

    /// Corrects the state with a box measured at `position` with heading `yaw` (modulo π;
    /// `None`: heading not measured).
    pub fn update(&mut self, position: &Vector3<f64>, yaw: Option<f64>, noise: &MeasurementNoise) {
        let mut h = Matrix4x6::zeros();
        h[(0, 0)] = 1.0;
        h[(1, 1)] = 1.0;
        h[(2, 2)] = 1.0;
        h[(3, YAW)] = 1.0;
        let mut innovation = Vector4::new(
            position.x - self.x[0],
            position.y - self.x[1],
            position.z - self.x[2],
            0.0,
        );
        let mut r = Matrix4::from_diagonal(&Vector4::new(
            noise.position.powi(2),
            noise.position.powi(2),
            noise.z.powi(2),
            noise.yaw.powi(2),
        ));
        match yaw {
            Some(yaw) => innovation[3] = wrap_angle(self.nearest_heading(yaw) - self.x[YAW]),
            // An unmeasured heading: an infinitely uncertain pseudo-measurement of it.
            None => {
                h[(3, YAW)] = 0.0;
                r[(3, 3)] = 1.0;
            }
        }
        let s = h * self.p * h.transpose() + r;
        let Some(s_inv) = s.try_inverse() else {
            return;
        };
        let k = self.p * h.transpose() * s_inv;
        self.x += k * innovation;
        self.x[YAW] = wrap_angle(self.x[YAW]);
        // Joseph form keeps the covariance symmetric and positive.
        let i_kh = Matrix6::identity() - k * h;
        self.p = i_kh * self.p * i_kh.transpose() + k * r * k.transpose();
    }

    /// Sets the heading to the direction of motion when the object clearly moves: a box's yaw
    /// is ambiguous by π, the velocity is not.
    pub fn align_heading_with_velocity(&mut self, min_speed: f64) {
        let v = self.velocity();
        if v.norm() >= min_speed && v.norm() > 2.0 * self.velocity_sigma() {
            self.x[YAW] = v.y.atan2(v.x);
        }
    }

    /// Replaces the heading (a wrong first guess of the box's axes), keeping its uncertainty.
    pub fn set_heading(&mut self, yaw: f64) {
        self.x[YAW] = wrap_angle(yaw);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const Q: ProcessNoise = ProcessNoise {
        accel: 2.0,
        z_walk: 0.2,
        yaw_walk: 0.3,
    };
    const R: MeasurementNoise = MeasurementNoise {
        position: 0.2,
        z: 0.2,
        yaw: 0.2,
    };

    #[test]
    fn wraps_angles_into_half_open_interval() {
        assert!((wrap_angle(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(-PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(0.5 - 4.0 * PI) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn learns_a_constant_velocity_from_positions() {
        let mut m = MotionModel::new(Vector3::zeros(), 0.0, &R, 10.0);
        for k in 1..=20 {
            m.predict(0.1, &Q);
            let t = k as f64 * 0.1;
            m.update(&Vector3::new(8.0 * t, -3.0 * t, 0.0), Some(0.0), &R);
        }
        let v = m.velocity();
        assert!((v.x - 8.0).abs() < 0.3, "vx = {}", v.x);
        assert!((v.y + 3.0).abs() < 0.3, "vy = {}", v.y);
        // The prediction of the next scan lands where the object will be.
        m.predict(0.1, &Q);
        let p = m.predicted_position(&R);
        assert!((p.mean - Vector2::new(16.8, -6.3)).norm() < 0.1);
    }

    #[test]
    fn unknown_velocity_admits_a_highway_jump_but_a_known_one_does_not() {
        // A new track of a car: velocity unknown (σ 15 m/s). A 3 m jump in 0.1 s is inside
        // the 99.9 % gate (χ², 2 dof: 13.8).
        let mut fresh = MotionModel::new(Vector3::zeros(), 0.0, &R, 15.0);
        fresh.predict(0.1, &Q);
        let gate = fresh.predicted_position(&R);
        assert!(gate.mahalanobis_squared(&Vector2::new(3.0, 0.0)) < 13.8);
        // A pedestrian-sized track (σ 2 m/s) is not allowed such a jump.
        let mut walker = MotionModel::new(Vector3::zeros(), 0.0, &R, 2.0);
        walker.predict(0.1, &Q);
        let gate = walker.predicted_position(&R);
        assert!(gate.mahalanobis_squared(&Vector2::new(3.0, 0.0)) > 13.8);
        // Once at rest for a few scans, a 3 m jump is far outside the gate.
        let mut parked = MotionModel::new(Vector3::zeros(), 0.0, &R, 15.0);
        for _ in 0..5 {
            parked.predict(0.1, &Q);
            parked.update(&Vector3::zeros(), Some(0.0), &R);
        }
        parked.predict(0.1, &Q);
        let gate = parked.predicted_position(&R);
        assert!(gate.mahalanobis_squared(&Vector2::new(3.0, 0.0)) > 13.8);
    }

    #[test]
    fn box_heading_is_taken_modulo_pi() {
        let mut m = MotionModel::new(Vector3::zeros(), 0.1, &R, 1.0);
        assert!((m.nearest_heading(0.1 + PI) - 0.1).abs() < 1e-9);
        m.update(&Vector3::zeros(), Some(0.15 - PI), &R);
        assert!((m.yaw() - 0.125).abs() < 0.03, "yaw = {}", m.yaw());
    }

    #[test]
    fn heading_follows_clear_motion() {
        let mut m = MotionModel::new(Vector3::zeros(), 0.0, &R, 10.0);
        for k in 1..=10 {
            m.predict(0.1, &Q);
            let t = k as f64 * 0.1;
            m.update(&Vector3::new(-5.0 * t, 0.0, 0.0), None, &R);
        }
        m.align_heading_with_velocity(1.0);
        assert!((wrap_angle(m.yaw() - PI)).abs() < 0.05, "yaw = {}", m.yaw());
    }

    #[test]
    fn covariance_stays_symmetric_and_positive() {
        let mut m = MotionModel::new(Vector3::zeros(), 0.0, &R, 10.0);
        for k in 0..50 {
            m.predict(0.1, &Q);
            if k % 3 != 0 {
                m.update(&Vector3::new(k as f64, 0.0, 0.0), Some(0.0), &R);
            }
        }
        let p = m.covariance();
        assert!((p - p.transpose()).norm() < 1e-9);
        assert!(p.symmetric_eigenvalues().min() > 0.0);
    }

    #[test]
    fn likelihood_prefers_the_certain_track_for_a_near_point() {
        let mut certain = MotionModel::new(Vector3::zeros(), 0.0, &R, 0.1);
        let mut vague = MotionModel::new(Vector3::new(0.5, 0.0, 0.0), 0.0, &R, 20.0);
        certain.predict(0.1, &Q);
        vague.predict(0.1, &Q);
        let p = Vector2::new(0.2, 0.0);
        let c = certain.predicted_position(&R);
        let v = vague.predicted_position(&R);
        // By Mahalanobis distance alone the vague track looks closer; by likelihood it is not.
        assert!(v.mahalanobis_squared(&p) < c.mahalanobis_squared(&p));
        assert!(c.negative_log_likelihood(&p) < v.negative_log_likelihood(&p));
    }
}
