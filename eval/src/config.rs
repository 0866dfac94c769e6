//! The scoring's parameters: when a hypothesis may match a ground-truth object.

use serde::Serialize;

/// Match thresholds. A GT object and a hypothesis may match only when their BEV centre distance
/// is strictly below the GT object's class threshold.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct EvalConfig {
    /// Threshold for every class (metres); the protocol's is 2.0.
    pub threshold: f64,
    /// Threshold for cyclists instead of `threshold` (the protocol's cyclist test uses 0.6).
    pub cyclist_threshold: Option<f64>,
}

impl Default for EvalConfig {
    /// The protocol's: 2.0 m for every class.
    fn default() -> Self {
        Self {
            threshold: 2.0,
            cyclist_threshold: None,
        }
    }
}

impl EvalConfig {
    /// The match threshold for a GT object of class `class` (case-insensitive "cyclist" takes
    /// `cyclist_threshold` when set).
    pub fn threshold_for(&self, class: &str) -> f64 {
        match self.cyclist_threshold {
            Some(cyclist) if class.eq_ignore_ascii_case("cyclist") => cyclist,
            _ => self.threshold,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cyclists_take_their_own_threshold() {
        let config = EvalConfig {
            threshold: 2.0,
            cyclist_threshold: Some(0.6),
        };
        assert_eq!(config.threshold_for("Cyclist"), 0.6);
        assert_eq!(config.threshold_for("cyclist"), 0.6);
        assert_eq!(config.threshold_for("Car"), 2.0);
        assert_eq!(EvalConfig::default().threshold_for("Cyclist"), 2.0);
    }
}
