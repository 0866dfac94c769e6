//! The tracker: one [`Tracker::step`] per scan takes the scan's clusters (world frame, with
//! their VFHs) and moves every track forward: predict, associate, update, decay, drop, birth.

use std::f64::consts::FRAC_PI_2;

use nalgebra::{Isometry3, Vector2, Vector3};
use rayon::prelude::*;

use super::assignment::Assigner;
use super::association::{PairScore, TrackPairs, associate};
use super::box_fit::{length_heading, place_box};
use super::classify::{ClassifyConfig, ShapeFeatures, ShapeVerdict, StructureKind, classify_shape};
use super::config::{AssociationMode, TrackConfig};
use super::dormant::DormantTracks;
use super::ground::Ground;
use super::motion::{MotionModel, wrap_angle};
use super::movement::{
    BESIDE_MOVING_MARGIN, Movement, Sighting, Subject, YOUNG_HITS, seen_through_all,
};
use super::observation::{Observation, Observer};
use super::views::{RecentViews, View};
use super::votes::ClassVotes;
use crate::vfh::{BINS, Vfh, chi_squared, max_deviation};
use crate::{ObjectClass, Point, TrackState};

/// A heading measurement further than this from the track's heading (rad) is an axis flip of
/// the box fit, not a turn.
const MAX_HEADING_STEP: f64 = std::f64::consts::FRAC_PI_4;
/// Consecutive flipped views after which the track takes the view's heading.
const HEADING_RESET_VIEWS: u32 = 3;
/// The same for a parked track: its heading was fitted to many views, and a few that read
/// it crosswise (a far car's back and the first metre of its side read either way, see
/// [`length_heading`]) are no wrong start.
const PARKED_HEADING_RESET_VIEWS: u32 = 8;
/// Weight of a larger view in the smoothed size.
const SIZE_GROW_RATE: f64 = 0.5;
/// An unmatched cluster whose centre lies this close (m) to a track's box is a fragment of
/// that object, not a new one.
const FRAGMENT_MARGIN: f64 = 0.5;
/// Arrival is judged only on a view shaped like an object whose centre lies within this (m)
/// of the track's predicted box: a track that jumped to another cluster stands where the
/// laser passed freely before, and has not moved.
const ARRIVAL_BOX_MARGIN: f64 = 1.0;

/// One cluster handed to the tracker.
#[derive(Clone, Copy, Debug)]
pub struct ClusterInput<'a> {
    /// The cluster's points in the world frame.
    pub points: &'a [Point],
    /// Its Viewpoint Feature Histogram.
    pub vfh: &'a Vfh,
    /// The VFH's cumulative distribution.
    pub cdf: &'a [f32; BINS],
    /// The mean surface variation of its points' neighbourhoods (see
    /// [`VfhEstimator::surface_variation`](crate::vfh::VfhEstimator::surface_variation)).
    pub surface_variation: f32,
}

/// Where and when a scan was taken.
#[derive(Clone, Copy, Debug)]
pub struct ScanContext<'a> {
    /// Scan time, seconds.
    pub timestamp: f64,
    /// Pose of the sensor in the world frame.
    pub pose: Isometry3<f64>,
    /// The ground in the world frame.
    pub ground: &'a Ground,
    /// The range filter's outer limit (m): clusters reaching it are cut by it.
    pub range_limit: f64,
    /// What this scan (the latest view) and the last ones saw along each direction, when the
    /// world frame is fixed (a pose is known): the evidence of motion. `None`: motion is not
    /// judged.
    pub views: Option<&'a RecentViews>,
}

impl ScanContext<'_> {
    /// Position of the sensor in the world frame.
    pub fn sensor(&self) -> Vector3<f64> {
        self.pose.translation.vector
    }
}

/// A track's predicted box, for splitting clusters that hold several objects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PredictedBox {
    /// Track id.
    pub id: u64,
    /// Predicted centre in the ground plane.
    pub center: Vector2<f64>,
    /// Heading, rad.
    pub heading: f64,
    /// Length and width, m.
    pub size: Vector2<f64>,
    /// A vehicle seen to move: its front stands where free space was a moment ago, and is
    /// no newcomer to peel off it (see [`super::arrivals`]).
    pub moving_vehicle: bool,
    /// A pedestrian or cyclist seen to move: where it walks into a bush, a parked car or a
    /// wall and DBSCAN joins them, its box carves it out (see [`super::split`]).
    pub moving_person: bool,
}

/// One track (tentative or confirmed, object or not yet identified).
#[derive(Clone, Debug)]
pub struct Track {
    id: u64,
    motion: MotionModel,
    /// Smoothed length, width, height.
    size: Vector3<f64>,
    vfh: Vfh,
    cdf: [f32; BINS],
    confidence: f32,
    age: u32,
    hits: u32,
    misses: u32,
    /// Whether the last scan, which the track missed, saw through the middle of its predicted
    /// box: the object is not where the track expects it. An object hidden by something
    /// nearer is not seen through; a track seen through is not reported while it coasts.
    /// `None` where the scans' free space is not known (tracking in the sensor frame).
    seen_through: Option<bool>,
    votes: ClassVotes,
    /// The identity the votes last gave the track as if it stood still (views shaped like
    /// nothing static), where the track was then and in how many views in all they gave it
    /// (an identity given only by motion is not held: a trunk judged moving on a pose error
    /// stays a trunk): a static track given it in [`HOLD_MIN_VIEWS`] views keeps it while
    /// [`ClassVotes::may_hold`] and it stays within [`HOLD_RADIUS`] of that place (the visible
    /// part of a wall slides along it; a parked car stays put).
    held: Option<(ObjectClass, Vector2<f64>, u32)>,
    /// The highest top above the ground (m) of a view shaped like a car lately, sinking by
    /// [`TOP_SINK`] a scan; 0 when none was.
    car_top: f64,
    /// The widest upper body (m) of a view shaped like a person lately, sinking by
    /// [`WIDTH_SINK`] a scan; 0 when none was.
    person_width: f64,
    movement: Movement,
    /// Whether a view showed the car-class track to be a truck or a bus while it moved (see
    /// [`is_truck`]; standing, a facade cut by the field of view is as tall): seen from farther
    /// or end on, a truck shows no more than a van's height, and it stays a truck.
    truck: bool,
    heading_flips: u32,
    /// The top (m above the ground) of the last view, if the field of view cut it.
    cut_top: Option<f64>,
    cluster: Option<usize>,
    /// Where the box centre was after the last matched view (the motion model's estimate),
    /// and when (s).
    last_seen: (Vector2<f64>, f64),
}

impl Track {
    /// Stable id.
    pub fn id(&self) -> u64 {
        self.id
    }

