//! Whether a track moves, told by free space rather than by its box's drift (the box of a
//! partly seen object slides as its view changes): the scan now sees through where the track
//! stood a moment ago (it left), or an earlier scan saw through where it stands now (it
//! arrived). A track keeps up to [`PROBES`] points of an earlier cluster, its probes, to ask
//! the scans about.

use nalgebra::{Point3, Vector2, Vector3};

use super::classify::ClassifyConfig;
use super::fragments::Bounds;
use super::tracker::ScanContext;
use super::views::View;
use super::visibility::{RangeImage, Visibility};
use crate::Point;

/// Probes kept per track.
const PROBES: usize = 24;
/// Probes lower than this above the ground (m) are not kept: the ground answers for them.
const PROBE_MIN_HEIGHT: f64 = 0.4;
/// An object has arrived where it stands when an earlier scan saw farther along every
/// direction up to this far (m) to either side of its points: a pose error or a thin post's
/// narrow silhouette in a far view does not make a static object look arrived.
const ARRIVAL_HALF_WIDTH: f64 = 0.4;
/// An object has left the place of a probe when the scan now sees farther along every
/// direction up to this far (m) to either side of it: near the sensor a cell is a few
/// centimetres wide, and the pose's error would otherwise show a close post as gone.
const LEFT_HALF_WIDTH: f64 = 0.15;
/// A moving track that stays within this (m) of one place for [`STILL_TIME`] is judged
/// afresh: a pedestrian who stopped, or a track that slid from a person onto a tree beside
/// them and, judged moving, reported the tree as the person.
const STILL_RADIUS: f64 = 1.0;
/// How long (s) a moving track stays within [`STILL_RADIUS`] before it is judged afresh
/// (2 s cost a pedestrian who waits a moment).
const STILL_TIME: f64 = 3.0;
/// A track whose cluster lies this far (m) from where its probes were taken... (a truck
/// passing at highway speed is gone in half a second, before `motion_probe_min_age` lets a
/// walker's probes clear their body; 1.5 m gave as many false positives as it won misses)
const FAST_STEP: f64 = 3.0;
/// ...judges its motion on probes from the scan before (s).
const FAST_PROBE_MIN_AGE: f64 = 0.05;
/// A moving track whose probes, `motion_probe_max_age` old, the scan still hits in this
/// share of those it decides on has not left: it stands still (a static car whose track
/// alternates with a post beside it, judged moving because it came into view).
const STAYED_FRACTION: f64 = 0.8;
/// Decided probes (seen through or hit) needed to judge motion.
const MIN_DECIDED_PROBES: usize = 6;
/// Tracks matched at most this many times are young: their arrival is also judged against
/// the scan from before their birth.
pub(super) const YOUNG_HITS: u32 = 3;
/// ...unless their view lies within this (m) of a moving track's box: a fragment of a moving
/// object arrived as much as the object did, and is no other object.
pub(super) const BESIDE_MOVING_MARGIN: f64 = 2.0;

/// The motion state of one track: whether it moves, and the probes that tell.
#[derive(Clone, Debug)]
pub(super) struct Movement {
    moving: bool,
    /// While moving: where the track was when it last moved [`STILL_RADIUS`] away from the
    /// place before, and when (s).
    still_since: (Vector2<f64>, f64),
    /// Points of an earlier cluster of the track (world frame) and when they were seen.
    probes: Vec<Vector3<f64>>,
    probe_time: f64,
}

/// What one view of a track shows the motion test.
#[derive(Clone, Copy, Debug)]
pub(super) struct Sighting<'a> {
    /// The cluster's points, world frame.
    pub points: &'a [Point],
    /// Their centroid.
    pub centroid: &'a Vector3<f64>,
    /// Shaped like an object and where the track was predicted: where it stands now may have
    /// been free space a moment ago.
    pub may_have_arrived: bool,
    /// It lies within [`BESIDE_MOVING_MARGIN`] of a moving track's box.
    pub beside_moving: bool,
}

