//! The paper's probability-decay model of tracking confidence: a match raises the confidence
//! towards 1, a scan without a match lets it decay exponentially with the time elapsed, and a
//! track whose confidence falls below a threshold is dropped.

use serde::{Deserialize, Serialize};

/// Parameters of the confidence model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ConfidenceConfig {
    /// Confidence of a newborn track. Default 0.5.
    pub initial: f32,
    /// Fraction of the gap to 1 closed by each match. Default 0.4.
    pub hit_gain: f32,
    /// Time constant of the decay without a match (s): after `t` seconds unmatched the
    /// confidence is multiplied by `exp(-t / decay_time)`. Default 0.6.
    pub decay_time: f64,
    /// A track whose confidence falls below this is dropped. Default 0.25.
    pub drop_below: f32,
}

impl Default for ConfidenceConfig {
    fn default() -> Self {
        Self {
            initial: 0.5,
            hit_gain: 0.4,
            decay_time: 0.6,
            drop_below: 0.25,
        }
    }
}

impl ConfidenceConfig {
    /// Confidence after a match.
    pub fn hit(&self, confidence: f32) -> f32 {
        (confidence + self.hit_gain * (1.0 - confidence)).clamp(0.0, 1.0)
    }

    /// Confidence after `dt` seconds without a match.
    pub fn miss(&self, confidence: f32, dt: f64) -> f32 {
        let factor = (-dt.max(0.0) / self.decay_time.max(1e-6)).exp();
        (confidence as f64 * factor) as f32
    }

    /// Whether a track with this confidence is dropped.
    pub fn is_lost(&self, confidence: f32) -> bool {
        confidence < self.drop_below
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_raise_towards_one_and_misses_decay_to_a_drop() {
        let c = ConfidenceConfig::default();
        let mut x = c.initial;
        for _ in 0..10 {
            let y = c.hit(x);
            assert!(y > x && y <= 1.0);
            x = y;
        }
        assert!(x > 0.99);
        // A well-established track survives a short occlusion (0.5 s at 10 Hz)...
        let mut coasting = x;
        for _ in 0..5 {
            coasting = c.miss(coasting, 0.1);
        }
        assert!(!c.is_lost(coasting), "confidence {coasting}");
        // ...but not a long one.
        for _ in 0..10 {
            coasting = c.miss(coasting, 0.1);
        }
        assert!(c.is_lost(coasting));
        // A newborn track that is never seen again goes quickly.
        let mut newborn = c.initial;
        let mut scans = 0;
        while !c.is_lost(newborn) {
            newborn = c.miss(newborn, 0.1);
            scans += 1;
        }
        assert!(scans <= 5, "a one-hit track lives {scans} scans");
    }

    #[test]
    fn decay_depends_on_elapsed_time_not_on_scan_count() {
        let c = ConfidenceConfig::default();
        let once = c.miss(0.9, 0.4);
        let mut four = 0.9;
        for _ in 0..4 {
            four = c.miss(four, 0.1);
        }
        assert!((once - four).abs() < 1e-5);
    }
}