    /// The index of the cluster matched in the last scan, if any.
    pub fn cluster(&self) -> Option<usize> {
        self.cluster
    }

    /// The VFH of the last matched cluster.
    pub fn vfh(&self) -> &Vfh {
        &self.vfh
    }

    /// Row-major covariance of the motion state `[x, y, z, vx, vy, θ]`.
    pub fn covariance(&self) -> [f64; 36] {
        let mut out = [0.0; 36];
        for (k, v) in out.iter_mut().enumerate() {
            *v = self.motion.covariance()[(k / 6, k % 6)];
        }
        out
    }

    /// Whether the track has been seen to move: the scan sees through where it was.
    pub fn is_moving(&self) -> bool {
        self.movement.is_moving()
    }

    /// Consecutive scans without a match.
    pub fn misses(&self) -> u32 {
        self.misses
    }

    /// What the track is: an object class, or `None` for structure / not identified. The
    /// class its votes give now, or, for a static track they no longer identify, the one it
    /// holds (a parked car seen from farther: see the `held` field).
    pub fn identity(&self) -> Option<ObjectClass> {
        let moving = self.is_moving();
        let fresh = self.votes.identity(moving);
        if fresh.is_some() || moving {
            return fresh;
        }
        let (class, at, views) = self.held?;
        let near = (self.motion.position().xy() - at).norm() <= HOLD_RADIUS;
        (views >= HOLD_MIN_VIEWS && near && self.votes.may_hold(class)).then_some(class)
    }

    /// Whether the track is parked: held as an object (identified in [`HOLD_MIN_VIEWS`]
    /// views), seen in [`PARKED_MIN_HITS`] scans and not found moving. A parked track takes a
    /// flipped heading only after [`PARKED_HEADING_RESET_VIEWS`] views, and in the world frame
    /// it is predicted without velocity (see [`Tracker::step`]).
    fn is_parked(&self) -> bool {
        self.held_class().is_some() && self.hits >= PARKED_MIN_HITS && !self.is_moving()
    }

    /// The class the track's votes have identified it as in at least [`HOLD_MIN_VIEWS`]
    /// views in a row, if any (see [`Self::held`]).
    fn held_class(&self) -> Option<ObjectClass> {
        self.held
            .filter(|&(_, _, views)| views >= HOLD_MIN_VIEWS)
            .map(|(class, _, _)| class)
    }

    /// Judges whether the track, just matched to `seen`, moves (see [`Movement::judge`]).
    fn judge_motion(&mut self, seen: &Sighting<'_>, scan: &ScanContext<'_>, c: &ClassifyConfig) {
        let track = Subject {
            id: self.id,
            hits: self.hits,
            position: self.motion.position().xy(),
        };
        self.movement.judge(track, seen, scan, c);
    }

    /// Updates [`Self::held`] after a view.
    fn settle_identity(&mut self) {
        if let Some(class) = self.votes.identity(false) {
            let views = match self.held {
                Some((held, _, views)) if held == class => views + 1,
                _ => 1,
            };
            self.held = Some((class, self.motion.position().xy(), views));
        } else if self.identity().is_none() {
            self.held = None;
        }
    }

    /// The track's box and motion in the world frame.
    pub fn state(&self) -> TrackState {
        TrackState {
            id: self.id,
            class: self.identity().unwrap_or(ObjectClass::Unknown),
            center: self.motion.position(),
            size: self.size,
            yaw: self.motion.yaw(),
            velocity: self.motion.velocity(),
            confidence: self.confidence,
            age: self.age,
            hits: self.hits,
        }
    }
}

/// All tracks of one vehicle.
#[derive(Debug)]
pub struct Tracker {
    config: TrackConfig,
    tracks: Vec<Track>,
    next_id: u64,
    dormant: DormantTracks,
    time: Option<f64>,
    observations: Vec<Observation>,
    pairs: Vec<TrackPairs>,
    assigner: Assigner,
    taken: Vec<bool>,
}

impl Tracker {
    /// A tracker without tracks.
    pub fn new(config: TrackConfig) -> Self {
        Self {
            dormant: DormantTracks::new(config.dormant.clone()),
            config,
            tracks: Vec::new(),
            next_id: 1,
            time: None,
            observations: Vec::new(),
            pairs: Vec::new(),
            assigner: Assigner::default(),
            taken: Vec::new(),
        }
    }

    /// The configuration in use.
    pub fn config(&self) -> &TrackConfig {
        &self.config
    }

    /// Every live track, tentative ones and structure included.
    pub fn tracks(&self) -> &[Track] {
        &self.tracks
    }

    /// What the last [`Tracker::step`] measured of each of its clusters, in their order.
    pub fn observations(&self) -> &[Observation] {
        &self.observations
    }

    /// Whether `track` is reported (see [`Tracker::reported`]).
    pub fn is_reported(&self, track: &Track) -> bool {
        let coasting = if track.hits < CONFIRMED_HITS {
            0
        } else if track.is_parked() && track.seen_through == Some(false) {
            self.config
                .report_coasting_scans
                .max(self.config.report_parked_coasting_scans)
        } else {
            self.config.report_coasting_scans
        };
        track.hits >= self.config.birth_hits
            && track.misses <= coasting
            && !(track.misses > 0 && track.seen_through == Some(true))
            && track.identity().is_some()
            && !self.is_on_a_matched_car(track)
    }

    /// Whether track `t` stands on a car track matched in the last scan that outranks it:
    /// given its identity in more views in a row (see [`Track::held`]), or in as many and
    /// matched more often, or as often and older. `t` is a second track on the same car, a
    /// piece of it seen apart or a track that slid off it onto what stands right behind it
    /// (whose views then stop adding to its identity). Reported, it is a false positive in
    /// every scan, and the car is one object either way.
    fn is_on_a_matched_car(&self, t: &Track) -> bool {
        let p = t.motion.position().xy();
        let rank = |u: &Track| {
            let views = u.held.map_or(0, |(_, _, views)| views);
            (views, u.hits, std::cmp::Reverse(u.id))
        };
        let (own_rank, confirmed) = (rank(t), self.confirmed_hits());
        self.tracks.iter().any(|u| {
            u.id != t.id
                && u.misses == 0
                && u.hits >= confirmed
                && on_car(u, &p)
                && u.identity() == Some(ObjectClass::Car)
                && rank(u) > own_rank
        })
    }

