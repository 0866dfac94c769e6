//! Ids of static objects whose tracks were dropped, kept for a while so that the object gets
//! its id back when it is seen again.
//!
//! A parked car or a standing person hidden for a few seconds (a bus passes, the sensor drives
//! past a hedge) loses its track to the confidence decay. It has not moved in the world frame:
//! a track born near where it was last seen, soon after, is that object again. A moving object
//! is remembered for [`MOVING_MEMORY`] only, where its velocity takes it: a walker lost in a
//! crowd for a moment, or behind a post.

use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

/// How long and how near a dropped static object is recognised.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DormantConfig {
    /// Seconds a dropped static object's id is kept (0 turns the memory off). Default 5.
    pub memory: f64,
    /// Largest distance (m) between where it was last seen and a new track's box centre: a
    /// partial view moves a car's box centre by up to a metre. Default 1.5.
    pub radius: f64,
}

impl Default for DormantConfig {
    fn default() -> Self {
        Self {
            memory: 5.0,
            radius: 1.5,
        }
    }
}

/// Seconds a dropped moving object's id is kept (at most the configured memory): after
/// longer unseen, where it is is a guess.
pub const MOVING_MEMORY: f64 = 1.5;

/// One remembered object.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Dormant {
    id: u64,
    /// Where it was last seen (world frame), when (s), and its velocity then (m/s).
    seen: (Vector2<f64>, f64),
    velocity: Vector2<f64>,
    /// Time (s) its track was dropped.
    dropped: f64,
}

impl Dormant {
    /// Where it is at time `now`.
    fn position(&self, now: f64) -> Vector2<f64> {
        self.seen.0 + self.velocity * (now - self.seen.1)
    }

    /// How long it is remembered (s).
    fn memory(&self, config: &DormantConfig) -> f64 {
        if self.velocity == Vector2::zeros() {
            config.memory
        } else {
            config.memory.min(MOVING_MEMORY)
        }
    }
}

/// The remembered objects.
#[derive(Clone, Debug, Default)]
pub struct DormantTracks {
    config: DormantConfig,
    remembered: Vec<Dormant>,
}

impl DormantTracks {
    /// An empty memory with `config`.
    pub fn new(config: DormantConfig) -> Self {
        Self {
            config,
            remembered: Vec::new(),
        }
    }

    /// Remembers object `id`, dropped at time `now`: last `seen` at a place (world frame) and
    /// time, moving at `velocity` (zero for a static object).
    pub fn remember(
        &mut self,
        id: u64,
        seen: (Vector2<f64>, f64),
        velocity: Vector2<f64>,
        now: f64,
    ) {
        if self.config.memory > 0.0 {
            self.remembered.push(Dormant {
                id,
                seen,
                velocity,
                dropped: now,
            });
        }
    }

    /// Forgets what was dropped more than the memory's length before `now`, or after it (the
    /// clock went back: another drive).
    pub fn expire(&mut self, now: f64) {
        let config = &self.config;
        self.remembered
            .retain(|d| (0.0..=d.memory(config)).contains(&(now - d.dropped)));
    }

    /// The id of the nearest remembered object within the radius of `position` at time `now`,
    /// forgotten now that it is claimed.
    pub fn claim(&mut self, position: Vector2<f64>, now: f64) -> Option<u64> {
        let radius = self.config.radius;
        let (k, _) = self
            .remembered
            .iter()
            .map(|d| (d.position(now) - position).norm())
            .enumerate()
            .filter(|&(_, distance)| distance <= radius)
            .min_by(|a, b| a.1.total_cmp(&b.1))?;
        Some(self.remembered.swap_remove(k).id)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_nearest_object_within_the_radius_is_claimed_once_until_forgotten() {
        let mut memory = DormantTracks::new(DormantConfig::default());
        memory.remember(7, (Vector2::new(10.0, 2.0), 1.0), Vector2::zeros(), 1.0);
        memory.remember(9, (Vector2::new(10.0, 3.2), 1.5), Vector2::zeros(), 1.5);
        assert_eq!(memory.claim(Vector2::new(20.0, 2.0), 0.0), None);
        assert_eq!(memory.claim(Vector2::new(10.2, 2.3), 0.0), Some(7));
        assert_eq!(memory.claim(Vector2::new(10.2, 2.3), 0.0), Some(9));
        assert_eq!(memory.claim(Vector2::new(10.2, 2.3), 0.0), None);
        memory.remember(11, (Vector2::new(0.0, 0.0), 2.0), Vector2::zeros(), 2.0);
        memory.expire(6.9);
        assert_eq!(memory.claim(Vector2::new(0.5, 0.0), 0.0), Some(11));
        memory.remember(12, (Vector2::new(0.0, 0.0), 2.0), Vector2::zeros(), 2.0);
        memory.expire(7.1);
        assert_eq!(memory.claim(Vector2::new(0.0, 0.0), 0.0), None);
        // A clock that goes back starts over.
        memory.remember(13, (Vector2::new(0.0, 0.0), 100.0), Vector2::zeros(), 100.0);
        memory.expire(0.1);
        assert_eq!(memory.claim(Vector2::new(0.0, 0.0), 0.0), None);
    }

    #[test]
    fn a_moving_object_is_claimed_where_it_went_for_a_short_while() {
        let mut memory = DormantTracks::new(DormantConfig::default());
        // A walker at 1.2 m/s along x, last seen at (10, 2) at t = 1.0, dropped at t = 1.3.
        let walker = (Vector2::new(10.0, 2.0), 1.0);
        memory.remember(4, walker, Vector2::new(1.2, 0.0), 1.3);
        assert_eq!(
            memory.claim(Vector2::new(10.0, 2.0), 2.5),
            None,
            "it has walked on"
        );
        assert_eq!(memory.claim(Vector2::new(11.7, 2.1), 2.5), Some(4));
        // Not remembered for as long as a static object.
        memory.remember(5, walker, Vector2::new(1.2, 0.0), 1.3);
        memory.expire(1.3 + MOVING_MEMORY + 0.1);
        assert_eq!(memory.claim(Vector2::new(12.9, 2.0), 3.0), None);
    }

    #[test]
    fn no_memory_remembers_nothing() {
        let mut memory = DormantTracks::new(DormantConfig {
            memory: 0.0,
            radius: 1.0,
        });
        memory.remember(1, (Vector2::zeros(), 0.0), Vector2::zeros(), 0.0);
        assert_eq!(memory.claim(Vector2::zeros(), 0.0), None);
    }
}