/// The track a [`Movement`] belongs to, as the test reads it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Subject {
    /// Its id, for the log.
    pub id: u64,
    /// Its matches, this view's included.
    pub hits: u32,
    /// Its position after this view.
    pub position: Vector2<f64>,
}

impl Movement {
    /// A track born at `position` at `timestamp`, not (yet) seen to move.
    pub(super) fn new(position: Vector2<f64>, timestamp: f64) -> Self {
        Self {
            moving: false,
            still_since: (position, timestamp),
            probes: Vec::new(),
            probe_time: timestamp,
        }
    }

    /// Whether the track has been seen to move.
    pub(super) fn is_moving(&self) -> bool {
        self.moving
    }

    /// Judges whether track `track`, just matched to `seen.points`, moves: where it was a
    /// moment ago is free space now (it left), or, when `seen.may_have_arrived`, where it is
    /// now was free space across its width a moment ago (it arrived: the place it left may
    /// stay hidden behind it, when it comes nearer or follows the vehicle). Keeps fresh
    /// probes while it does not.
    pub(super) fn judge(
        &mut self,
        track: Subject,
        seen: &Sighting<'_>,
        scan: &ScanContext<'_>,
        c: &ClassifyConfig,
    ) {
        let Some((views, now)) = scan.views.and_then(|v| Some((v, v.latest()?))) else {
            return;
        };
        let points = seen.points;
        let age = scan.timestamp - self.probe_time;
        if self.moving {
            let here = track.position;
            if (here - self.still_since.0).norm() > STILL_RADIUS {
                self.still_since = (here, scan.timestamp);
            } else if scan.timestamp - self.still_since.1 >= STILL_TIME {
                tracing::trace!("track {} has stood still: motion judged afresh", track.id);
                self.moving = false;
                self.probes.clear();
                return;
            }
            if !self.probes.is_empty() && age >= c.motion_probe_max_age {
                let (through, hit) = self.left_counts(now);
                if mostly_hit((through, hit)) {
                    tracing::trace!(
                        "track {} has not left: seen through {through}, hit {hit}",
                        track.id
                    );
                    self.moving = false;
                    self.probes.clear();
                    return;
                }
            }
            if self.probes.is_empty() || age >= c.motion_probe_max_age {
                self.take_probes(points, scan);
            }
            return;
        }
        let moved_far = has_moved_far(&self.probes, seen.centroid);
        let min_age = if moved_far {
            FAST_PROBE_MIN_AGE
        } else {
            c.motion_probe_min_age
        };
        if !self.probes.is_empty() && age >= min_age {
            let then = views.at(self.probe_time);
            // A person-sized track whose probes are free now but whose cluster stood where it
            // stands when they were taken slid from a walker onto a post beside them.
            let slid =
                person_sized(points, c) && then.is_some_and(|v| stood_there(v, points, scan));
            let left = if slid { (0, 0) } else { self.left_counts(now) };
            // A cluster far from where the track stood may be another one it jumped to, seen
            // then between what stood in front of it: only the plain test tells its arrival.
            let visibility = if moved_far {
                RangeImage::visibility_across
            } else {
                RangeImage::visibility_past_occluders
            };
            let arrived = then
                .filter(|_| seen.may_have_arrived)
                .map_or((0, 0), |then| {
                    arrived_counts(then, points, scan, visibility)
                });
            for (way, counts) in [("left", left), ("arrived", arrived)] {
                if self.start_moving_if_free(track, counts, way, scan, c) {
                    return;
                }
            }
        }
        if self.probes.is_empty() || age > c.motion_probe_max_age {
            self.take_probes(points, scan);
        }
        // A young track's probes are too fresh to tell anything yet; where it stands now may
        // have been free space in the scan that long before its birth (a walker who came out
        // from behind a parked car, a truck that drove into view).
        let before_birth =
            (track.hits <= YOUNG_HITS && seen.may_have_arrived && !seen.beside_moving)
                .then(|| views.before(self.probe_time, c.motion_probe_min_age))
                .flatten();
        if let Some(then) = before_birth {
            // Before its birth nothing of the track says what stood behind what hid it then,
            // and the plain test is kept: judged past occluders (1 m gap), a person-sized
            // object 20 m away on KITTI 0000 that no label marks was seen to arrive at its
            // birth (15 false positives).
            let counts = arrived_counts(then, points, scan, RangeImage::visibility_across);
            self.start_moving_if_free(track, counts, "arrived before its birth", scan, c);
        }
    }