    /// The tracks to report: matched `birth_hits` times, identified as objects, and matched in
    /// the last scan, or in one of the last `report_coasting_scans + 1` once matched
    /// `CONFIRMED_HITS` times if the last scan did not see through their box (parked tracks the
    /// scan shows not to be seen through: `report_parked_coasting_scans + 1`); not a second
    /// track on a car: one standing on a car track matched in the last scan that was given its
    /// identity in more views in a row (or in as many and matched more often).
    pub fn reported(&self) -> impl Iterator<Item = &Track> + '_ {
        self.tracks.iter().filter(|t| self.is_reported(t))
    }

    /// Matches that make a track confirmed: it coasts through misses and guides splits.
    fn confirmed_hits(&self) -> u32 {
        self.config.birth_hits.max(CONFIRMED_HITS)
    }

    /// The boxes the confirmed tracks are predicted to occupy at `timestamp`, but a second
    /// track's on the same car: of two car tracks less than 1 m apart, only the one matched
    /// more often (or as often, and older) predicts a box.
    pub fn predicted_boxes(&self, timestamp: f64) -> impl Iterator<Item = PredictedBox> + '_ {
        let dt = self.time.map_or(0.0, |t| (timestamp - t).max(0.0));
        self.tracks
            .iter()
            .filter(|t| t.hits >= self.confirmed_hits())
            .filter(|t| !self.is_second_on_a_car(t))
            .filter_map(move |t| {
                let class = t.identity()?;
                let moving_person = t.is_moving()
                    && matches!(class, ObjectClass::Pedestrian | ObjectClass::Cyclist);
                // A person's smoothed size creeps up with every view that holds a little of
                // what they pass; their class's size is what carves them out of it.
                let size = match self.config.classify.size_of(class) {
                    Some(prior) if moving_person => Vector2::new(prior.length, prior.width),
                    _ => t.size.xy(),
                };
                Some(PredictedBox {
                    id: t.id,
                    center: t.motion.position().xy() + t.motion.velocity() * dt,
                    heading: t.motion.yaw(),
                    size,
                    moving_vehicle: t.is_moving() && class == ObjectClass::Car,
                    moving_person,
                })
            })
    }

    /// Whether car track `t` lies within [`SAME_CAR_DISTANCE`] of a confirmed car track
    /// matched more often (or as often, and older): a second track on the same car. Its box
    /// claims none of the car's points, or splitting would share the car out between the two
    /// and keep both alive, one of them a false positive in every scan; unmatched, it fades.
    fn is_second_on_a_car(&self, t: &Track) -> bool {
        let car = Some(ObjectClass::Car);
        t.identity() == car
            && self.tracks.iter().any(|u| {
                u.id != t.id
                    && u.hits >= self.confirmed_hits()
                    && u.identity() == car
                    && (u.hits, std::cmp::Reverse(u.id)) > (t.hits, std::cmp::Reverse(t.id))
                    && (u.motion.position() - t.motion.position()).xy().norm() < SAME_CAR_DISTANCE
            })
    }

    /// Processes one scan's clusters.
    pub fn step(&mut self, scan: &ScanContext<'_>, clusters: &[ClusterInput<'_>]) {
        let dt = self.time.map_or(0.0, |t| (scan.timestamp - t).max(0.0));
        self.time = Some(scan.timestamp);
        let process = self.config.motion.process_noise();
        for t in &mut self.tracks {
            // A parked track's box stays where its views put it: the velocity its filter reads
            // off views that show more or less of it (a parked car's side coming into view as
            // the sensor passes) is no motion, and carried on, it slid a parked car's box off
            // the car. Only where the scans' free space tells whether a track moves: tracked in
            // the sensor frame, parked cars move with the scene.
            if scan.views.is_some() && t.is_parked() {
                t.motion.stop();
            }
            t.motion.predict(dt, &process);
            t.age += 1;
            t.cluster = None;
        }
        // Each cluster's observation is its own: measured in parallel, kept in cluster order.
        let classify = &self.config.classify;
        clusters
            .par_iter()
            .map_init(Observer::default, |observer, c| {
                observer.observe(c.points, c.surface_variation, scan, classify)
            })
            .collect_into_vec(&mut self.observations);
        self.score_pairs(scan, clusters);
        let matches = associate(
            &self.config.association,
            &self.pairs,
            clusters.len(),
            &mut self.assigner,
        );
        self.taken.clear();
        self.taken.resize(clusters.len(), false);
        let now = scan.views.and_then(|views| views.at(scan.timestamp));
        for (k, m) in matches.into_iter().enumerate() {
            match m {
                Some(j) => {
                    self.taken[j] = true;
                    self.update(k, j, scan, &clusters[j]);
                }
                None => {
                    let t = &mut self.tracks[k];
                    t.seen_through = now.map(|now| box_seen_through(t, now));
                    t.misses += 1;
                    t.confidence = self.config.confidence.miss(t.confidence, dt);
                }
            }
        }
        let confidence = &self.config.confidence;
        let dormant = &mut self.dormant;
        dormant.expire(scan.timestamp);
        self.tracks.retain(|t| {
            let lost = confidence.is_lost(t.confidence);
            if lost && t.hits >= CONFIRMED_HITS && t.identity().is_some() {
                let velocity = if t.is_moving() {
                    t.motion.velocity()
                } else {
                    Vector2::zeros()
                };
                dormant.remember(t.id, t.last_seen, velocity, scan.timestamp);
            }
            !lost
        });
        for (j, cluster) in clusters.iter().enumerate() {
            if !self.taken[j] && self.may_be_born(j) {
                self.birth(j, scan, cluster);
            }
        }
    }

    /// Scores the (track, cluster) pairs association looks at: the gated ones, or all of
    /// them in the paper's modes.
    fn score_pairs(&mut self, scan: &ScanContext<'_>, clusters: &[ClusterInput<'_>]) {
        let gated = self.config.association.mode == AssociationMode::GatedAssignment;
        let gate = self.config.association.gate;
        self.pairs
            .resize_with(self.tracks.len(), TrackPairs::default);
        for (t, pairs) in self.tracks.iter().zip(&mut self.pairs) {
            pairs.pairs.clear();
            let identity = t.identity();
            let range = (t.motion.position() - scan.sensor()).xy().norm();
            let predicted = t
                .motion
                .predicted_position(&self.config.motion.measurement_noise(range));
            pairs.motion_ready = t.hits >= 2;
            pairs.log_det = predicted.covariance.determinant().max(1e-12).ln();
            let reach = (gate * predicted.covariance.symmetric_eigenvalues().max()).sqrt()
                + t.size.xy().norm() / 2.0;
            let person_reach = pedestrian_reach(t, scan, &self.config);
            let car_reach = parked_car_reach(t, identity, scan, &self.config);
            let longest = longest_view(t, &self.config);
            for (j, o) in self.observations.iter().enumerate() {
                let too_long = o.shape.length > longest;
                if gated
                    && (too_long
                        || foreign_view(identity, t.truck, o, &self.config.classify)
                        || shorter_than_cut(t, identity, o)
                        || car_reach.is_some_and(|r| {
                            !inside_box(t, &o.rect.center, r + o.rect.extent.norm() / 2.0)
                        })
                        || (o.rect.center - predicted.mean).norm()
                            > reach + o.rect.extent.norm() / 2.0)
                {
                    continue;
                }
                let center = measured_center(t, o, scan, &self.config);
                let mahalanobis2 = predicted.mahalanobis_squared(&center.xy());
                let out_of_person_reach =
                    person_reach.is_some_and(|r| (center.xy() - t.last_seen.0).norm() > r);
                if gated && (mahalanobis2 > gate || out_of_person_reach) {
                    continue;
                }
                pairs.pairs.push(PairScore {
                    cluster: j,
                    chi2: chi_squared(&t.vfh, clusters[j].vfh),
                    max_deviation: max_deviation(&t.cdf, clusters[j].cdf),
                    mahalanobis2,
                    nll: predicted.negative_log_likelihood(&center.xy()),
                    unlike_structure: structure_unlike(identity, o),
                });
            }
        }
        self.pairs.truncate(self.tracks.len());
    }

    /// Corrects track `k` with cluster `j`.
    fn update(&mut self, k: usize, j: usize, scan: &ScanContext<'_>, cluster: &ClusterInput<'_>) {
        let config = &self.config;
        let o = &self.observations[j];
        // Only a young track's arrival before its birth is judged (this match is counted
        // below): the others need not look for a moving track beside them.
        let young = self.tracks[k].hits < YOUNG_HITS;
        let beside_moving = young && self.beside_moving_track(Some(k), &o.rect.center);
        let t = &mut self.tracks[k];
        let heading = box_heading(t, o, config);
        let range = o.shape.range;
        let noise = config.motion.measurement_noise(range);
        let may_have_arrived = matches!(
            o.verdict,
            ShapeVerdict::Object(_) | ShapeVerdict::Movable(_)
        ) && inside_box(t, &o.rect.center, ARRIVAL_BOX_MARGIN);
        // Size first: the box centre is placed with the size this view supports.
        update_size(t, o, heading, config);
        let center = measured_center(t, o, scan, config);
        let yaw = if fast(t, config) {
            None
        } else {
            let prior = class_size(t, o, config);
            let sensor = scan.sensor().xy();
            let view = length_heading(&o.rect, prior.x, prior.y, SINGLE_FACE_DEPTH, &sensor);
            if heading_error(view, t.motion.yaw()) < MAX_HEADING_STEP {
                t.heading_flips = 0;
                Some(view)
            } else {
                // Probably the box fit flipping axes; several views in a row: a wrong start.
                t.heading_flips += 1;
                let reset = if t.is_parked() {
                    PARKED_HEADING_RESET_VIEWS
                } else {
                    HEADING_RESET_VIEWS
                };
                if t.heading_flips >= reset {
                    t.heading_flips = 0;
                    t.motion.set_heading(view);
                }
                None
            }
        };
        t.motion.update(&center, yaw, &noise);
        t.motion
            .align_heading_with_velocity(config.motion.heading_from_velocity_speed);
        t.vfh = *cluster.vfh;
        t.cdf = *cluster.cdf;
        t.confidence = config.confidence.hit(t.confidence);
        t.hits += 1;
        t.misses = 0;
        t.cluster = Some(j);
        t.last_seen = (t.motion.position().xy(), scan.timestamp);
        t.car_top = (t.car_top - TOP_SINK).max(car_top(o));
        t.cut_top = cut_top(o);
        t.person_width = (t.person_width - WIDTH_SINK).max(person_width(o));
        if !o.clipped {
            // A view cut by the range limit shows nothing of what the object is.
            let verdict = verdict_with_person_width(o, t.person_width, config)
                .unwrap_or_else(|| verdict_with_car_top(o, t.car_top, config));
            if !partial_view_of_held_car(t, o, verdict) {
                t.votes.add(verdict, config.classify.vote_memory);
            }
            let seen = Sighting {
                points: cluster.points,
                centroid: &o.centroid,
                may_have_arrived,
                beside_moving,
            };
            t.judge_motion(&seen, scan, &config.classify);
        }
        t.settle_identity();
        trace_view("update", t, o);
    }

    /// Whether unmatched cluster `j` may start a track: not structure, and not a fragment of
    /// an existing object.
    fn may_be_born(&self, j: usize) -> bool {
        let o = &self.observations[j];
        if o.clipped || matches!(o.verdict, ShapeVerdict::Structure(_)) {
            return false;
        }
        let c = o.rect.center;
        // A person is not split into person-shaped parts (stacked ones were joined already): a
        // sure person beside a person's track is another person, and beside a track of no
        // object (a tree, a kiosk) a person, not a fragment of it.
        let sure_person = |class| class == ObjectClass::Pedestrian;
        let person_view = matches!(o.verdict, ShapeVerdict::Object(class) if sure_person(class));
        !self.tracks.iter().any(|t| {
            t.hits >= self.config.birth_hits
                && inside_box(t, &c, FRAGMENT_MARGIN)
                && !(person_view && t.identity().is_none_or(sure_person))
        })
    }

    /// Whether `center` lies within [`BESIDE_MOVING_MARGIN`] of the box of a moving track
    /// other than track `k`.
    fn beside_moving_track(&self, k: Option<usize>, center: &Vector2<f64>) -> bool {
        self.tracks.iter().enumerate().any(|(i, t)| {
            Some(i) != k && t.is_moving() && inside_box(t, center, BESIDE_MOVING_MARGIN)
        })
    }

    /// Starts a track on cluster `j`.
    fn birth(&mut self, j: usize, scan: &ScanContext<'_>, cluster: &ClusterInput<'_>) {
        let config = &self.config;
        let o = &self.observations[j];
        let class = match o.verdict {
            ShapeVerdict::Object(class) | ShapeVerdict::Movable(class) => Some(class),
            _ => None,
        };
        let prior = class.and_then(|c| config.classify.size_of(c));
        let (length, width) =
            prior.map_or((o.shape.length, o.shape.width), |p| (p.length, p.width));
        let sensor = scan.sensor().xy();
        let heading = length_heading(&o.rect, length, width, SINGLE_FACE_DEPTH, &sensor);
        let (seen_l, seen_w) = extents_along(o, heading);
        let size = Vector3::new(
            seen_l.max(prior.map_or(0.0, |p| p.length)),
            seen_w.max(prior.map_or(0.0, |p| p.width)),
            o.shape.top,
        );
        let xy = place_box(&o.corners(), heading, size.xy(), &scan.sensor().xy());
        let center = Vector3::new(xy.x, xy.y, o.ground_z + size.z / 2.0);
        let m = &config.motion;
        let velocity_sigma = match class {
            Some(ObjectClass::Car) => m.birth_velocity_sigma_car,
            Some(ObjectClass::Cyclist) => m.birth_velocity_sigma_cyclist,
            _ => m.birth_velocity_sigma_pedestrian,
        };
        let range = o.shape.range;
        let mut votes = ClassVotes::default();
        votes.add(o.verdict, config.classify.vote_memory);
        // An object seen again where its dropped track left it, or where it was going, gets
        // its id back.
        let id = match self.dormant.claim(center.xy(), scan.timestamp) {
            Some(id) => id,
            None => {
                let id = self.next_id;
                self.next_id += 1;
                id
            }
        };
        let beside_moving = self.beside_moving_track(None, &o.rect.center);
        self.tracks.push(Track {
            id,
            motion: MotionModel::new(center, heading, &m.measurement_noise(range), velocity_sigma),
            size,
            vfh: *cluster.vfh,
            cdf: *cluster.cdf,
            confidence: config.confidence.initial,
            age: 1,
            hits: 1,
            misses: 0,
            seen_through: None,
            votes,
            held: None,
            car_top: car_top(o),
            person_width: person_width(o),
            movement: Movement::new(center.xy(), scan.timestamp),
            heading_flips: 0,
            cut_top: cut_top(o),
            truck: false,
            cluster: Some(j),
            last_seen: (center.xy(), scan.timestamp),
        });
        if let Some(t) = self.tracks.last_mut() {
            let shaped_like_an_object = matches!(
                o.verdict,
                ShapeVerdict::Object(_) | ShapeVerdict::Movable(_)
            );
            let seen = Sighting {
                points: cluster.points,
                centroid: &o.centroid,
                may_have_arrived: shaped_like_an_object,
                beside_moving,
            };
            t.judge_motion(&seen, scan, &config.classify);
            t.settle_identity();
            trace_view("birth", t, o);
        }
    }
}

