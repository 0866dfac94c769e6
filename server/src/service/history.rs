//! Where each track has been: a bounded list of positions per track.

use std::collections::{HashMap, VecDeque};

use trackd_client::api::TrackPoint;
use trackd_perception::TrackState;

/// Tracks unseen for this many frames are forgotten.
const FORGET_AFTER_FRAMES: u64 = 100;

/// Positions of recent tracks.
pub struct History {
    per_track: HashMap<u64, (u64, VecDeque<TrackPoint>)>,
    capacity: usize,
}

impl History {
    /// Keeps at most `capacity` positions per track.
    pub fn new(capacity: usize) -> Self {
        Self {
            per_track: HashMap::new(),
            capacity: capacity.max(1),
        }
    }

    /// Records the tracks of frame `frame` taken at `timestamp`.
    pub fn record(&mut self, frame: u64, timestamp: f64, tracks: &[TrackState]) {
        for t in tracks {
            let (last, points) = self.per_track.entry(t.id).or_default();
            *last = frame;
            if points.len() == self.capacity {
                points.pop_front();
            }
            points.push_back(TrackPoint {
                frame,
                timestamp,
                x: t.center.x,
                y: t.center.y,
                z: t.center.z,
            });
        }
        self.per_track
            .retain(|_, (last, _)| frame.saturating_sub(*last) <= FORGET_AFTER_FRAMES);
    }

    /// The positions of track `id`, oldest first.
    pub fn of(&self, id: u64) -> Option<Vec<TrackPoint>> {
        self.per_track
            .get(&id)
            .map(|(_, points)| points.iter().cloned().collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Vector2, Vector3};
    use trackd_perception::ObjectClass;

    fn track(id: u64, x: f64) -> TrackState {
        TrackState {
            id,
            class: ObjectClass::Car,
            center: Vector3::new(x, 0.0, 0.0),
            size: Vector3::new(4.0, 2.0, 1.5),
            yaw: 0.0,
            velocity: Vector2::zeros(),
            confidence: 1.0,
            age: 1,
            hits: 1,
        }
    }

    #[test]
    fn keeps_the_latest_positions_and_forgets_old_tracks() {
        let mut h = History::new(2);
        h.record(0, 0.0, &[track(1, 0.0), track(2, 5.0)]);
        h.record(1, 0.1, &[track(1, 1.0)]);
        h.record(2, 0.2, &[track(1, 2.0)]);
        let xs: Vec<f64> = h.of(1).expect("track 1").iter().map(|p| p.x).collect();
        assert_eq!(xs, [1.0, 2.0]);
        assert_eq!(h.of(2).expect("track 2").len(), 1);
        h.record(200, 20.0, &[track(1, 3.0)]);
        assert!(h.of(2).is_none());
        assert!(h.of(3).is_none());
    }
}