    /// Replaces the probes with those of the cluster's `points` in this scan.
    fn take_probes(&mut self, points: &[Point], scan: &ScanContext<'_>) {
        self.probes.clear();
        self.probes.extend(probe_points(points, scan));
        self.probe_time = scan.timestamp;
    }

    /// How many of the probes the scan `now` sees through and how many it hits: whether the
    /// object has left the place they were taken. What stands well in front of a probe does
    /// not count: a walker coming along the line of sight hides the place they left from the
    /// rows of their own body, and a parked car the rows of their legs.
    fn left_counts(&self, now: &View) -> (usize, usize) {
        count_views(now, self.probes.iter().copied(), left_visibility)
    }

    /// Judges the track moving when at least [`MIN_DECIDED_PROBES`] of its probes were
    /// decided (`counts`: seen through, hit) and `moving_free_fraction` of them were seen
    /// through; `way` says how, for the log. Returns whether it did.
    fn start_moving_if_free(
        &mut self,
        track: Subject,
        (through, hit): (usize, usize),
        way: &str,
        scan: &ScanContext<'_>,
        c: &ClassifyConfig,
    ) -> bool {
        let free = through + hit >= MIN_DECIDED_PROBES
            && through as f64 >= c.moving_free_fraction * (through + hit) as f64;
        if free {
            tracing::trace!(
                "track {} moves ({way}): seen through {through}, hit {hit}",
                track.id
            );
            self.moving = true;
            self.still_since = (track.position, scan.timestamp);
        }
        free
    }
}

/// Whether, of the probes a view decides on (`counts`: seen through, hit), at least
/// [`MIN_DECIDED_PROBES`] and [`STAYED_FRACTION`] of them were hit: something stands there.
fn mostly_hit((through, hit): (usize, usize)) -> bool {
    hit >= MIN_DECIDED_PROBES && hit as f64 >= STAYED_FRACTION * (through + hit) as f64
}

/// Whether `points` reach no farther along x or y than a pedestrian's length.
fn person_sized(points: &[Point], c: &ClassifyConfig) -> bool {
    let b = Bounds::of(points);
    (0..2).all(|k| f64::from(b.max[k] - b.min[k]) <= c.pedestrian_max_length)
}

/// Whether the earlier view `then` hit the probe points of a cluster's `points` where they
/// are (in [`STAYED_FRACTION`] of those it decides on): the cluster stood there then.
fn stood_there(then: &View, points: &[Point], scan: &ScanContext<'_>) -> bool {
    mostly_hit(count_views(then, probe_points(points, scan), |image, p| {
        image.visibility_across(p, 0.0)
    }))
}

/// How many of the probe points of a cluster's `points` the earlier view `then` saw through
/// and how many it hit, as `visibility` judges them: whether where the cluster stands now was
/// free space then.
fn arrived_counts(
    then: &View,
    points: &[Point],
    scan: &ScanContext<'_>,
    visibility: fn(&RangeImage, &Vector3<f64>, f64) -> Visibility,
) -> (usize, usize) {
    count_views(then, probe_points(points, scan), |image, p| {
        visibility(image, p, ARRIVAL_HALF_WIDTH)
    })
}

/// Whether the cluster centred at `centroid` lies farther than [`FAST_STEP`] from the mean
/// of the `probes` kept of the track: a vehicle passing at highway speed, or the visible part
/// of a wall sliding along with the sensor, which the probes' visibility then tells apart.
fn has_moved_far(probes: &[Vector3<f64>], centroid: &Vector3<f64>) -> bool {
    if probes.is_empty() {
        return false;
    }
    let then = probes.iter().sum::<Vector3<f64>>() / probes.len() as f64;
    (centroid - then).xy().norm() > FAST_STEP
}