/// Matches before a track coasts through misses and guides the splitting of clusters: a
/// track seen once may be a fragment, reported only in the scan that showed it.
const CONFIRMED_HITS: u32 = 2;

/// Car tracks whose centres are closer than this (m) are on the same car: two cars side by
/// side stand a car's width (1.6 m or more) apart.
const SAME_CAR_DISTANCE: f64 = 1.0;

/// How far (m) a static track may drift from where its views last identified it and keep
/// that identity.
const HOLD_RADIUS: f64 = 1.0;

/// Views a static track's votes must have identified it in before it holds the identity.
const HOLD_MIN_VIEWS: u32 = 5;

/// Scans a track held as an object must have been seen in, and not found moving, to be
/// parked (see [`Track::is_parked`]): by then a moving one has shown its motion.
const PARKED_MIN_HITS: u32 = 10;

/// How fast (m per scan) the remembered top of a track sinks towards what is seen now.
const TOP_SINK: f64 = 0.02;

/// The top (m) of view `o` if it is shaped like a car, else 0.
fn car_top(o: &Observation) -> f64 {
    if is_car(o.verdict) { o.shape.top } else { 0.0 }
}

/// Whether a verdict names a car.
fn is_car(verdict: ShapeVerdict) -> bool {
    matches!(
        verdict,
        ShapeVerdict::Object(ObjectClass::Car) | ShapeVerdict::Movable(ObjectClass::Car)
    )
}

