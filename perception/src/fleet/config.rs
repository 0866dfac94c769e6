//! Thresholds of fleet fusion.

use serde::{Deserialize, Serialize};

/// How remote super frames are checked, aged and associated with own tracks.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FusionConfig {
    /// A vehicle silent this long (ms) has its objects expire.
    pub ttl_ms: u64,
    /// Two observations closer than this on the ground plane (m) are the same object.
    pub gate_m: f64,
    /// A super frame whose origin is farther than this from the fleet origin (m) is rejected.
    pub max_origin_offset_m: f64,
    /// A super frame with more objects than this is rejected.
    pub max_objects: usize,
    /// An object farther than this from the fleet origin (m) makes its super frame rejected.
    pub max_range_m: f64,
    /// Observations are moved along their velocity for at most this long (ms) to the present.
    pub max_prediction_ms: u64,
}

impl Default for FusionConfig {
    fn default() -> Self {
        Self {
            ttl_ms: 2_000,
            gate_m: 2.0,
            max_origin_offset_m: 50_000.0,
            max_objects: 1_000,
            max_range_m: 100_000.0,
            max_prediction_ms: 500,
        }
    }
}
