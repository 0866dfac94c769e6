//! The filter's nominal state and the layout of its error state.

use nalgebra::{Isometry3, SMatrix, Translation3, UnitQuaternion, Vector3};

/// Size of the error state: position, velocity, attitude, accelerometer and gyroscope biases.
pub const ERROR_STATE_DIM: usize = 15;

/// Covariance of the error state. Rows/columns in blocks of three: [`POSITION`],
/// [`VELOCITY`], [`ATTITUDE`], [`ACCEL_BIAS`], [`GYRO_BIAS`].
pub type Covariance = SMatrix<f64, ERROR_STATE_DIM, ERROR_STATE_DIM>;

/// First index of the position error (world frame, metres).
pub const POSITION: usize = 0;
/// First index of the velocity error (world frame, m/s).
pub const VELOCITY: usize = 3;
/// First index of the attitude error: a small rotation in the IMU frame, radians
/// (true orientation = estimate · Exp(δθ)).
pub const ATTITUDE: usize = 6;
/// First index of the accelerometer bias error (IMU frame, m/s²).
pub const ACCEL_BIAS: usize = 9;
/// First index of the gyroscope bias error (IMU frame, rad/s).
pub const GYRO_BIAS: usize = 12;

/// The nominal (best-estimate) state of the IMU.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct NavState {
    /// IMU position in the world frame, metres.
    pub position: Vector3<f64>,
    /// IMU velocity in the world frame, m/s.
    pub velocity: Vector3<f64>,
    /// Rotation from the IMU frame to the world frame.
    pub orientation: UnitQuaternion<f64>,
    /// Accelerometer bias, IMU frame, m/s².
    pub accel_bias: Vector3<f64>,
    /// Gyroscope bias, IMU frame, rad/s.
    pub gyro_bias: Vector3<f64>,
}

impl NavState {
    /// The IMU's pose in the world frame.
    pub fn pose(&self) -> Isometry3<f64> {
        Isometry3::from_parts(Translation3::from(self.position), self.orientation)
    }

    /// Applies an error-state correction to the nominal state.
    pub fn inject(&mut self, dx: &SMatrix<f64, ERROR_STATE_DIM, 1>) {
        self.position += dx.fixed_rows::<3>(POSITION);
        self.velocity += dx.fixed_rows::<3>(VELOCITY);
        let rotation = UnitQuaternion::from_scaled_axis(dx.fixed_rows::<3>(ATTITUDE).into_owned());
        self.orientation *= rotation;
        self.orientation.renormalize_fast();
        self.accel_bias += dx.fixed_rows::<3>(ACCEL_BIAS);
        self.gyro_bias += dx.fixed_rows::<3>(GYRO_BIAS);
    }
}
