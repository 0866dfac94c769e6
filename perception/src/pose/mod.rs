//! Stage 1 of the paper: ego-vehicle pose estimation.
//!
//! An error-state extended Kalman filter (ESKF) over 15 error states — position, velocity,
//! attitude, accelerometer bias, gyroscope bias. The OXTS packet's IMU (`ax, ay, az` specific
//! force and `wx, wy, wz` rates, IMU frame) drives the prediction; the packet's GPS position
//! (`lat, lon, alt` through the fleet's [`GeoOrigin`](crate::geo::GeoOrigin)) and GPS
//! velocity (`ve, vn, vu`) correct it, with a non-holonomic pseudo-measurement (a car does not
//! slide sideways or lift off) and, loosely, the unit's own roll, pitch and yaw as anchors.
//!
//! Why this filter: a full 3-D attitude (not a planar model) keeps pitch and roll consistent
//! with the accelerometers on slopes and in turns; estimated biases keep a bias-y IMU usable
//! through GPS dropouts; the error-state form keeps the attitude linearisation
//! well-conditioned. Yaw matters most for placing far objects (0.1° is 7 cm at 40 m): the
//! gyroscope carries it from frame to frame, GPS velocity with the non-holonomic constraint
//! and the packet's heading hold it over time.
//!
//! Three details keep a static object still in the world from frame to frame (the tracker's
//! need, beyond absolute accuracy):
//! - the IMU is sampled once per scan; where the rates change abruptly between two samples
//!   the packet's attitude increment refines the rotation (`turn.rs`);
//! - GPS jumps are rejected by a Mahalanobis gate on the innovation ([`PoseConfig`]); a shift
//!   that lasts is re-anchored on;
//! - the tracker works in an odometry frame that GPS corrections move at a bounded speed
//!   ([`PoseConfig::max_output_correction_speed`]), while the filter (the world frame)
//!   converges from its first fix or corrects at once after an outage.
//!
//! See [`gps`] for what counts as a dropout. One 15×15 predict and five small corrections per
//! scan: microseconds.

mod config;
mod ekf;
mod error;
mod estimator;
mod gate;
pub mod gps;
mod imu;
mod measurement;
mod report;
mod slew;
mod state;
mod turn;

pub use config::PoseConfig;
pub use error::PoseError;
pub use estimator::PoseEstimator;
pub use gps::Dropout;
pub use report::{FixOutcome, StepReport};
pub use state::{ACCEL_BIAS, ATTITUDE, Covariance, ERROR_STATE_DIM, GYRO_BIAS, POSITION, VELOCITY};