/// The verdict on view `o` of a track that looked like a car of top `car_top` lately. A
/// view's top only bounds the height from below (the beams that reach a distant car's roof
/// return only now and then), so the car's top is the highest seen: a view without the roof
/// is still the car, not a low object, and a view under the car height of a thing that was
/// seen taller (a bush, a hedge) is not a sure car. (Views cut by the range limit are
/// [`ShapeVerdict::Unknown`] and stay so.)
fn verdict_with_car_top(o: &Observation, car_top: f64, config: &TrackConfig) -> ShapeVerdict {
    let lower_bound = matches!(
        o.verdict,
        ShapeVerdict::Structure(StructureKind::TooLow) | ShapeVerdict::Object(ObjectClass::Car)
    );
    if !lower_bound || car_top <= o.shape.top {
        return o.verdict;
    }
    let shape = ShapeFeatures {
        top: car_top,
        ..o.shape
    };
    let lifted = classify_shape(&shape, &config.classify);
    if is_car(lifted) { lifted } else { o.verdict }
}

/// Beyond this range (m) a parked car's view often shows its lower body or its roof alone.
const PARTIAL_CAR_RANGE: f64 = 30.0;

/// A view's top may exceed the remembered car top by this much (m) and still be the car's.
const CAR_TOP_MARGIN: f64 = 0.1;

/// Whether view `o`, judged `verdict`, is a partial view of a parked car that tells nothing of
/// what it is: `t` is a static track held as a car (see [`Track::held`]: identified in
/// [`HOLD_MIN_VIEWS`] views), and the view lies farther than [`PARTIAL_CAR_RANGE`], is no
/// taller than the car was lately seen (`car_top`), and is judged structure for what it lacks
/// (too low, floating: its lower body or its roof alone) or for its sparse returns (top-heavy,
/// rough as foliage). Such a view takes no vote; counted as structure, a few of them in a row
/// took a far parked car's identity. A view larger than the car still votes: what the car is
/// joined to may be all there is. A moving track holds no identity (see [`Track::identity`]):
/// every view votes, or a car's track that moved on to a bush by the road would report the
/// bush as the car.
fn partial_view_of_held_car(t: &Track, o: &Observation, verdict: ShapeVerdict) -> bool {
    t.held_class() == Some(ObjectClass::Car)
        && !t.is_moving()
        && t.car_top > 0.0
        && o.shape.range >= PARTIAL_CAR_RANGE
        && o.shape.top <= t.car_top + CAR_TOP_MARGIN
        && matches!(
            verdict,
            ShapeVerdict::Structure(
                StructureKind::TooLow
                    | StructureKind::Floating
                    | StructureKind::Tree
                    | StructureKind::Foliage
            )
        )
}

/// How fast (m per scan) the remembered upper-body width of a track narrows towards what is
/// seen now.
const WIDTH_SINK: f64 = 0.01;

