//! Super frames (the paper's Algorithm 2, last step): at a trigger — every `period` seconds of
//! scan time, or as soon as a track reaches high confidence for the first time — the
//! high-confidence tracks, with their boxes, motion covariance, VFH and a voxel-down-sampled
//! point set, become the protobuf message a vehicle broadcasts to the fleet.

use nalgebra::{Isometry3, Vector3};
use rustc_hash::{FxHashMap, FxHashSet};
use serde::{Deserialize, Serialize};
use trackd_proto as proto;

use crate::{Point, TrackState, geo::GeoOrigin, wire};

/// When super frames are made and what goes in them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SuperFrameConfig {
    /// Seconds of scan time between two super frames.
    pub period: f64,
    /// Tracks at or above this confidence are shared.
    pub min_confidence: f32,
    /// Voxel edge (metres) of the down-sampled points shared per object.
    pub voxel: f64,
    /// At most this many points per object.
    pub max_points: usize,
}

impl Default for SuperFrameConfig {
    fn default() -> Self {
        Self {
            period: 1.0,
            min_confidence: 0.6,
            voxel: 0.2,
            max_points: 256,
        }
    }
}

/// Decides when a super frame is due and numbers them.
#[derive(Debug)]
pub struct Trigger {
    config: SuperFrameConfig,
    last: Option<f64>,
    announced: FxHashSet<u64>,
    next_sequence: u64,
}

impl Trigger {
    /// A trigger that fires at the first high-confidence track.
    pub fn new(config: SuperFrameConfig) -> Self {
        Self {
            config,
            last: None,
            announced: FxHashSet::default(),
            next_sequence: 0,
        }
    }

    /// The parameters in use.
    pub fn config(&self) -> &SuperFrameConfig {
        &self.config
    }

    /// The sequence number of the super frame due at `timestamp` given the current tracks, or
    /// `None`: due when `period` has passed since the last one, or when a track is at high
    /// confidence for the first time. Nothing is due while no track is at high confidence.
    pub fn poll(&mut self, timestamp: f64, tracks: &[TrackState]) -> Option<u64> {
        let mut newcomer = false;
        let mut any = false;
        for t in tracks
            .iter()
            .filter(|t| t.confidence >= self.config.min_confidence)
        {
            any = true;
            newcomer |= self.announced.insert(t.id);
        }
        let period_over = self
            .last
            .is_none_or(|last| timestamp - last >= self.config.period);
        if !any || !(newcomer || period_over) {
            return None;
        }
        // Forget tracks that are gone, so the set stays as small as the track list.
        let alive: FxHashSet<u64> = tracks.iter().map(|t| t.id).collect();
        self.announced.retain(|id| alive.contains(id));
        self.last = Some(timestamp);
        self.next_sequence += 1;
        Some(self.next_sequence - 1)
    }
}

/// What the tracker adds to a track for the super frame.
pub struct ObjectDetail<'a> {
    /// Row-major covariance of the motion state [x, y, z, vx, vy, yaw].
    pub covariance: [f64; 36],
    /// The latest cluster's VFH (308 bins).
    pub vfh: &'a [f32],
    /// The latest cluster's points in the tracking frame (see
    /// [`SuperFrameHeader::points_to_world`]).
    pub points: &'a [Point],
}

/// The super frame of the tracks at or above `config.min_confidence`.
pub struct SuperFrameHeader<'a> {
    /// The broadcasting vehicle.
    pub vehicle_id: &'a str,
    /// From [`Trigger::poll`].
    pub sequence: u64,
    /// Scan time (seconds).
    pub timestamp: f64,
    /// Pose of the vehicle's Velodyne frame in the world frame.
    pub ego_pose: &'a Isometry3<f64>,
    /// The world frame's geodetic origin, when known.
    pub origin: Option<&'a GeoOrigin>,
    /// Added to the objects' points to place them in the world frame: the tracker works in
    /// the odometry frame (see `PoseEstimator::odometry`); the tracks come already placed.
    pub points_to_world: Vector3<f64>,
}

/// Builds the message from the tracks and, per track, the detail the tracker holds.
pub fn build<'a>(
    header: &SuperFrameHeader<'_>,
    config: &SuperFrameConfig,
    tracks: impl IntoIterator<Item = (&'a TrackState, ObjectDetail<'a>)>,
) -> proto::SuperFrame {
    let objects = tracks
        .into_iter()
        .filter(|(t, _)| t.confidence >= config.min_confidence)
        .map(|(t, d)| {
            let mut points = voxel_downsample(d.points, config.voxel, config.max_points);
            let shift = header.points_to_world.cast::<f32>();
            for p in &mut points {
                p.x += shift.x;
                p.y += shift.y;
                p.z += shift.z;
            }
            wire::track_to_proto(t, &d.covariance, d.vfh, wire::pack_xyz(&points))
        })
        .collect();
    proto::SuperFrame {
        version: proto::SCHEMA_VERSION,
        vehicle_id: header.vehicle_id.to_string(),
        sequence: header.sequence,
        timestamp: header.timestamp,
        ego_pose: Some(wire::pose_to_proto(header.ego_pose)),
        origin: header.origin.map(wire::origin_to_proto),
        objects,
    }
}

