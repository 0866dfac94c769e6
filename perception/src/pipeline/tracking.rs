//! The pipeline's back half: a segmented scan's clusters split among the tracks that claim
//! them (a new VFH for each part), tracked; the scan's occupancy update and super frame. It
//! holds everything that lasts from scan to scan but the pose filter.

use std::ops::Range;

use super::gather::{Signature, describe, larger_than_any_object, largest_object_side};
use super::{FrameOutput, Laps, Segmented, TrackingFrame};
use crate::config::Config;
use crate::occupancy::{OccupancyMap, OccupancyScan};
use crate::superframe::{ObjectDetail, SuperFrameHeader, Trigger};
use crate::track::arrivals::{ArrivalPeeler, Scene};
use crate::track::{ClusterInput, PredictedBox, RecentViews, ScanContext, Splitter, Tracker, View};
use crate::vfh::VfhEstimator;
use crate::{Point, TrackState};

/// The clusters the tracker takes: the gathered ones, split among the tracks that claim them.
#[derive(Debug, Default)]
struct Parts {
    /// Each part's points in the scan's gathered points.
    ranges: Vec<Range<usize>>,
    /// Each part's VFH (`None`: too few points to describe).
    signatures: Vec<Option<Signature>>,
    /// The confirmed tracks' predicted boxes.
    boxes: Vec<PredictedBox>,
    /// Those of them of moving people.
    people: Vec<PredictedBox>,
    /// Scratch: the parts of one cluster.
    split: Vec<Range<usize>>,
}

/// Views are kept this much longer (s) than the oldest motion probe they may be compared with.
const VIEW_SLACK: f64 = 0.5;
/// Newcomers to a large cluster are points that stand where the newest scan at least this
/// much earlier (s) saw through: at 10 Hz the scan 0.5 s earlier, since which a pedestrian
/// has walked half a metre.
const ARRIVAL_AGE: f64 = 0.45;

/// The back half's state: tracker, recent views, occupancy map, super-frame trigger.
pub struct Tracking {
    config: Config,
    vehicle_id: String,
    splitter: Splitter,
    peeler: ArrivalPeeler,
    estimator: VfhEstimator,
    tracker: Tracker,
    occupancy: OccupancyMap,
    /// Whether scans go out in [`FrameOutput::occupancy_scan`] instead of into `occupancy`.
    hands_out_occupancy: bool,
    trigger: Trigger,
    views: RecentViews,
    parts: Parts,
}

impl Tracking {
    /// The back half with `config`, for the vehicle `vehicle_id`.
    pub fn new(config: Config, vehicle_id: String) -> Self {
        Self {
            splitter: Splitter::default(),
            peeler: ArrivalPeeler::default(),
            estimator: VfhEstimator::new(config.vfh.clone()),
            tracker: Tracker::new(config.track.clone()),
            occupancy: OccupancyMap::new(config.occupancy.clone()),
            hands_out_occupancy: false,
            trigger: Trigger::new(config.superframe.clone()),
            views: RecentViews::new(config.track.classify.motion_probe_max_age + VIEW_SLACK),
            parts: Parts::default(),
            config,
            vehicle_id,
        }
    }

    /// The configuration in use.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The tracker (every track, tentative and structure included).
    pub fn tracker(&self) -> &Tracker {
        &self.tracker
    }

    /// The occupancy map built so far.
    pub fn occupancy(&self) -> &OccupancyMap {
        &self.occupancy
    }

    /// From now on each scan's occupancy update is handed out in
    /// [`FrameOutput::occupancy_scan`], for the caller to integrate into a map of its own (e.g.
    /// on another thread, overlapping the next scans); [`Self::occupancy`] stays as it is.
    pub fn hand_out_occupancy(&mut self) {
        self.hands_out_occupancy = true;
    }

    /// Tracks one segmented scan. `scan` keeps its buffers for the next
    /// [`Segmentation::segment`](super::Segmentation::segment).
    pub fn track(&mut self, scan: &mut Segmented) -> FrameOutput {
        let mut laps = Laps::resume(std::mem::take(&mut scan.timings));
        let pose = scan.pose;
        self.split_among_tracks(scan);
        laps.lap("split");

        let with_visibility = scan.tracking_frame == TrackingFrame::World;
        if with_visibility {
            let spare = self.views.take_buffer(scan.timestamp);
            self.views.push(View {
                timestamp: scan.timestamp,
                pose,
                image: std::mem::replace(&mut scan.image, spare),
            });
        } else {
            self.views.clear();
        }

        let (parts, points) = (&self.parts, &scan.clusters.points);
        let inputs: Vec<ClusterInput<'_>> = parts
            .ranges
            .iter()
            .zip(&parts.signatures)
            .filter_map(|(r, signature)| {
                let (vfh, cdf, surface_variation) = signature.as_ref()?;
                Some(ClusterInput {
                    points: &points[r.clone()],
                    vfh,
                    cdf,
                    surface_variation: *surface_variation,
                })
            })
            .collect();
        let context = ScanContext {
            timestamp: scan.timestamp,
            pose,
            ground: &scan.ground,
            range_limit: f64::from(self.config.filter.max_range),
            views: with_visibility.then_some(&self.views),
        };
        self.tracker.step(&context, &inputs);
        let world_from_odometry = scan.world_from_odometry;
        let tracks: Vec<TrackState> = self
            .tracker
            .reported()
            .map(|t| {
                let mut state = t.state();
                state.center += world_from_odometry.vector;
                state
            })
            .collect();
        laps.lap("track");
        let ego_pose = world_from_odometry * pose;

        let mut occupancy_scan = None;
        if with_visibility {
            let sensor = pose.translation.vector;
            if self.hands_out_occupancy {
                occupancy_scan = Some(OccupancyScan {
                    sensor,
                    obstacles: scan.obstacles.clone(),
                    ground: scan.ground_points.clone(),
                });
            } else {
                self.occupancy
                    .integrate(sensor, &scan.obstacles, &scan.ground_points);
            }
        }
        laps.lap("occupancy");

        let superframe = self.trigger.poll(scan.timestamp, &tracks).map(|sequence| {
            let header = SuperFrameHeader {
                vehicle_id: &self.vehicle_id,
                sequence,
                timestamp: scan.timestamp,
                ego_pose: &ego_pose,
                origin: scan.origin.as_ref(),
                points_to_world: world_from_odometry.vector,
            };
            let details = self.tracker.reported().zip(&tracks).map(|(t, state)| {
                let points = t.cluster().map_or(&[][..], |j| inputs[j].points);
                (
                    state,
                    ObjectDetail {
                        covariance: t.covariance(),
                        vfh: &t.vfh().bins,
                        points,
                    },
                )
            });
            crate::superframe::build(&header, &self.config.superframe, details)
        });
        laps.lap("superframe");

        FrameOutput {
            index: scan.index,
            timestamp: scan.timestamp,
            ego_pose,
            odometry_pose: pose,
            tracking_frame: scan.tracking_frame,
            tracks,
            superframe,
            timings: laps.finish(),
            counts: scan.counts.clone(),
            occupancy_scan,
        }
    }