/// The upper width (m) of view `o` if it is shaped like a person, else 0.
fn person_width(o: &Observation) -> f64 {
    let person = match o.verdict {
        ShapeVerdict::Object(class) | ShapeVerdict::Movable(class) => is_person(class),
        _ => false,
    };
    if person { o.shape.upper_width } else { 0.0 }
}

/// Whether a class is a person: a pedestrian or a cyclist.
fn is_person(class: ObjectClass) -> bool {
    matches!(class, ObjectClass::Pedestrian | ObjectClass::Cyclist)
}

/// The verdict on view `o`, shaped like a person but too narrow to be sure of, of a track whose
/// person-shaped views were up to `person_width` wide lately, if that makes it sure. A far
/// view's widths fall short by up to a column's spacing (13 cm at 40 m), more or less from scan
/// to scan as the columns fall on the body; a post stays as thin as it is, a person's shoulders
/// and swinging arms show their width in some views.
fn verdict_with_person_width(
    o: &Observation,
    person_width: f64,
    config: &TrackConfig,
) -> Option<ShapeVerdict> {
    let narrow = matches!(o.verdict, ShapeVerdict::Movable(class) if is_person(class));
    if !narrow || person_width <= o.shape.upper_width {
        return None;
    }
    let shape = ShapeFeatures {
        upper_width: person_width,
        length: o.shape.length.max(person_width),
        ..o.shape
    };
    let lifted = classify_shape(&shape, &config.classify);
    matches!(lifted, ShapeVerdict::Object(class) if is_person(class)).then_some(lifted)
}

/// A view whose outline is thinner than this (m) shows one face only.
const SINGLE_FACE_DEPTH: f64 = 0.5;

/// Whether the track's speed is high and known well enough to give its heading.
fn fast(t: &Track, config: &TrackConfig) -> bool {
    let speed = t.motion.velocity().norm();
    speed >= config.motion.heading_from_velocity_speed && speed > 2.0 * t.motion.velocity_sigma()
}

/// The heading to place the box of `t` on view `o`: the direction of motion when fast, else
/// the axis of the view's outline nearest the track's heading.
fn box_heading(t: &Track, o: &Observation, config: &TrackConfig) -> f64 {
    if fast(t, config) {
        let v = t.motion.velocity();
        return v.y.atan2(v.x);
    }
    let theta = t.motion.yaw();
    let a = o.rect.yaw;
    let b = o.rect.yaw + FRAC_PI_2;
    if heading_error(a, theta) <= heading_error(b, theta) {
        a
    } else {
        b
    }
}

/// Difference between two headings modulo π, in [0, π/2].
fn heading_error(a: f64, b: f64) -> f64 {
    let d = wrap_angle(a - b).abs();
    d.min(std::f64::consts::PI - d)
}

/// Visible extents of `o` along `heading` and across it.
fn extents_along(o: &Observation, heading: f64) -> (f64, f64) {
    if heading_error(heading, o.rect.yaw) < std::f64::consts::FRAC_PI_4 {
        (o.rect.extent.x, o.rect.extent.y)
    } else {
        (o.rect.extent.y, o.rect.extent.x)
    }
}

/// The size prior of the track's class (its identity, else this view's verdict; a car-class
/// track shown to be a truck while moving, see [`Track::truck`], takes a truck's in the views
/// shorter than a car), else what the track has seen.
fn class_size(t: &Track, o: &Observation, config: &TrackConfig) -> Vector2<f64> {
    let c = &config.classify;
    let prior = match size_class(t, o) {
        Some(ObjectClass::Car) if t.is_moving() && t.truck && shorter_than_car(o, c) => {
            Some(c.truck_size)
        }
        other => other.and_then(|class| c.size_of(class)),
    };
    prior.map_or(t.size.xy(), |p| Vector2::new(p.length, p.width))
}

/// Whether view `o` shows less than a car's length (a truck seen end on or in part: its
/// length unseen); a longer view shows the truck's length itself.
fn shorter_than_car(o: &Observation, c: &ClassifyConfig) -> bool {
    o.rect.extent.x.max(o.rect.extent.y) < c.car_max_length
}

/// The class whose size track `t` takes: its identity, else view `o`'s verdict.
fn size_class(t: &Track, o: &Observation) -> Option<ObjectClass> {
    t.identity().or(match o.verdict {
        ShapeVerdict::Object(c) | ShapeVerdict::Movable(c) => Some(c),
        _ => None,
    })
}

/// A view cut by the field of view this high (m) or higher is a truck's or a bus's: vans
/// and cars are lower.
const TRUNCATED_TRUCK_TOP: f64 = 2.7;

/// Whether moving car-class track `t` is a truck or a bus: its smoothed height reaches
/// `truck_min_height`, or view `o` is cut by the top of the field of view no lower than
/// [`TRUNCATED_TRUCK_TOP`] (30 m away the field of view ends 2.8 m above the ground, so a
/// truck seen there never shows its height) and is box-shaped
/// ([`ShapeFeatures::is_box_shaped`]).
fn is_truck(t: &Track, o: &Observation, c: &ClassifyConfig) -> bool {
    let cut_high = o.shape.truncated && o.shape.top >= TRUNCATED_TRUCK_TOP;
    t.size.z >= c.truck_min_height || (cut_high && o.shape.is_box_shaped())
}

/// Smooths the track's size towards this view (larger views quickly, smaller ones slowly),
/// never below the class prior.
fn update_size(t: &mut Track, o: &Observation, heading: f64, config: &TrackConfig) {
    t.truck |= t.is_moving()
        && size_class(t, o) == Some(ObjectClass::Car)
        && is_truck(t, o, &config.classify);
    let prior = class_size(t, o, config);
    let (seen_l, seen_w) = extents_along(o, heading);
    let target = Vector3::new(seen_l.max(prior.x), seen_w.max(prior.y), o.shape.top);
    for k in 0..3 {
        let rate = if target[k] > t.size[k] {
            SIZE_GROW_RATE
        } else {
            config.size_shrink_rate
        };
        t.size[k] += rate * (target[k] - t.size[k]);
    }
}

/// Whether a track identified as `identity` (a truck if `truck`) cannot have seen view `o` of
/// itself: seen in part, no object is a pole (thin and taller than a person,
/// `pole_min_height`: a far parked car's track took the post beside it in every scan that
/// missed the car, and was reported more than 2 m from the car), nor floats above the ground
/// reaching higher than its class stands (a person no taller than a pole's least height, a car
/// or van than `whole_van_max_height`; a sign, a canopy or a crown over it; a truck's cab seen
/// over the cars before it is the truck's).
fn foreign_view(
    identity: Option<ObjectClass>,
    truck: bool,
    o: &Observation,
    c: &ClassifyConfig,
) -> bool {
    let Some(class) = identity else {
        return false;
    };
    match o.verdict {
        ShapeVerdict::Structure(StructureKind::Pole) => true,
        ShapeVerdict::Structure(StructureKind::Floating) => match class {
            ObjectClass::Car => !truck && o.shape.top > c.whole_van_max_height,
            ObjectClass::Pedestrian | ObjectClass::Cyclist => o.shape.top > c.pole_min_height,
            ObjectClass::Unknown | ObjectClass::OtherMovable => false,
        },
        _ => false,
    }
}

