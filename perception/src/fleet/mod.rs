//! Fleet fusion: remote vehicles' super frames and this vehicle's tracks as one world view.
//!
//! Pure logic, no I/O and no clock: the caller (the service) passes the time of each event in
//! milliseconds of its own monotonic clock. Tracking never depends on this; only how long
//! remote objects are kept and how far they are predicted does.

mod config;
mod fuse;
mod origin;
mod remote;

use std::collections::BTreeMap;

use nalgebra::Vector2;
use trackd_proto::SuperFrame;

pub use config::FusionConfig;
pub use fuse::{FusedObject, Observation, fuse};
pub use origin::{OriginShift, distance_m, is_plausible};
pub use remote::{MAX_VEHICLE_ID_LEN, Rejection, is_valid_vehicle_id, objects_in_fleet_frame};

use crate::{TrackState, geo::GeoOrigin};

/// What is known of one remote vehicle.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RemoteVehicle {
    /// Whether its liveliness token is present.
    pub alive: bool,
    /// When its last super frame arrived (ms).
    pub last_seen_ms: Option<u64>,
    /// Sequence number of its last super frame.
    pub sequence: Option<u64>,
    /// Scan timestamp of its last super frame (its clock, seconds).
    pub timestamp: Option<f64>,
    /// Publish → receive delay of its last super frame (ms), when the transport told it.
    pub lag_ms: Option<f64>,
    /// Super frames accepted from it.
    pub superframes: u64,
    /// Objects of its last super frame, in the fleet frame; emptied when it expires.
    pub objects: Vec<TrackState>,
}

/// This vehicle's view of the fleet.
pub struct Fusion {
    own_id: String,
    origin: Option<GeoOrigin>,
    config: FusionConfig,
    remotes: BTreeMap<String, RemoteVehicle>,
}

impl Fusion {
    /// Fusion for vehicle `own_id` in the world frame of `origin` (the fleet's).
    pub fn new(own_id: impl Into<String>, origin: Option<GeoOrigin>, config: FusionConfig) -> Self {
        Self {
            own_id: own_id.into(),
            origin,
            config,
            remotes: BTreeMap::new(),
        }
    }

    /// The configuration in use.
    pub fn config(&self) -> &FusionConfig {
        &self.config
    }

    /// Takes in a remote super frame that arrived at `now_ms`, `lag_ms` after it was sent.
    /// Returns how many objects it holds, or why it was refused (state unchanged then).
    pub fn ingest(
        &mut self,
        frame: &SuperFrame,
        now_ms: u64,
        lag_ms: Option<f64>,
    ) -> Result<usize, Rejection> {
        let objects =
            objects_in_fleet_frame(frame, &self.own_id, self.origin.as_ref(), &self.config)?;
        let count = objects.len();
        let vehicle = self.remotes.entry(frame.vehicle_id.clone()).or_default();
        vehicle.last_seen_ms = Some(now_ms);
        vehicle.sequence = Some(frame.sequence);
        vehicle.timestamp = Some(frame.timestamp);
        vehicle.lag_ms = lag_ms;
        vehicle.superframes += 1;
        vehicle.objects = objects;
        Ok(count)
    }

    /// Records that `vehicle`'s liveliness token appeared (`alive`) or vanished. A vanished
    /// vehicle's objects expire at once.
    pub fn set_alive(&mut self, vehicle: &str, alive: bool) {
        if vehicle == self.own_id || !is_valid_vehicle_id(vehicle) {
            return;
        }
        let v = self.remotes.entry(vehicle.to_string()).or_default();
        v.alive = alive;
        if !alive {
            v.objects.clear();
        }
    }

    /// Drops the objects of vehicles silent for longer than the TTL at `now_ms`.
    pub fn expire(&mut self, now_ms: u64) {
        for v in self.remotes.values_mut() {
            let silent = v
                .last_seen_ms
                .is_none_or(|t| now_ms.saturating_sub(t) > self.config.ttl_ms);
            if silent {
                v.objects.clear();
            }
        }
    }

    /// Remote vehicles heard of, by id.
    pub fn vehicles(&self) -> &BTreeMap<String, RemoteVehicle> {
        &self.remotes
    }

    /// The fused view at `now_ms`, given this vehicle's latest tracks, made `own_age_ms` ago.
    /// Expired vehicles are left out (call [`Fusion::expire`] to also free their objects).
    pub fn view(
        &self,
        own_tracks: &[TrackState],
        own_age_ms: u64,
        now_ms: u64,
    ) -> Vec<FusedObject> {
        let mut groups = Vec::with_capacity(1 + self.remotes.len());
        groups.push(
            own_tracks
                .iter()
                .map(|t| self.observation(&self.own_id, t, own_age_ms))
                .collect(),
        );
        for (id, v) in &self.remotes {
            let Some(seen) = v.last_seen_ms else { continue };
            let age_ms = now_ms.saturating_sub(seen);
            if age_ms > self.config.ttl_ms {
                continue;
            }
            groups.push(
                v.objects
                    .iter()
                    .map(|o| self.observation(id, o, age_ms))
                    .collect(),
            );
        }
        fuse(&groups, self.config.gate_m)
    }

