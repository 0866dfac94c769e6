//! The paper's Algorithm 2 for one vehicle: pose → filter → ground → world → DBSCAN → VFH →
//! tracking → occupancy → super frame, one scan at a time. Every buffer is kept from scan to
//! scan, so a steady stream of scans allocates next to nothing.

use std::ops::Range;
use std::time::Instant;

use nalgebra::{Isometry3, Translation3, Vector3};
use rayon::prelude::*;
use thiserror::Error;

use crate::cluster::{ClusterError, Clustering, Dbscan};
use crate::filter::Filter;
use crate::ground::GroundRemoval;
use crate::occupancy::{OccupancyMap, OccupancyScan};
use crate::pose::{PoseError, PoseEstimator};
use crate::superframe::{ObjectDetail, SuperFrameHeader, Trigger};
use crate::track::fragments::{Bounds, stacked_groups};
use crate::track::person_split::{PersonShape, PersonSplitter};
use crate::track::{
    ClusterInput, Ground, PredictedBox, RecentViews, ScanContext, Splitter, Tracker, View,
};
use crate::transform::to_world;
use crate::vfh::{BINS, Vfh, VfhEstimator};
use crate::{Ego, Frame, Point, StageTimings, TrackState, config::Config, geo::GeoOrigin};

/// Who runs the pipeline and where its world frame is.
#[derive(Clone, Debug)]
pub struct Vehicle {
    /// The vehicle's id in the fleet (Zenoh key, super frames).
    pub id: String,
    /// The fleet's geodetic origin; `None`: the first GPS fix becomes the origin.
    pub origin: Option<GeoOrigin>,
    /// KITTI's `Tr_imu_to_velo`: maps IMU coordinates to Velodyne coordinates.
    pub imu_to_velo: Isometry3<f64>,
}

/// The frame the tracks are expressed in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TrackingFrame {
    /// The fleet's world frame (a pose was known).
    World,
    /// The sensor frame of each scan (no pose source).
    Sensor,
}

/// The sensor pose of one scan as the pipeline uses it.
struct EgoPose {
    /// In the odometry frame every stage works in: continuous from scan to scan.
    odometry: Isometry3<f64>,
    /// Places the odometry frame in the world frame the outputs are in.
    world_from_odometry: Translation3<f64>,
    /// What the tracks are expressed in.
    frame: TrackingFrame,
}

/// Point and cluster counts of one frame.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct FrameCounts {
    /// Points in the scan.
    pub points: usize,
    /// Points left after range filtering.
    pub filtered: usize,
    /// Points left after ground removal.
    pub non_ground: usize,
    /// DBSCAN clusters.
    pub clusters: usize,
}

/// What one processed scan yields.
#[derive(Clone, Debug)]
pub struct FrameOutput {
    /// 0-based index of the scan in this pipeline's input.
    pub index: u64,
    /// The scan's timestamp (seconds).
    pub timestamp: f64,
    /// Pose of the Velodyne frame in the world frame (identity when tracking in the sensor frame).
    pub ego_pose: Isometry3<f64>,
    /// The same pose in the odometry frame the tracker works in (see
    /// [`PoseEstimator::odometry`]); equal to `ego_pose` unless OXTS drives the pose.
    pub odometry_pose: Isometry3<f64>,
    /// The frame the tracks are expressed in.
    pub tracking_frame: TrackingFrame,
    /// Confirmed object tracks (static structure excluded), in the world frame.
    pub tracks: Vec<TrackState>,
    /// The super frame this scan triggered, if any.
    pub superframe: Option<trackd_proto::SuperFrame>,
    /// Wall time per stage.
    pub timings: StageTimings,
    /// Point and cluster counts.
    pub counts: FrameCounts,
    /// The scan's update of the occupancy map, when the pipeline hands it out (see
    /// [`Pipeline::hand_out_occupancy`]) instead of integrating it.
    pub occupancy_scan: Option<OccupancyScan>,
}