/// A view cut by the field of view shows the thing reaching at least this much higher than an
/// uncut view of another (m): within it, the two are the same thing seen differently.
const CUT_TOP_MARGIN: f64 = 0.4;

/// How far (m) from where a track standing still was last seen a view of another thing may
/// lie: nearer, it is the same thing seen differently (a person under a tree's crown, seen
/// without it).
const STILL_TRACK_REACH: f64 = 1.0;

/// The top of view `o` if the field of view cut it: the thing reaches at least that high.
fn cut_top(o: &Observation) -> Option<f64> {
    o.shape.truncated.then_some(o.shape.top)
}

/// Whether unidentified track `t`, standing still, cannot have seen view `o` of itself: its
/// last view was cut by the field of view at a top more than [`CUT_TOP_MARGIN`] above the
/// whole view `o`, of an object's shape, more than [`STILL_TRACK_REACH`] away. A person
/// walking out of a car's shadow past the post a track stood on took that track, and was
/// reported only when the post's votes had faded, eight scans later.
fn shorter_than_cut(t: &Track, identity: Option<ObjectClass>, o: &Observation) -> bool {
    let objectish = matches!(
        o.verdict,
        ShapeVerdict::Object(_) | ShapeVerdict::Movable(_)
    );
    identity.is_none()
        && objectish
        && !t.is_moving()
        && !o.shape.truncated
        && t.cut_top
            .is_some_and(|top| o.shape.top < top - CUT_TOP_MARGIN)
        && (o.rect.center - t.last_seen.0).norm() > STILL_TRACK_REACH
}

/// Whether view `o` is structure that an object identified as `identity` does not show of
/// itself: a person or a rider shows no structure at all, a car no tree or foliage (seen in
/// part, a car looks too low, floating, or joined to something too large; no object's track
/// takes a pole's view at all, see [`foreign_view`]). A pedestrian walking along a row of
/// trees took their crowns, which slid along with the sensor, and left the person to a second
/// track.
fn structure_unlike(identity: Option<ObjectClass>, o: &Observation) -> bool {
    let ShapeVerdict::Structure(kind) = o.verdict else {
        return false;
    };
    match identity {
        Some(ObjectClass::Pedestrian | ObjectClass::Cyclist) => true,
        Some(ObjectClass::Car) => matches!(kind, StructureKind::Tree | StructureKind::Foliage),
        Some(ObjectClass::Unknown | ObjectClass::OtherMovable) | None => false,
    }
}

/// The longest view track `t` may take: `size_gate` times its length (at least its class's
/// typical length: a car's track born on its corner as it came into view has not grown to a
/// car's size when the car shows whole, and a second track was born on the car) plus 1 m, and
/// for an identified person, whose smoothed size grows with every view a little larger, at
/// most its class's longest view plus 1 m (a pedestrian walking along a wall took ever longer
/// pieces of it and became a 4.5 m track on the wall).
fn longest_view(t: &Track, config: &TrackConfig) -> f64 {
    let c = &config.classify;
    let identity = t.identity();
    let class_length = identity
        .and_then(|class| c.size_of(class))
        .map_or(0.0, |size| size.length);
    let length = t.size.x.max(t.size.y).max(class_length);
    let by_size = config.association.size_gate * length + 1.0;
    let by_class = match identity {
        Some(ObjectClass::Pedestrian) => c.pedestrian_max_length + 1.0,
        _ => f64::INFINITY,
    };
    by_size.min(by_class)
}

/// Where view `o` puts the centre of track `t`'s box.
fn measured_center(
    t: &Track,
    o: &Observation,
    scan: &ScanContext<'_>,
    config: &TrackConfig,
) -> Vector3<f64> {
    let heading = box_heading(t, o, config);
    let xy = place_box(&o.corners(), heading, t.size.xy(), &scan.sensor().xy());
    Vector3::new(xy.x, xy.y, o.ground_z + t.size.z / 2.0)
}

/// How far (m) from where pedestrian track `t` was last seen a view may lie now: as far as a
/// person walks or runs since then, plus a margin. However wide the motion model's gate has
/// grown while the track coasted, it does not take a person metres away. `None` for tracks
/// not identified as pedestrians.
fn pedestrian_reach(t: &Track, scan: &ScanContext<'_>, config: &TrackConfig) -> Option<f64> {
    if t.identity() != Some(ObjectClass::Pedestrian) {
        return None;
    }
    let elapsed = (scan.timestamp - t.last_seen.1).max(0.0);
    let m = &config.motion;
    Some(m.pedestrian_max_speed * elapsed + m.pedestrian_reach_margin)
}

/// How far (m) outside parked car `t`'s box (its class `identity`) a view may lie now: as far
/// as the car, pulling out since it was last seen, has gone, plus a margin. A parked car
/// hidden for a few scans took a pedestrian 3 m beyond its box once the motion model's gate
/// had grown. `None` for tracks not parked as cars.
fn parked_car_reach(
    t: &Track,
    identity: Option<ObjectClass>,
    scan: &ScanContext<'_>,
    config: &TrackConfig,
) -> Option<f64> {
    if !t.is_parked() || identity != Some(ObjectClass::Car) {
        return None;
    }
    let elapsed = (scan.timestamp - t.last_seen.1).max(0.0);
    let m = &config.motion;
    Some(0.5 * m.parked_max_acceleration * elapsed * elapsed + m.parked_reach_margin)
}

/// Whether the scan `now` sees through the middle of track `t`'s predicted box, at its centre
/// and a quarter of its height above, as a moving track's probes are looked through: free
/// space where the object should stand; what hides the object tells nothing.
fn box_seen_through(t: &Track, now: &View) -> bool {
    let center = t.motion.position();
    seen_through_all(now, &[center, center + Vector3::z() * (t.size.z / 4.0)])
}

/// Whether `p` lies on car track `t`: within its length plus [`ON_CAR_MARGIN`] along it and
/// [`SAME_CAR_DISTANCE`] across it (two cars side by side stand farther apart).
fn on_car(t: &Track, p: &Vector2<f64>) -> bool {
    let (along, across) = box_offsets(t, p);
    along <= t.size.x / 2.0 + ON_CAR_MARGIN && across <= SAME_CAR_DISTANCE
}