    /// An observation brought to the present along its velocity (for at most the configured
    /// prediction horizon).
    fn observation(&self, vehicle: &str, o: &TrackState, age_ms: u64) -> Observation {
        let dt = age_ms.min(self.config.max_prediction_ms) as f64 / 1000.0;
        let shift: Vector2<f64> = o.velocity * dt;
        let mut center = o.center;
        center.x += shift.x;
        center.y += shift.y;
        Observation {
            vehicle: vehicle.to_string(),
            track: o.id,
            class: o.class,
            center,
            size: o.size,
            yaw: o.yaw,
            velocity: o.velocity,
            confidence: o.confidence,
            age_ms,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ObjectClass;
    use nalgebra::Vector3;
    use trackd_proto::{Box3, GeoPoint, TrackedObject};

    const ORIGIN: GeoOrigin = GeoOrigin::new(49.011_213_954_206, 8.422_885_922_889_3, 112.83);

    fn frame(vehicle: &str, objects: &[(u64, f64, f64)]) -> SuperFrame {
        SuperFrame {
            version: trackd_proto::SCHEMA_VERSION,
            vehicle_id: vehicle.into(),
            sequence: 1,
            timestamp: 0.5,
            ego_pose: None,
            origin: Some(GeoPoint {
                lat: ORIGIN.lat,
                lon: ORIGIN.lon,
                alt: ORIGIN.alt,
            }),
            objects: objects
                .iter()
                .map(|&(id, x, y)| TrackedObject {
                    id,
                    class: trackd_proto::ObjectClass::Car as i32,
                    r#box: Some(Box3 {
                        x,
                        y,
                        z: 0.8,
                        l: 4.0,
                        w: 1.8,
                        h: 1.5,
                        yaw: 0.0,
                    }),
                    vx: 1.0,
                    vy: 0.0,
                    confidence: 0.8,
                    ..Default::default()
                })
                .collect(),
        }
    }

    fn own_track(id: u64, x: f64, y: f64) -> TrackState {
        TrackState {
            id,
            class: ObjectClass::Car,
            center: Vector3::new(x, y, 0.8),
            size: Vector3::new(4.0, 1.8, 1.5),
            yaw: 0.0,
            velocity: Vector2::zeros(),
            confidence: 0.9,
            age: 5,
            hits: 5,
        }
    }

    #[test]
    fn remote_objects_join_own_tracks_and_expire_after_the_ttl() {
        let mut f = Fusion::new("a", Some(ORIGIN), FusionConfig::default());
        f.set_alive("b", true);
        assert_eq!(
            f.ingest(&frame("b", &[(3, 10.0, 0.0), (4, 50.0, 2.0)]), 1_000, None),
            Ok(2)
        );
        let own = [own_track(1, 10.3, 0.0)];
        let view = f.view(&own, 0, 1_100);
        assert_eq!(view.len(), 2);
        assert_eq!(view[0].sources, ["a", "b"]);
        assert_eq!(view[1].sources, ["b"]);
        // Predicted 100 ms along vx = 1 m/s.
        assert!(
            (view[1].center.x - 50.1).abs() < 1e-9,
            "{}",
            view[1].center.x
        );
        assert_eq!(view[1].age_ms, 100);
        // Past the TTL: only own tracks remain.
        assert_eq!(f.view(&own, 0, 3_001).len(), 1);
        f.expire(3_001);
        assert!(f.vehicles()["b"].objects.is_empty());
    }

    #[test]
    fn lost_liveliness_expires_at_once_and_a_new_frame_rejoins() {
        let mut f = Fusion::new("a", Some(ORIGIN), FusionConfig::default());
        f.ingest(&frame("b", &[(3, 10.0, 0.0)]), 0, None)
            .expect("accepted");
        f.set_alive("b", false);
        assert!(f.view(&[], 0, 10).is_empty());
        f.set_alive("b", true);
        f.ingest(&frame("b", &[(3, 10.0, 0.0)]), 20, None)
            .expect("accepted");
        assert_eq!(f.view(&[], 0, 30).len(), 1);
        assert_eq!(f.vehicles()["b"].superframes, 2);
    }

    #[test]
    fn malformed_frames_are_refused_and_change_nothing() {
        let mut f = Fusion::new("a", Some(ORIGIN), FusionConfig::default());
        let mut no_version = frame("b", &[(1, 0.0, 0.0)]);
        no_version.version = 0;
        let mut nan = frame("b", &[(1, 0.0, 0.0)]);
        if let Some(b) = nan.objects[0].r#box.as_mut() {
            b.x = f64::NAN;
        }
        let mut far = frame("b", &[(1, 0.0, 0.0)]);
        far.origin = Some(GeoPoint {
            lat: 40.0,
            lon: -74.0,
            alt: 10.0,
        });
        let mut no_origin = frame("b", &[(1, 0.0, 0.0)]);
        no_origin.origin = None;
        let too_many = frame("b", &vec![(1, 0.0, 0.0); 1_001]);
        let reasons: Vec<&str> = [
            no_version,
            nan,
            far,
            no_origin,
            too_many,
            frame("a", &[]),
            frame("b/x", &[]),
        ]
        .iter()
        .map(|fr| f.ingest(fr, 0, None).expect_err("refused").reason())
        .collect();
        assert_eq!(
            reasons,
            [
                "no_version",
                "bad_object",
                "origin_too_far",
                "bad_origin",
                "too_many_objects",
                "own",
                "bad_vehicle_id"
            ]
        );
        assert!(f.vehicles().is_empty());
    }

    #[test]
    fn a_frame_in_a_nearby_origin_is_converted() {
        let mut f = Fusion::new("a", Some(ORIGIN), FusionConfig::default());
        let other = GeoOrigin::new(49.012, 8.425, 110.0);
        let mut fr = frame("b", &[(1, 0.0, 0.0)]);
        fr.origin = Some(GeoPoint {
            lat: other.lat,
            lon: other.lon,
            alt: other.alt,
        });
        f.ingest(&fr, 0, None).expect("accepted");
        let o = &f.vehicles()["b"].objects[0];
        let expected = ORIGIN.to_local(other.lat, other.lon, other.alt + 0.8);
        assert!(
            (o.center - expected).norm() < 1e-6,
            "{} vs {expected}",
            o.center
        );
    }
}
