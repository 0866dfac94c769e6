//! Continuity of the odometry pose.
//!
//! Every GPS correction moves the filter's position: by centimetres a step in steady
//! driving, by a metre or more while it converges from its first fix or when GPS returns
//! after an outage. Every static object would move with it. The odometry position instead
//! absorbs each step's correction into an offset and releases it at a bounded speed, like the
//! odometry frame of a localisation stack: the filter itself (and its covariance) stays exact;
//! the odometry frame follows it slowly.

use nalgebra::Vector3;

/// The offset (world frame, metres) of the published position from the filter's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Slew {
    offset: Vector3<f64>,
}

impl Slew {
    /// Takes in a step's position correction (after − before the GPS updates) and releases up
    /// to `max_speed · dt` metres of the accumulated offset; `max_speed` ≤ 0 publishes the
    /// filter's position as is.
    pub fn absorb(&mut self, correction: &Vector3<f64>, dt: f64, max_speed: f64) {
        if !(max_speed > 0.0 && correction.iter().all(|c| c.is_finite())) {
            self.offset = Vector3::zeros();
            return;
        }
        let offset = self.offset - correction;
        let length = offset.norm();
        let budget = max_speed * dt.max(0.0);
        self.offset = if length > budget {
            offset * ((length - budget) / length)
        } else {
            Vector3::zeros()
        };
    }

    /// The odometry position minus the filter's.
    pub fn offset(&self) -> Vector3<f64> {
        self.offset
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_corrections_pass_through() {
        let mut slew = Slew::default();
        slew.absorb(&Vector3::new(0.05, 0.0, 0.0), 0.1, 1.0);
        assert_eq!(slew.offset(), Vector3::zeros());
    }

    #[test]
    fn a_large_correction_is_released_at_the_speed_limit() {
        let mut slew = Slew::default();
        slew.absorb(&Vector3::new(0.35, 0.0, 0.0), 0.1, 1.0);
        assert!((slew.offset() - Vector3::new(-0.25, 0.0, 0.0)).norm() < 1e-12);
        slew.absorb(&Vector3::zeros(), 0.1, 1.0);
        assert!((slew.offset() - Vector3::new(-0.15, 0.0, 0.0)).norm() < 1e-12);
        slew.absorb(&Vector3::zeros(), 0.1, 1.0);
        slew.absorb(&Vector3::zeros(), 0.1, 1.0);
        assert_eq!(slew.offset(), Vector3::zeros());
    }

    #[test]
    fn zero_speed_or_nan_publishes_the_filter() {
        let mut slew = Slew::default();
        slew.absorb(&Vector3::new(3.0, 0.0, 0.0), 0.1, 0.0);
        assert_eq!(slew.offset(), Vector3::zeros());
        slew.absorb(&Vector3::new(3.0, 0.0, 0.0), 0.1, 1.0);
        slew.absorb(&Vector3::new(f64::NAN, 0.0, 0.0), 0.1, 1.0);
        assert_eq!(slew.offset(), Vector3::zeros());
    }
}