/// The centroid of the points in each occupied voxel of edge `voxel`, at most `max` of them
/// (evenly thinned), in a deterministic order.
pub fn voxel_downsample(points: &[Point], voxel: f64, max: usize) -> Vec<Point> {
    let inv = 1.0 / voxel;
    let mut cells: FxHashMap<[i32; 3], (usize, [f64; 3], usize)> = FxHashMap::default();
    for (i, p) in points.iter().enumerate() {
        let key = [p.x, p.y, p.z].map(|v| (f64::from(v) * inv).floor() as i32);
        let cell = cells.entry(key).or_insert((i, [0.0; 3], 0));
        cell.1[0] += f64::from(p.x);
        cell.1[1] += f64::from(p.y);
        cell.1[2] += f64::from(p.z);
        cell.2 += 1;
    }
    let mut cells: Vec<_> = cells.into_values().collect();
    cells.sort_unstable_by_key(|(first, _, _)| *first);
    let stride = cells.len().div_ceil(max.max(1)).max(1);
    cells
        .iter()
        .step_by(stride)
        .map(|(_, s, n)| {
            let n = *n as f64;
            Point::new((s[0] / n) as f32, (s[1] / n) as f32, (s[2] / n) as f32, 0.0)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use nalgebra::{Vector2, Vector3};

    use super::*;
    use crate::ObjectClass;

    fn track(id: u64, confidence: f32) -> TrackState {
        TrackState {
            id,
            class: ObjectClass::Car,
            center: Vector3::new(id as f64, 0.0, 0.8),
            size: Vector3::new(4.2, 1.8, 1.5),
            yaw: 0.0,
            velocity: Vector2::zeros(),
            confidence,
            age: 5,
            hits: 5,
        }
    }

    #[test]
    fn fires_on_a_new_confident_track_then_by_period() {
        let mut trigger = Trigger::new(SuperFrameConfig::default());
        assert_eq!(
            trigger.poll(0.0, &[track(1, 0.3)]),
            None,
            "no confident track yet"
        );
        assert_eq!(
            trigger.poll(0.1, &[track(1, 0.7)]),
            Some(0),
            "first confident track"
        );
        assert_eq!(
            trigger.poll(0.2, &[track(1, 0.8)]),
            None,
            "already announced"
        );
        assert_eq!(
            trigger.poll(0.3, &[track(1, 0.8), track(2, 0.9)]),
            Some(1),
            "a newcomer"
        );
        assert_eq!(trigger.poll(1.2, &[track(1, 0.8)]), None, "period not over");
        assert_eq!(trigger.poll(1.3, &[track(1, 0.8)]), Some(2), "period over");
        assert_eq!(
            trigger.poll(5.0, &[track(1, 0.1)]),
            None,
            "nothing confident to share"
        );
    }

    #[test]
    fn builds_only_confident_objects_with_thinned_points() {
        let cloud: Vec<Point> = (0..1000)
            .map(|i| {
                Point::new(
                    (i % 10) as f32 * 0.05,
                    (i / 10 % 10) as f32 * 0.05,
                    (i / 100) as f32 * 0.05,
                    0.0,
                )
            })
            .collect();
        let vfh = [1.0f32; 308];
        let tracks = [track(1, 0.9), track(2, 0.2)];
        let pose = Isometry3::identity();
        let origin = GeoOrigin::new(49.0, 8.4, 110.0);
        let header = SuperFrameHeader {
            vehicle_id: "car-1",
            sequence: 4,
            timestamp: 12.5,
            ego_pose: &pose,
            origin: Some(&origin),
            points_to_world: Vector3::zeros(),
        };
        let cfg = SuperFrameConfig::default();
        let detail = || ObjectDetail {
            covariance: [0.0; 36],
            vfh: &vfh,
            points: &cloud,
        };
        let sf = build(&header, &cfg, tracks.iter().map(|t| (t, detail())));
        assert_eq!(
            (sf.vehicle_id.as_str(), sf.sequence, sf.version),
            ("car-1", 4, proto::SCHEMA_VERSION)
        );
        assert_eq!(sf.objects.len(), 1);
        let pts = wire::unpack_xyz(&sf.objects[0].points).unwrap();
        // A 0.5 m cube at 0.2 m voxels: 3 x 3 x 3 cells.
        assert_eq!(pts.len(), 27);
        assert_eq!(sf.objects[0].vfh.len(), 308);
    }

    #[test]
    fn downsampling_caps_the_count() {
        let line: Vec<Point> = (0..1000)
            .map(|i| Point::new(i as f32 * 0.3, 0.0, 0.0, 0.0))
            .collect();
        let kept = voxel_downsample(&line, 0.2, 100);
        assert_eq!(kept.len(), 100);
        assert!(
            kept.windows(2).all(|w| w[1].x > w[0].x),
            "order follows the input"
        );
    }
}