/// Up to [`PROBES`] of a cluster's `points`, spread over it, that stand clear of the ground.
fn probe_points<'p>(
    points: &'p [Point],
    scan: &'p ScanContext<'_>,
) -> impl Iterator<Item = Vector3<f64>> + 'p {
    let stride = points.len().div_ceil(PROBES * 2).max(1);
    points
        .iter()
        .step_by(stride)
        .map(|p| Vector3::new(p.x as f64, p.y as f64, p.z as f64))
        .filter(|p| scan.ground.height(p) >= PROBE_MIN_HEIGHT)
        .take(PROBES)
}

/// What `image` shows of the sensor-frame point `p` when asked whether an object has left it:
/// what stands well in front of it does not count (see [`LEFT_HALF_WIDTH`]).
fn left_visibility(image: &RangeImage, p: &Vector3<f64>) -> Visibility {
    image.visibility_past_occluders(p, LEFT_HALF_WIDTH)
}

/// Whether the scan `now` sees through every one of the world-frame `points`, judged as a
/// track's probes are when it is asked whether the object has left them: nothing stands there.
pub(super) fn seen_through_all(now: &View, points: &[Vector3<f64>]) -> bool {
    count_views(now, points.iter().copied(), left_visibility).0 == points.len()
}

/// How many of the world-frame `points` `view` saw through (free space then) and how many it
/// hit, as `visibility` judges a sensor-frame point in its image.
fn count_views(
    view: &View,
    points: impl Iterator<Item = Vector3<f64>>,
    visibility: impl Fn(&RangeImage, &Vector3<f64>) -> Visibility,
) -> (usize, usize) {
    let to_sensor = view.pose.inverse();
    let (mut through, mut hit) = (0, 0);
    for p in points {
        match visibility(&view.image, &(to_sensor * Point3::from(p)).coords) {
            Visibility::SeenThrough => through += 1,
            Visibility::Hit => hit += 1,
            Visibility::Hidden | Visibility::Unknown => {}
        }
    }
    (through, hit)
}

#[cfg(test)]
mod tests {
    use nalgebra::Isometry3;

    use super::*;
    use crate::track::Ground;
    use crate::track::tracker::tests::scan_at;

    /// The face of a post 0.2 m wide, 0.2-1.8 m up, at `x`, `y` (world frame, ground z = 0).
    fn post(x: f32, y: f32) -> Vec<Point> {
        let mut out = Vec::new();
        for row in 0..33 {
            for i in 0..5 {
                out.push(Point::new(
                    x,
                    y - 0.1 + 0.05 * i as f32,
                    0.2 + 0.05 * row as f32,
                    0.0,
                ));
            }
        }
        out
    }

    /// A view from a sensor 1.73 m above the world origin of the world-frame `points`.
    fn view(points: &[Point]) -> View {
        let pose = Isometry3::translation(0.0, 0.0, 1.73);
        let in_sensor: Vec<Point> = points
            .iter()
            .map(|p| Point::new(p.x, p.y, p.z - 1.73, 0.0))
            .collect();
        let mut image = RangeImage::default();
        image.build(&in_sensor);
        View {
            timestamp: 0.0,
            pose,
            image,
        }
    }

    #[test]
    fn a_post_stood_where_it_stands_a_walker_who_came_there_did_not() {
        let ground = Ground::horizontal(0.0);
        let scan = scan_at(0.5, &ground);
        // A wall 30 m away behind everything.
        let wall: Vec<Point> = (0..400)
            .flat_map(|i| {
                (0..30).map(move |k| Point::new(30.0, -10.0 + 0.05 * i as f32, 0.1 * k as f32, 0.0))
            })
            .collect();
        let here = post(10.0, 0.5);
        // The earlier view saw the post where it stands now...
        let with_post = view(&[wall.clone(), here.clone()].concat());
        assert!(stood_there(&with_post, &here, &scan));
        // ...or saw through that place to the wall: a walker who has arrived.
        let without = view(&wall);
        assert!(!stood_there(&without, &here, &scan));
        let c = ClassifyConfig::default();
        assert!(person_sized(&here, &c));
        assert!(!person_sized(&[here, post(12.0, 0.5)].concat(), &c));
    }
}