/// Why a scan could not be processed. The pipeline's tracks are unchanged when this is
/// returned.
#[derive(Debug, Error)]
pub enum PipelineError {
    /// The scan's timestamp is not after the previous scan's.
    #[error("scan timestamp {got} is not after the previous one ({previous})")]
    TimeNotIncreasing {
        /// The previous timestamp.
        previous: f64,
        /// The rejected timestamp.
        got: f64,
    },
    /// The ego-pose filter refused the scan's OXTS packet (e.g. no GPS fix yet).
    #[error("ego pose: {0}")]
    Pose(#[from] PoseError),
    /// DBSCAN could not run.
    #[error("clustering: {0}")]
    Cluster(#[from] ClusterError),
}

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
    filtered: Vec<Point>,
    is_ground: Vec<bool>,
    obstacles: Vec<Point>,
    ground: Vec<Point>,
    obstacles_world: Vec<Point>,
    ground_world: Vec<Point>,
    clustering: Clustering,
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

/// One vehicle's perception state: pose filter, tracker, occupancy map, super-frame trigger.
pub struct Pipeline {
    config: Config,
    vehicle: Vehicle,
    pose: Option<PoseEstimator>,
    filter: Filter,
    ground_removal: GroundRemoval,
    dbscan: Dbscan,
    person_splitter: PersonSplitter,
    splitter: Splitter,
    tracker: Tracker,
    occupancy: OccupancyMap,
    /// Whether scans go out in [`FrameOutput::occupancy_scan`] instead of into `occupancy`.
    hands_out_occupancy: bool,
    trigger: Trigger,
    ground: Ground,
    views: RecentViews,
    buffers: Buffers,
    next_index: u64,
    last_timestamp: Option<f64>,
}

/// Stage timing: the milliseconds since the last lap, under `name`.
struct Laps {
    last: Instant,
    timings: StageTimings,
}

impl Laps {
    fn start() -> Self {
        Self {
            last: Instant::now(),
            timings: StageTimings::default(),
        }
    }

    fn lap(&mut self, name: &'static str) {
        let now = Instant::now();
        let ms = (now - self.last).as_secs_f64() * 1e3;
        self.timings.stages.push((name, ms));
        self.last = now;
    }
}

impl Pipeline {
    /// A pipeline for `vehicle` with `config`.
    pub fn new(config: Config, vehicle: Vehicle) -> Self {
        Self {
            filter: Filter::new(config.filter.clone()),
            ground_removal: GroundRemoval::new(config.ground.clone()),
            dbscan: Dbscan::new(config.cluster.clone()),
            person_splitter: PersonSplitter::default(),
            splitter: Splitter::default(),
            tracker: Tracker::new(config.track.clone()),
            occupancy: OccupancyMap::new(config.occupancy.clone()),
            hands_out_occupancy: false,
            trigger: Trigger::new(config.superframe.clone()),
            ground: Ground::horizontal(0.0),
            views: RecentViews::new(config.track.classify.motion_probe_max_age + VIEW_SLACK),
            buffers: Buffers::default(),
            pose: None,
            config,
            vehicle,
            next_index: 0,
            last_timestamp: None,
        }
    }

    /// The configuration in use.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The vehicle this pipeline runs for.
    pub fn vehicle(&self) -> &Vehicle {
        &self.vehicle
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

    /// The fleet's geodetic origin, once known (given, or the first GPS fix).
    pub fn origin(&self) -> Option<GeoOrigin> {
        self.vehicle
            .origin
            .or_else(|| self.pose.as_ref().and_then(PoseEstimator::origin))
    }

    /// Processes one scan.
    pub fn process(&mut self, frame: Frame) -> Result<FrameOutput, PipelineError> {
        if let Some(previous) = self.last_timestamp
            && frame.timestamp <= previous
        {
            return Err(PipelineError::TimeNotIncreasing {
                previous,
                got: frame.timestamp,
            });
        }
        let mut laps = Laps::start();
        let EgoPose {
            odometry: pose,
            world_from_odometry,
            frame: tracking_frame,
        } = self.ego_pose(&frame)?;
        laps.lap("pose");
        self.last_timestamp = Some(frame.timestamp);
        let index = self.next_index;
        self.next_index += 1;

        // The range image reads nothing but the scan: it is built while the stages up to VFH
        // run, by another worker when one is free (its time is in none of their laps).
        let with_visibility = tracking_frame == TrackingFrame::World;
        let ego_box = self.config.filter.ego_box;
        let mut image = self.views.take_buffer(frame.timestamp);
        let (staged, ()) = rayon::join(
            || self.segment_and_describe(&frame, &pose, &mut laps),
            || {
                if with_visibility {
                    image.build(
                        frame
                            .points
                            .iter()
                            .filter(|p| !ego_box.is_some_and(|b| b.contains(p))),
                    );
                }
            },
        );
        staged?;
        if with_visibility {
            self.views.push(View {
                timestamp: frame.timestamp,
                pose,
                image,
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
        let scan = ScanContext {
            timestamp: frame.timestamp,
            pose,
            ground: &self.ground,
            range_limit: f64::from(self.config.filter.max_range),
            views: with_visibility.then_some(&self.views),
        };
        self.tracker.step(&scan, &inputs);
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
        if tracking_frame == TrackingFrame::World {
            let sensor = pose.translation.vector;
            if self.hands_out_occupancy {
                occupancy_scan = Some(OccupancyScan {
                    sensor,
                    obstacles: b.obstacles_world.clone(),
                    ground: b.ground_world.clone(),
                });
            } else {
                self.occupancy
                    .integrate(sensor, &b.obstacles_world, &b.ground_world);
            }
        }
        laps.lap("occupancy");

        let superframe = self.trigger.poll(frame.timestamp, &tracks).map(|sequence| {
            let origin = self
                .vehicle
                .origin
                .or_else(|| self.pose.as_ref().and_then(PoseEstimator::origin));
            let header = SuperFrameHeader {
                vehicle_id: &self.vehicle.id,
                sequence,
                timestamp: frame.timestamp,
                ego_pose: &ego_pose,
                origin: origin.as_ref(),
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

        Ok(FrameOutput {
            index,
            timestamp: frame.timestamp,
            ego_pose,
            odometry_pose: pose,
            tracking_frame,
            tracks,
            superframe,
            timings: laps.timings,
            counts: FrameCounts {
                points: frame.points.len(),
                filtered: b.filtered.len(),
                non_ground: b.obstacles.len(),
                clusters: b.clustering.len(),
            },
            occupancy_scan,
        })
    }

    /// Filter, ground, world, DBSCAN and VFH of one scan at `pose`, each lapped: fills the
    /// buffers up to the described clusters and the local ground.
    fn segment_and_describe(
        &mut self,
        frame: &Frame,
        pose: &Isometry3<f64>,
        laps: &mut Laps,
    ) -> Result<(), ClusterError> {
        let b = &mut self.buffers;
        self.filter.run(&frame.points, &mut b.filtered);
        laps.lap("filter");

        let plane = self.ground_removal.segment(&b.filtered, &mut b.is_ground);
        b.obstacles.clear();
        b.ground.clear();
        for (p, &g) in b.filtered.iter().zip(&b.is_ground) {
            if g { &mut b.ground } else { &mut b.obstacles }.push(*p);
        }
        laps.lap("ground");

        to_world(&b.obstacles, pose, &mut b.obstacles_world);
        to_world(&b.ground, pose, &mut b.ground_world);
        let normal = pose.rotation * Vector3::from(plane.normal);
        let offset = plane.offset - normal.dot(&pose.translation.vector);
        self.ground.set_plane(normal, offset);
        self.ground
            .fill_cells(pose.translation.vector.xy(), &b.ground_world);
        laps.lap("world");

        self.dbscan.run(&b.obstacles_world, &mut b.clustering)?;
        self.gather_clusters(frame.timestamp, pose.translation.vector);
        laps.lap("cluster");

        self.describe_clusters(pose);
        laps.lap("vfh");
        Ok(())
    }

    /// The scan's sensor pose: from the OXTS packet through the pose EKF, given, or none
    /// (identity, tracking in the sensor frame).
    fn ego_pose(&mut self, frame: &Frame) -> Result<EgoPose, PoseError> {
        let given = |pose: Isometry3<f64>, frame| EgoPose {
            odometry: pose,
            world_from_odometry: Translation3::identity(),
            frame,
        };
        match &frame.ego {
            Ego::Oxts(oxts) => {
                let (config, vehicle) = (&self.config, &self.vehicle);
                let estimator = self.pose.get_or_insert_with(|| {
                    PoseEstimator::new(config.pose.clone(), vehicle.origin, vehicle.imu_to_velo)
                });
                estimator.update(frame.timestamp, oxts)?;
                Ok(EgoPose {
                    odometry: estimator.odometry().ok_or(PoseError::AwaitingAttitude)?,
                    world_from_odometry: estimator.world_from_odometry(),
                    frame: TrackingFrame::World,
                })
            }
            Ego::Pose(pose) => Ok(given(*pose, TrackingFrame::World)),
            Ego::None => Ok(given(Isometry3::identity(), TrackingFrame::Sensor)),
        }
    }

    /// Gathers DBSCAN's clusters into `clusters`: stacked fragments of one object joined,
    /// clusters larger than any object left to the map, people a gap away peeled off,
    /// clusters holding several confirmed tracks' predicted boxes split among them.
    fn gather_clusters(&mut self, timestamp: f64, sensor: Vector3<f64>) {
        let b = &mut self.buffers;
        let classify = &self.config.track.classify;
        b.bounds.clear();
        for members in b.clustering.clusters() {
            let points = members.iter().map(|&i| &b.obstacles_world[i as usize]);
            b.bounds.push(Bounds::of(points));
        }
        stacked_groups(&b.bounds, &mut b.groups);
        // Order the members by group: a counting sort over the clusters' member lists.
        let group_count = b.groups.iter().max().map_or(0, |g| g + 1);
        b.group_ranges.clear();
        b.group_ranges.resize(group_count, 0..0);
        let mut sizes = vec![0usize; group_count];
        for (k, members) in b.clustering.clusters().enumerate() {
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
        for (k, members) in b.clustering.clusters().enumerate() {
            let r = &mut b.group_ranges[b.groups[k]];
            for &i in members {
                c.points[r.end] = b.obstacles_world[i as usize];
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
                    &self.ground,
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