    /// Splits each gathered cluster of `scan` that several confirmed tracks' predicted boxes
    /// claim among them, or that newcomers are peeled off, describing the new parts; the
    /// others keep their VFH. Moving people and newcomers are peeled off the clusters larger
    /// than any object too (a walker along a facade), whose rest stays with the map.
    fn split_among_tracks(&mut self, scan: &mut Segmented) {
        let p = &mut self.parts;
        p.boxes.clear();
        p.boxes.extend(self.tracker.predicted_boxes(scan.timestamp));
        p.ranges.clear();
        p.signatures.clear();
        // The earlier scan newcomers are told by (the current one is not among the views yet).
        let then = (scan.tracking_frame == TrackingFrame::World)
            .then(|| self.views.before(scan.timestamp, ARRIVAL_AGE))
            .flatten();
        let viewpoint = scan.pose.translation.vector;
        let viewpoint = [viewpoint.x, viewpoint.y, viewpoint.z];
        let scene = Scene {
            ground: &scan.ground,
            sensor: [viewpoint[0], viewpoint[1]],
            boxes: &p.boxes,
        };
        let estimator = &mut self.estimator;
        let mut describe_part = |points: &[Point]| describe(estimator, points, viewpoint);
        let (splitter, peeler) = (&mut self.splitter, &mut self.peeler);
        // A cluster is shared out among the boxes that claim it, or else its newcomers are
        // peeled off it.
        let mut split_or_peel =
            |points: &mut [Point], boxes: &[PredictedBox], split: &mut Vec<Range<usize>>| {
                split.clear();
                splitter.split(points, boxes, split);
                if let (1, Some(then)) = (split.len(), then) {
                    split.clear();
                    peeler.split(points, then, &scene, split);
                }
            };
        let split_merged = self.config.track.split_merged_clusters;
        let clusters = &mut scan.clusters;
        for (r, signature) in clusters.ranges.iter().zip(&mut clusters.signatures) {
            p.split.clear();
            if split_merged {
                split_or_peel(&mut clusters.points[r.clone()], &p.boxes, &mut p.split);
            }
            if p.split.len() <= 1 {
                p.ranges.push(r.clone());
                p.signatures.push(signature.take());
                continue;
            }
            let out = (&mut p.ranges, &mut p.signatures);
            push_parts(
                &p.split,
                &clusters.points,
                r.start,
                None,
                out,
                &mut describe_part,
            );
        }
        if !split_merged {
            return;
        }
        // Only a moving person's box claims a part of what is larger than any object: a
        // parked car's box would take the facade behind it.
        p.people.clear();
        p.people
            .extend(p.boxes.iter().filter(|b| b.moving_person).copied());
        let largest = Some(largest_object_side(&self.config));
        for r in &clusters.oversized {
            split_or_peel(&mut clusters.points[r.clone()], &p.people, &mut p.split);
            if p.split.len() <= 1 {
                continue;
            }
            let out = (&mut p.ranges, &mut p.signatures);
            push_parts(
                &p.split,
                &clusters.points,
                r.start,
                largest,
                out,
                &mut describe_part,
            );
        }
    }
}

/// Appends the parts `split` (relative to `start` in `points`) to the tracker's parts `out`
/// (ranges, signatures), each described anew, but those reaching farther than `largest` (m)
/// along x or y.
fn push_parts(
    split: &[Range<usize>],
    points: &[Point],
    start: usize,
    largest: Option<f32>,
    out: (&mut Vec<Range<usize>>, &mut Vec<Option<Signature>>),
    describe_part: &mut impl FnMut(&[Point]) -> Option<Signature>,
) {
    let (ranges, signatures) = out;
    for part in split {
        let part = start + part.start..start + part.end;
        let points = &points[part.clone()];
        if largest.is_some_and(|largest| larger_than_any_object(points, largest)) {
            continue;
        }
        signatures.push(describe_part(points));
        ranges.push(part);
    }
}
