//! The pipeline's back half: a segmented scan's clusters gathered (fragments joined, merged
//! objects split), described by their VFH, tracked; the scan's occupancy update and super
//! frame. It holds everything that lasts from scan to scan but the pose filter.

use std::ops::Range;

use nalgebra::Isometry3;
use rayon::prelude::*;

use super::{FrameOutput, Laps, Segmented, TrackingFrame};
use crate::config::Config;
use crate::occupancy::{OccupancyMap, OccupancyScan};
use crate::superframe::{ObjectDetail, SuperFrameHeader, Trigger};
use crate::track::fragments::{Bounds, stacked_groups};
use crate::track::person_split::{PersonShape, PersonSplitter};
use crate::track::{ClusterInput, PredictedBox, RecentViews, ScanContext, Splitter, Tracker, View};
use crate::vfh::{BINS, Vfh, VfhEstimator};
use crate::{Point, TrackState};

/// What VFH tells of one cluster: its histogram, the histogram's CDF and the cluster's surface
/// variation.
type Signature = (Vfh, [f32; BINS], f32);

/// The clusters of one scan, gathered contiguously: what VFH and tracking read.
#[derive(Debug, Default)]
struct Clusters {
    /// Points of every cluster, one after the other (world frame).
    points: Vec<Point>,
    /// Each cluster's points.
    ranges: Vec<Range<usize>>,
    /// Each cluster's VFH and its CDF (`None`: too few points to describe).
    signatures: Vec<Option<Signature>>,
}

/// Reusable buffers of the stages.
#[derive(Debug, Default)]
struct Buffers {
    bounds: Vec<Bounds>,
    groups: Vec<usize>,
    group_ranges: Vec<Range<usize>>,
    boxes: Vec<PredictedBox>,
    people: Vec<Range<usize>>,
    clusters: Clusters,
    /// Which entry of `clusters` each tracker input is.
    described: Vec<usize>,
}

/// Views are kept this much longer (s) than the oldest motion probe they may be compared with.
const VIEW_SLACK: f64 = 0.5;

/// The back half's state: tracker, recent views, occupancy map, super-frame trigger.
pub struct Tracking {
    config: Config,
    vehicle_id: String,
    person_splitter: PersonSplitter,
    splitter: Splitter,
    tracker: Tracker,
    occupancy: OccupancyMap,
    /// Whether scans go out in [`FrameOutput::occupancy_scan`] instead of into `occupancy`.
    hands_out_occupancy: bool,
    trigger: Trigger,
    views: RecentViews,
    buffers: Buffers,
}

impl Tracking {
    /// The back half with `config`, for the vehicle `vehicle_id`.
    pub fn new(config: Config, vehicle_id: String) -> Self {
        Self {
            person_splitter: PersonSplitter::default(),
            splitter: Splitter::default(),
            tracker: Tracker::new(config.track.clone()),
            occupancy: OccupancyMap::new(config.occupancy.clone()),
            hands_out_occupancy: false,
            trigger: Trigger::new(config.superframe.clone()),
            views: RecentViews::new(config.track.classify.motion_probe_max_age + VIEW_SLACK),
            buffers: Buffers::default(),
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
        self.gather_clusters(scan);
        laps.lap("gather");
        self.describe_clusters(&pose);
        laps.lap("vfh");

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

        let b = &self.buffers;
        let c = &b.clusters;
        let inputs: Vec<ClusterInput<'_>> = b
            .described
            .iter()
            .filter_map(|&k| {
                let (vfh, cdf, surface_variation) = c.signatures[k].as_ref()?;
                Some(ClusterInput {
                    points: &c.points[c.ranges[k].clone()],
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

    /// Gathers DBSCAN's clusters into `clusters`: stacked fragments of one object joined,
    /// clusters larger than any object left to the map, people a gap away peeled off,
    /// clusters holding several confirmed tracks' predicted boxes split among them.
    fn gather_clusters(&mut self, scan: &Segmented) {
        let (timestamp, sensor) = (scan.timestamp, scan.pose.translation.vector);
        let b = &mut self.buffers;
        let classify = &self.config.track.classify;
        b.bounds.clear();
        for members in scan.clustering.clusters() {
            let points = members.iter().map(|&i| &scan.obstacles[i as usize]);
            b.bounds.push(Bounds::of(points));
        }
        stacked_groups(&b.bounds, &mut b.groups);
        // Order the members by group: a counting sort over the clusters' member lists.
        let group_count = b.groups.iter().max().map_or(0, |g| g + 1);
        b.group_ranges.clear();
        b.group_ranges.resize(group_count, 0..0);
        let mut sizes = vec![0usize; group_count];
        for (k, members) in scan.clustering.clusters().enumerate() {
            sizes[b.groups[k]] += members.len();
        }
        let mut start = 0;
        for (g, size) in sizes.iter().enumerate() {
            b.group_ranges[g] = start..start;
            start += size;
        }
        let c = &mut b.clusters;
        c.points.clear();
        c.points.resize(start, Point::default());
        for (k, members) in scan.clustering.clusters().enumerate() {
            let r = &mut b.group_ranges[b.groups[k]];
            for &i in members {
                c.points[r.end] = scan.obstacles[i as usize];
                r.end += 1;
            }
        }
        b.boxes.clear();
        b.boxes.extend(self.tracker.predicted_boxes(timestamp));
        c.ranges.clear();
        let largest = classify.max_object_length as f32 * std::f32::consts::SQRT_2;
        let person = PersonShape::of(classify);
        let sensor = [sensor.x, sensor.y];
        for r in &b.group_ranges {
            let bounds = Bounds::of(&c.points[r.clone()]);
            let too_large =
                bounds.max[0] - bounds.min[0] > largest || bounds.max[1] - bounds.min[1] > largest;
            if too_large {
                continue;
            }
            let before = c.ranges.len();
            if self.config.track.split_merged_clusters {
                b.people.clear();
                self.person_splitter.split(
                    &mut c.points[r.clone()],
                    sensor,
                    &scan.ground,
                    &person,
                    &mut b.people,
                );
                for person in &b.people {
                    let part = r.start + person.start..r.start + person.end;
                    let first = c.ranges.len();
                    self.splitter
                        .split(&mut c.points[part.clone()], &b.boxes, &mut c.ranges);
                    for p in &mut c.ranges[first..] {
                        *p = part.start + p.start..part.start + p.end;
                    }
                }
            } else {
                c.ranges.push(r.clone());
            }
            debug_assert!(c.ranges[before..].iter().all(|p| p.end <= r.end));
        }
    }

    /// Computes the VFH of every gathered cluster, in parallel.
    fn describe_clusters(&mut self, pose: &Isometry3<f64>) {
        let b = &mut self.buffers;
        let c = &mut b.clusters;
        let viewpoint = pose.translation.vector;
        let viewpoint = [viewpoint.x, viewpoint.y, viewpoint.z];
        let config = &self.config.vfh;
        let points = &c.points;
        c.ranges
            .par_iter()
            .map_init(
                || VfhEstimator::new(config.clone()),
                |estimator, r| {
                    estimator
                        .compute(&points[r.clone()], viewpoint)
                        .map(|vfh| (vfh, vfh.cdf(), estimator.surface_variation()))
                },
            )
            .collect_into_vec(&mut c.signatures);
        b.described.clear();
        b.described
            .extend((0..c.ranges.len()).filter(|&k| c.signatures[k].is_some()));
    }
}
