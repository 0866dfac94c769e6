//! The pipeline's front half: ego pose, range filter, ground removal, world transform, DBSCAN,
//! the clusters gathered and described by their VFH, with the scan's range image built beside
//! them. It reads nothing the tracker writes, so the next scan can be segmented while this one
//! is tracked.

use nalgebra::{Isometry3, Translation3, Vector3};

use super::gather::{Clusters, Gatherer};
use super::{EgoPose, FrameCounts, Laps, PipelineError, TrackingFrame, Vehicle};
use crate::cluster::{Clustering, Dbscan};
use crate::config::Config;
use crate::filter::Filter;
use crate::geo::GeoOrigin;
use crate::ground::GroundRemoval;
use crate::pose::{PoseConfig, PoseError, PoseEstimator};
use crate::track::{Ground, RangeImage};
use crate::transform::to_world;
use crate::{Ego, Frame, Point, StageTimings};

/// One scan after segmentation: what the tracking half reads. Its buffers are reused from scan
/// to scan (pass it back to [`Segmentation::segment`]).
#[derive(Debug)]
pub struct Segmented {
    pub(super) index: u64,
    pub(super) timestamp: f64,
    /// The sensor pose in the odometry frame every stage works in.
    pub(super) pose: Isometry3<f64>,
    /// Places the odometry frame in the world frame the outputs are in.
    pub(super) world_from_odometry: Translation3<f64>,
    pub(super) tracking_frame: TrackingFrame,
    /// The fleet's geodetic origin, once known.
    pub(super) origin: Option<GeoOrigin>,
    /// Non-ground points, odometry frame.
    pub(super) obstacles: Vec<Point>,
    /// Ground points, odometry frame.
    pub(super) ground_points: Vec<Point>,
    pub(super) clustering: Clustering,
    /// The clusters gathered for tracking, with their VFHs.
    pub(super) clusters: Clusters,
    /// The ground plane and its local heights.
    pub(super) ground: Ground,
    /// Nearest range per direction (the motion test's view); filled when tracking in the world
    /// frame.
    pub(super) image: RangeImage,
    pub(super) counts: FrameCounts,
    pub(super) timings: StageTimings,
}

impl Default for Segmented {
    fn default() -> Self {
        Self {
            index: 0,
            timestamp: 0.0,
            pose: Isometry3::identity(),
            world_from_odometry: Translation3::identity(),
            tracking_frame: TrackingFrame::World,
            origin: None,
            obstacles: Vec::new(),
            ground_points: Vec::new(),
            clustering: Clustering::default(),
            clusters: Clusters::default(),
            ground: Ground::horizontal(0.0),
            image: RangeImage::default(),
            counts: FrameCounts::default(),
            timings: StageTimings::default(),
        }
    }
}

/// The front half's state: the pose filter, the stages and their buffers.
pub struct Segmentation {
    vehicle: Vehicle,
    pose_config: PoseConfig,
    pose: Option<PoseEstimator>,
    filter: Filter,
    ground_removal: GroundRemoval,
    dbscan: Dbscan,
    gatherer: Gatherer,
    filtered: Vec<Point>,
    is_ground: Vec<bool>,
    obstacles: Vec<Point>,
    ground: Vec<Point>,
    next_index: u64,
    last_timestamp: Option<f64>,
}

impl Segmentation {
    /// The front half for `vehicle` with `config`.
    pub fn new(config: &Config, vehicle: Vehicle) -> Self {
        Self {
            vehicle,
            pose_config: config.pose.clone(),
            pose: None,
            filter: Filter::new(config.filter.clone()),
            ground_removal: GroundRemoval::new(config.ground.clone()),
            dbscan: Dbscan::new(config.cluster.clone()),
            gatherer: Gatherer::new(config),
            filtered: Vec::new(),
            is_ground: Vec::new(),
            obstacles: Vec::new(),
            ground: Vec::new(),
            next_index: 0,
            last_timestamp: None,
        }
    }

