//! What can go wrong when feeding the ego-pose filter.

use super::gps::Dropout;

/// Why a pose update was refused. The filter's state is unchanged by a refused update.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PoseError {
    /// The timestamp is NaN or infinite.
    #[error("timestamp {0} is not a finite number of seconds")]
    InvalidTimestamp(f64),
    /// The timestamp equals the previous one (a repeated packet).
    #[error("duplicate timestamp {0} s")]
    DuplicateTimestamp(f64),
    /// The timestamp is older than the previous one.
    #[error("timestamp {current} s is older than the previous {previous} s")]
    OutOfOrder {
        /// The previous accepted timestamp, seconds.
        previous: f64,
        /// The refused timestamp, seconds.
        current: f64,
    },
    /// The filter is not initialised yet and this packet cannot start it: its GPS position is
    /// a dropout.
    #[error("no usable GPS fix yet to initialise the pose: {0:?}")]
    AwaitingFix(Dropout),
    /// The filter is not initialised yet and this packet cannot start it: its roll, pitch or
    /// yaw is not finite.
    #[error("no finite roll, pitch and yaw yet to initialise the pose")]
    AwaitingAttitude,
    /// A given pose holds NaN or infinite values.
    #[error("the given pose is not finite")]
    InvalidPose,
}
