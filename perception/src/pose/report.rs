//! What one update did with the packet's GPS, for metrics and logs.

use serde::{Deserialize, Serialize};

use super::gps::Dropout;

/// What happened to one GPS measurement (position or velocity) in one update.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FixOutcome {
    /// Folded into the estimate; `nis` is its normalised innovation squared.
    Used {
        /// Squared Mahalanobis distance of the innovation.
        nis: f64,
    },
    /// Outside the innovation gate: treated as a jump and ignored.
    Rejected {
        /// Squared Mahalanobis distance of the innovation.
        nis: f64,
    },
    /// Gated out for too many updates in a row, so taken as a real shift: the filter forgot
    /// its own belief of that quantity and took the measurement.
    Reanchored {
        /// Squared Mahalanobis distance of the innovation before re-anchoring.
        nis: f64,
    },
    /// Not usable (see [`Dropout`]): the filter predicted through it.
    Dropout(Dropout),
    /// The measurement started (or restarted) the filter.
    Initialised,
    /// No measurement was involved (a given pose, or a degenerate innovation).
    None,
}

impl FixOutcome {
    /// Whether the measurement shaped the estimate.
    pub fn used(&self) -> bool {
        matches!(
            self,
            Self::Used { .. } | Self::Reanchored { .. } | Self::Initialised
        )
    }
}

/// What one update did.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepReport {
    /// The GPS position.
    pub position: FixOutcome,
    /// The GPS velocity.
    pub velocity: FixOutcome,
    /// The filter was (re)started from this packet.
    pub initialised: bool,
    /// The IMU fields were not finite, so the previous sample was held.
    pub imu_held: bool,
}

impl Default for StepReport {
    fn default() -> Self {
        Self {
            position: FixOutcome::None,
            velocity: FixOutcome::None,
            initialised: false,
            imu_held: false,
        }
    }
}