    /// The vehicle this pipeline runs for.
    pub fn vehicle(&self) -> &Vehicle {
        &self.vehicle
    }

    /// The fleet's geodetic origin, once known (given, or the first GPS fix).
    pub fn origin(&self) -> Option<GeoOrigin> {
        self.vehicle
            .origin
            .or_else(|| self.pose.as_ref().and_then(PoseEstimator::origin))
    }

    /// Segments `frame` into `out` (its previous content is overwritten, its buffers reused).
    /// On error nothing is kept of the scan, and the next scan is segmented as if it had not
    /// come.
    pub fn segment(&mut self, frame: &Frame, out: &mut Segmented) -> Result<(), PipelineError> {
        if let Some(previous) = self.last_timestamp
            && frame.timestamp <= previous
        {
            return Err(PipelineError::TimeNotIncreasing {
                previous,
                got: frame.timestamp,
            });
        }
        let mut laps = Laps::start(std::mem::take(&mut out.timings));
        let EgoPose {
            odometry: pose,
            world_from_odometry,
            frame: tracking_frame,
        } = self.ego_pose(frame)?;
        laps.lap("pose");
        self.last_timestamp = Some(frame.timestamp);
        out.index = self.next_index;
        self.next_index += 1;
        out.timestamp = frame.timestamp;
        out.pose = pose;
        out.world_from_odometry = world_from_odometry;
        out.tracking_frame = tracking_frame;
        out.origin = self.origin();

        // The range image reads nothing but the scan: it is built while the stages run, by
        // another worker when one is free (its time is in none of their laps).
        let with_visibility = tracking_frame == TrackingFrame::World;
        let ego_box = self.filter.config().ego_box;
        let mut image = std::mem::take(&mut out.image);
        let (staged, ()) = rayon::join(
            || self.stages(frame, &pose, out, &mut laps),
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
        out.image = image;
        staged?;
        out.counts = FrameCounts {
            points: frame.points.len(),
            filtered: self.filtered.len(),
            non_ground: self.obstacles.len(),
            clusters: out.clustering.len(),
        };
        out.timings = laps.finish();
        Ok(())
    }

    /// Filter, ground, world, DBSCAN, gathering and VFH of one scan at `pose`, each lapped.
    fn stages(
        &mut self,
        frame: &Frame,
        pose: &Isometry3<f64>,
        out: &mut Segmented,
        laps: &mut Laps,
    ) -> Result<(), PipelineError> {
        self.filter.run(&frame.points, &mut self.filtered);
        laps.lap("filter");

        let plane = self
            .ground_removal
            .segment(&self.filtered, &mut self.is_ground);
        self.obstacles.clear();
        self.ground.clear();
        for (p, &g) in self.filtered.iter().zip(&self.is_ground) {
            if g {
                &mut self.ground
            } else {
                &mut self.obstacles
            }
            .push(*p);
        }
        laps.lap("ground");

        to_world(&self.obstacles, pose, &mut out.obstacles);
        to_world(&self.ground, pose, &mut out.ground_points);
        let normal = pose.rotation * Vector3::from(plane.normal);
        let offset = plane.offset - normal.dot(&pose.translation.vector);
        out.ground.set_plane(normal, offset);
        out.ground
            .fill_cells(pose.translation.vector.xy(), &out.ground_points);
        laps.lap("world");

        self.dbscan.run(&out.obstacles, &mut out.clustering)?;
        laps.lap("dbscan");

        let sensor = pose.translation.vector;
        self.gatherer.gather(
            &out.clustering,
            &out.obstacles,
            sensor,
            &out.ground,
            &mut out.clusters,
        );
        laps.lap("gather");
        self.gatherer
            .describe(&mut out.clusters, [sensor.x, sensor.y, sensor.z]);
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
                let (config, vehicle) = (&self.pose_config, &self.vehicle);
                let estimator = self.pose.get_or_insert_with(|| {
                    PoseEstimator::new(config.clone(), vehicle.origin, vehicle.imu_to_velo)
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
}
