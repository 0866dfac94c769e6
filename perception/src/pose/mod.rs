//! Stage 1 of the paper: ego-vehicle pose estimation.
//!
//! An error-state extended Kalman filter (ESKF) over 15 error states — position, velocity,
//! attitude, accelerometer bias, gyroscope bias — whose nominal state is integrated from the
//! OXTS packet's IMU (`ax, ay, az` specific force and `wx, wy, wz` rates, IMU frame) and
//! corrected by the packet's GPS position (`lat, lon, alt` through the fleet's
//! [`GeoOrigin`](crate::geo::GeoOrigin)) and GPS velocity (`ve, vn, vu`), plus a
//! non-holonomic pseudo-measurement (a car does not slide sideways or lift off) and, loosely,
//! the packet's own gravity-referenced roll and pitch.
//!
//! Why this filter: a full 3-D attitude (not a planar model) keeps pitch and roll consistent
//! with the accelerometers on slopes and in turns, and estimated biases keep a cheap,
//! bias-y IMU usable through GPS dropouts; the error-state form keeps the attitude
//! linearisation well-conditioned. Yaw, which matters most for placing far objects, is
//! observable from GPS velocity together with the non-holonomic constraint even at constant
//! speed. GPS jumps are rejected by a Mahalanobis gate on the innovation ([`PoseConfig`]).
//! See [`gps`] for what counts as a dropout.
//!
//! One 15×15 predict and four small corrections per scan: microseconds.

mod config;
mod ekf;
mod error;
mod estimator;
mod gate;
pub mod gps;
mod imu;
mod measurement;
mod report;
mod state;

pub use config::PoseConfig;
pub use error::PoseError;
pub use estimator::PoseEstimator;
pub use gps::Dropout;
pub use report::{FixOutcome, StepReport};
pub use state::{ACCEL_BIAS, ATTITUDE, Covariance, ERROR_STATE_DIM, GYRO_BIAS, POSITION, VELOCITY};