/// How far (m) beyond a car's ends a second track on it may stand: a box fitted to a far car's
/// views falls short of its length.
const ON_CAR_MARGIN: f64 = 0.3;

/// Whether `p` lies within `margin` of the track's current box.
fn inside_box(t: &Track, p: &Vector2<f64>, margin: f64) -> bool {
    let (along, across) = box_offsets(t, p);
    along <= t.size.x / 2.0 + margin && across <= t.size.y / 2.0 + margin
}

/// How far (m) `p` lies from track `t`'s centre along its heading and across it.
fn box_offsets(t: &Track, p: &Vector2<f64>) -> (f64, f64) {
    let (s, c) = t.motion.yaw().sin_cos();
    let d = p - t.motion.position().xy();
    ((c * d.x + s * d.y).abs(), (-s * d.x + c * d.y).abs())
}

/// Logs what a view of track `t` showed (`TRACKD_LOG=trackd_perception::track=trace`).
fn trace_view(event: &str, t: &Track, o: &Observation) {
    let p = t.motion.position();
    let f = &o.shape;
    tracing::trace!(
        "{event} track {} at ({:.1}, {:.1}) hits {} moving {} identity {:?} | view n {} \
         L {:.2} W {:.2} top {:.2} bottom {:.2} upper {:.2} lower {:.2} truncated {} \
         oblique {} -> {:?}",
        t.id,
        p.x,
        p.y,
        t.hits,
        t.is_moving(),
        t.identity(),
        o.points,
        f.length,
        f.width,
        f.top,
        f.bottom,
        f.upper_width,
        f.lower_width,
        f.truncated,
        f.oblique_face,
        o.verdict
    );
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// A scan at `timestamp` by a sensor 1.73 m above the world origin, over `ground`, cut at
    /// 50 m, with no earlier views.
    pub(in crate::track) fn scan_at(timestamp: f64, ground: &Ground) -> ScanContext<'_> {
        ScanContext {
            timestamp,
            pose: Isometry3::translation(0.0, 0.0, 1.73),
            ground,
            range_limit: 50.0,
            views: None,
        }
    }

    /// A board 1 m wide, 0.1 m apart, `bottom` to `top` metres up, facing the sensor 20 m
    /// ahead (world frame, ground z = 0).
    fn board(bottom: f32, top: f32) -> Vec<Point> {
        let rows = ((top - bottom) / 0.1).round() as i32;
        (0..=rows)
            .flat_map(|row| {
                (0..=10)
                    .map(move |i| Point::new(20.0, 0.1 * i as f32, bottom + 0.1 * row as f32, 0.0))
            })
            .collect()
    }

    /// The faces a sensor at the origin sees of a car 4.4 × 1.8 × 1.5 m whose rear stands
    /// 18 m ahead: its rear and its right side, 0.1 m apart.
    fn car_rear_and_side() -> Vec<Point> {
        let mut points = Vec::new();
        for row in 2..=15 {
            let z = 0.1 * row as f32;
            for i in 0..=18 {
                points.push(Point::new(18.0, -0.9 + 0.1 * i as f32, z, 0.0));
            }
            for i in 1..=44 {
                points.push(Point::new(18.0 + 0.1 * i as f32, -0.9, z, 0.0));
            }
        }
        points
    }

    #[test]
    fn of_two_tracks_on_one_car_the_one_identified_in_more_views_in_a_row_is_reported() {
        let ground = Ground::horizontal(0.0);
        let mut tracker = Tracker::new(TrackConfig::default());
        let points = car_rear_and_side();
        let vfh = Vfh {
            bins: [1.0 / BINS as f32; BINS],
        };
        let cdf = vfh.cdf();
        let cluster = ClusterInput {
            points: &points,
            vfh: &vfh,
            cdf: &cdf,
            surface_variation: 0.0,
        };
        for k in 0..8 {
            tracker.step(&scan_at(0.1 * f64::from(k), &ground), &[cluster]);
        }
        assert_eq!(tracker.tracks.len(), 1);
        let car = &tracker.tracks[0];
        assert_eq!(car.identity(), Some(ObjectClass::Car));
        let (class, at, views) = car.held.expect("the car's views identified it");
        // A second track on the car, matched once less but identified in one view more in a
        // row (the first one's views stopped giving it the car: it slid off it).
        let mut second = car.clone();
        second.id = 99;
        second.hits -= 1;
        second.held = Some((class, at, views + 1));
        tracker.tracks.push(second);
        let reported: Vec<u64> = tracker.reported().map(|t| t.id).collect();
        assert_eq!(reported, vec![99]);
        // Identified in as many views, the one matched more often is reported.
        tracker.tracks[1].held = Some((class, at, views));
        let reported: Vec<u64> = tracker.reported().map(|t| t.id).collect();
        assert_eq!(reported, vec![tracker.tracks[0].id]);
    }

    #[test]
    fn no_object_seen_in_part_is_a_pole_or_floats_above_its_class() {
        let ground = Ground::horizontal(0.0);
        let scan = scan_at(0.0, &ground);
        let c = ClassifyConfig::default();
        let observe = |points: &[Point]| Observer::default().observe(points, 0.0, &scan, &c);
        let (car, person) = (Some(ObjectClass::Car), Some(ObjectClass::Pedestrian));
        // A post 3 m tall: nobody's part.
        let pole: Vec<Point> = (0..28)
            .map(|k| Point::new(20.0, 0.0, 0.2 + 0.1 * k as f32, 0.0))
            .collect();
        let pole = observe(&pole);
        assert_eq!(pole.verdict, ShapeVerdict::Structure(StructureKind::Pole));
        assert!(foreign_view(car, false, &pole, &c) && foreign_view(person, false, &pole, &c));
        assert!(!foreign_view(None, false, &pole, &c));
        // A sign 1.8-3 m up: no car's, no person's; a truck's cab over the cars before it.
        let sign = observe(&board(1.8, 3.0));
        assert_eq!(
            sign.verdict,
            ShapeVerdict::Structure(StructureKind::Floating)
        );
        assert!(foreign_view(car, false, &sign, &c) && foreign_view(person, false, &sign, &c));
        assert!(!foreign_view(car, true, &sign, &c));
        // What shows of a car or a walker over the cars before them floats as low as they are.
        let over_cars = observe(&board(1.2, 1.9));
        assert_eq!(
            over_cars.verdict,
            ShapeVerdict::Structure(StructureKind::Floating)
        );
        assert!(!foreign_view(car, false, &over_cars, &c));
        assert!(!foreign_view(person, false, &over_cars, &c));
    }
}
