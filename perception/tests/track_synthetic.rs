//! The tracker on synthetic clusters: boxes seen from a sensor (their visible faces only),
//! moving along straight lines, fed scan by scan.

mod track_support;

use nalgebra::{Isometry3, Vector2, Vector3};
use track_support::{FLAT, flat_clusters};
use trackd_perception::track::{AssociationMode, Ground, ScanContext, TrackConfig, Tracker};
use trackd_perception::{ObjectClass, Point};

/// A box moving at constant velocity.
#[derive(Clone, Copy)]
struct Body {
    start: Vector2<f64>,
    velocity: Vector2<f64>,
    size: Vector3<f64>,
    /// A rider on a bicycle: above 1.1 m only the central 0.6 m of the length is body.
    rider: bool,
}

impl Body {
    fn center(&self, t: f64) -> Vector2<f64> {
        self.start + self.velocity * t
    }

    fn heading(&self) -> f64 {
        if self.velocity.norm() > 0.0 {
            self.velocity.y.atan2(self.velocity.x)
        } else {
            0.0
        }
    }

    /// Points on the faces that look at the sensor at the origin, from 0.2 m above the ground
    /// to the top.
    fn visible_points(&self, t: f64, spacing: f64) -> Vec<Point> {
        let c = self.center(t);
        let yaw = self.heading();
        let axis = Vector2::new(yaw.cos(), yaw.sin());
        let normal = Vector2::new(-axis.y, axis.x);
        let (l, w, h) = (self.size.x, self.size.y, self.size.z);
        let faces = [
            (axis * l / 2.0, normal, w / 2.0),
            (-axis * l / 2.0, normal, w / 2.0),
            (normal * w / 2.0, axis, l / 2.0),
            (-normal * w / 2.0, axis, l / 2.0),
        ];
        let mut out = Vec::new();
        for (offset, dir, half) in faces {
            let fc = c + offset;
            if (-fc).dot(&offset) <= 0.0 {
                continue;
            }
            let n = (2.0 * half / spacing).ceil() as i32;
            let mut z = 0.2;
            while z <= h {
                for i in 0..=n {
                    let p = fc + dir * (-half + 2.0 * half * i as f64 / n as f64);
                    if self.rider && z > 1.1 && (p - c).dot(&axis).abs() > 0.3 {
                        continue;
                    }
                    out.push(Point::new(p.x as f32, p.y as f32, z as f32, 0.0));
                }
                z += spacing;
            }
        }
        out
    }
}

fn car(start: (f64, f64), velocity: (f64, f64)) -> Body {
    Body {
        start: Vector2::new(start.0, start.1),
        velocity: Vector2::new(velocity.0, velocity.1),
        size: Vector3::new(4.4, 1.8, 1.5),
        rider: false,
    }
}

fn cyclist(start: (f64, f64), velocity: (f64, f64)) -> Body {
    Body {
        start: Vector2::new(start.0, start.1),
        velocity: Vector2::new(velocity.0, velocity.1),
        size: Vector3::new(1.8, 0.6, 1.75),
        rider: true,
    }
}

/// Spacing (m) of a 64-beam scanner's returns on a surface `range` metres away (some 0.43°, a
/// person 10 m away gets ~300 points), at most 0.15 m.
fn scan_spacing(range: f64) -> f64 {
    (0.0075 * range).clamp(0.03, 0.15)
}

/// Output of one scan: (track id, class, world centre) of each reported track.
type Reported = Vec<(u64, ObjectClass, Vector3<f64>)>;

/// Runs the tracker over `scans` scans at 10 Hz; `visible(k, i)` says whether body `i` is
/// seen in scan `k`.
fn run(
    config: TrackConfig,
    bodies: &[Body],
    scans: usize,
    visible: impl Fn(usize, usize) -> bool,
) -> Vec<Reported> {
    run_within(config, bodies, scans, visible, f64::INFINITY)
}

/// [`run`] with the scans cut at `range_limit` metres.
fn run_within(
    config: TrackConfig,
    bodies: &[Body],
    scans: usize,
    visible: impl Fn(usize, usize) -> bool,
    range_limit: f64,
) -> Vec<Reported> {
    drive(
        &mut Tracker::new(config),
        bodies,
        scans,
        visible,
        range_limit,
    )
}

/// Feeds `tracker` the scans of [`run_within`].
fn drive(
    tracker: &mut Tracker,
    bodies: &[Body],
    scans: usize,
    visible: impl Fn(usize, usize) -> bool,
    range_limit: f64,
) -> Vec<Reported> {
    let clouds = |k: usize| {
        let t = k as f64 * 0.1;
        bodies
            .iter()
            .enumerate()
            .filter(|(i, _)| visible(k, *i))
            .map(|(_, b)| b.visible_points(t, scan_spacing(b.center(t).norm())))
            .collect()
    };
    drive_clouds(tracker, scans, clouds, range_limit)
}

/// Feeds `tracker` `scans` scans at 10 Hz, scan `k` holding the clusters `clouds(k)` (world
/// frame) cut at `range_limit` metres, seen by a sensor 1.73 m above the origin; returns what
/// each scan reports.
fn drive_clouds(
    tracker: &mut Tracker,
    scans: usize,
    clouds: impl Fn(usize) -> Vec<Vec<Point>>,
    range_limit: f64,
) -> Vec<Reported> {
    let cdf = FLAT.cdf();
    let ground = Ground::horizontal(0.0);
    let mut out = Vec::new();
    for k in 0..scans {
        let t = k as f64 * 0.1;
        let clouds = clouds(k);
        let clusters = flat_clusters(&clouds, &cdf);
        let scan = ScanContext {
            timestamp: t,
            pose: Isometry3::translation(0.0, 0.0, 1.73),
            ground: &ground,
            range_limit,
            views: None,
        };
        tracker.step(&scan, &clusters);
        out.push(
            tracker
                .reported()
                .map(|tr| {
                    let s = tr.state();
                    (s.id, s.class, s.center)
                })
                .collect(),
        );
    }
    out
}

/// The reported track nearest to `p` (BEV) within 2 m.
fn near(reported: &Reported, p: Vector2<f64>) -> Option<(u64, ObjectClass, f64)> {
    reported
        .iter()
        .map(|(id, class, c)| (*id, *class, (c.xy() - p).norm()))
        .filter(|(_, _, d)| *d < 2.0)
        .min_by(|a, b| a.2.total_cmp(&b.2))
}

#[test]
fn a_car_driving_away_keeps_one_id_and_its_true_centre() {
    // Seen from behind only: its centroid lies ~2 m before its centre.
    let body = car((8.0, 0.0), (5.0, 0.0));
    let out = run(TrackConfig::default(), &[body], 30, |_, _| true);
    let mut ids = Vec::new();
    for (k, reported) in out.iter().enumerate().skip(1) {
        let truth = body.center(k as f64 * 0.1);
        let (id, class, d) = near(reported, truth).unwrap_or_else(|| panic!("scan {k}: lost"));
        assert!(d < 0.5, "scan {k}: centre {d:.2} m off");
        assert_eq!(class, ObjectClass::Car);
        ids.push(id);
        assert_eq!(reported.len(), 1, "scan {k}: {reported:?}");
    }
    ids.dedup();
    assert_eq!(ids.len(), 1, "one id for the whole drive: {ids:?}");
}

#[test]
fn a_highway_car_is_reported_from_its_first_scan() {
    // 30 m/s (3 m per scan) crossing in front, an oncoming one at 33 m/s, and a parked one:
    // each identified in its first view and followed from there.
    let bodies = [
        car((-30.0, 12.0), (30.0, 0.0)),
        car((60.0, -4.0), (-33.0, 0.0)),
        car((10.0, 6.0), (0.0, 0.0)),
    ];
    let out = run(TrackConfig::default(), &bodies, 20, |_, _| true);
    for (k, reported) in out.iter().enumerate() {
        for (i, b) in bodies.iter().enumerate() {
            let truth = b.center(k as f64 * 0.1);
            assert!(
                near(reported, truth).is_some(),
                "scan {k}: body {i} at {truth:?} not reported: {reported:?}"
            );
        }
        assert_eq!(reported.len(), bodies.len(), "scan {k}: {reported:?}");
    }
}

#[test]
fn two_cyclists_side_by_side_never_swap() {
    // Riders 1 m apart (centre to centre), closing to 0.6 m by the last scan, riding together.
    let a = cyclist((6.0, 1.0), (5.0, 0.0));
    let b = cyclist((6.0, 2.0), (5.0, -0.1));
    let out = run(TrackConfig::default(), &[a, b], 40, |_, _| true);
    let mut ids: Option<(u64, u64)> = None;
    for (k, reported) in out.iter().enumerate().skip(1) {
        let t = k as f64 * 0.1;
        let (ia, ca, da) = near(reported, a.center(t)).expect("rider a reported");
        let (ib, _, db) = near(reported, b.center(t)).expect("rider b reported");
        assert!(da < 0.45 && db < 0.45, "scan {k}: {da:.2} / {db:.2} m off");
        assert_ne!(ia, ib);
        assert_eq!(ca, ObjectClass::Cyclist);
        match ids {
            None => ids = Some((ia, ib)),
            Some(expected) => assert_eq!((ia, ib), expected, "scan {k}: swap"),
        }
    }
}

#[test]
fn a_short_occlusion_keeps_the_id_and_a_long_one_drops_the_track() {
    let body = car((10.0, -3.0), (4.0, 1.0));
    // Hidden in scans 10..13 (0.3 s).
    let out = run(TrackConfig::default(), &[body], 25, |k, _| {
        !(10..13).contains(&k)
    });
    let id_before = near(&out[9], body.center(0.9)).expect("seen").0;
    let id_after = near(&out[14], body.center(1.4)).expect("seen again").0;
    assert_eq!(id_before, id_after);
    // Coasting is reported for a couple of scans at the predicted position.
    assert!(near(&out[10], body.center(1.0)).is_some());
    // Gone for good from scan 5: reported no longer after a short coast.
    let out = run(TrackConfig::default(), &[body], 30, |k, _| k < 5);
    assert!(out[29].is_empty());
    assert!(out[5..].iter().filter(|r| !r.is_empty()).count() <= 2);
}

#[test]
fn structure_is_not_reported() {
    let wall = Body {
        start: Vector2::new(5.0, 9.0),
        velocity: Vector2::zeros(),
        size: Vector3::new(25.0, 0.4, 3.0),
        rider: false,
    };
    let pole = Body {
        start: Vector2::new(8.0, -4.0),
        velocity: Vector2::zeros(),
        size: Vector3::new(0.25, 0.25, 5.0),
        rider: false,
    };
    let kerb = Body {
        start: Vector2::new(12.0, 4.0),
        velocity: Vector2::zeros(),
        size: Vector3::new(8.0, 0.3, 0.35),
        rider: false,
    };
    let parked = car((15.0, -6.0), (0.0, 0.0));
    let out = run(
        TrackConfig::default(),
        &[wall, pole, kerb, parked],
        10,
        |_, _| true,
    );
    for reported in &out[1..] {
        assert_eq!(reported.len(), 1, "only the parked car: {reported:?}");
        assert!(near(reported, parked.center(0.0)).is_some());
    }
}

#[test]
fn every_association_mode_tracks_a_lone_car() {
    for mode in [
        AssociationMode::Chi2,
        AssociationMode::Chi2Mdt,
        AssociationMode::Chi2MdtMotion,
        AssociationMode::GatedAssignment,
    ] {
        let mut config = TrackConfig::default();
        config.association.mode = mode;
        let body = car((12.0, 4.0), (-3.0, 2.0));
        let out = run(config, &[body], 15, |_, _| true);
        let ids: std::collections::BTreeSet<u64> = out
            .iter()
            .enumerate()
            .skip(1)
            .map(|(k, r)| {
                let (id, _, d) = near(r, body.center(k as f64 * 0.1)).expect("reported");
                assert!(d < 0.5, "{mode:?}, scan {k}: {d:.2} m off");
                id
            })
            .collect();
        assert!(out[1..].iter().all(|r| r.len() == 1), "{mode:?}");
        assert_eq!(ids.len(), 1, "{mode:?}");
    }
}

fn pedestrian(start: (f64, f64)) -> Body {
    Body {
        start: Vector2::new(start.0, start.1),
        velocity: Vector2::zeros(),
        size: Vector3::new(0.6, 0.5, 1.75),
        rider: false,
    }
}

/// The ids reported near `a` in scans `before` and near `b` in scan `after`.
fn ids_near(out: &[Reported], a: &Body, before: usize, b: &Body, after: usize) -> (u64, u64) {
    let (first, class, _) = near(&out[before], a.center(0.0)).expect("first person reported");
    assert_eq!(class, ObjectClass::Pedestrian);
    let (second, _, _) = near(&out[after], b.center(0.0)).expect("second person reported");
    (first, second)
}

#[test]
fn a_coasting_pedestrian_track_does_not_jump_to_a_person_metres_away() {
    // One person 35 m away stands for 5 scans and is then hidden; a second one steps out
    // 3.2 m away half a second later, inside the gate the first track's coasting has grown.
    let (a, b) = (pedestrian((35.0, 3.0)), pedestrian((35.0, 6.2)));
    let visible = |k: usize, i: usize| if i == 0 { k < 5 } else { k >= 10 };
    let out = run(TrackConfig::default(), &[a, b], 15, visible);
    let (first, second) = ids_near(&out, &a, 4, &b, 14);
    assert_ne!(
        first, second,
        "the second person took the first one's track"
    );
    // Without the bound on a person's speed, the motion gate alone lets the track jump.
    let mut config = TrackConfig::default();
    config.motion.pedestrian_max_speed = f64::INFINITY;
    let out = run(config, &[a, b], 15, visible);
    let (first, second) = ids_near(&out, &a, 4, &b, 14);
    assert_eq!(
        first, second,
        "the gate alone no longer lets the track jump"
    );
}

#[test]
fn a_parked_car_hidden_until_its_track_is_dropped_gets_its_id_back() {
    // Seen for a second, hidden for three (the track is dropped), then seen again.
    let parked = car((15.0, -6.0), (0.0, 0.0));
    let visible = |k: usize, _: usize| !(10..40).contains(&k);
    let out = run(TrackConfig::default(), &[parked], 45, visible);
    let before = near(&out[9], parked.center(0.0)).expect("seen").0;
    let after = near(&out[44], parked.center(0.0)).expect("seen again").0;
    assert_eq!(before, after, "a new id for the same parked car");
    // Without the memory the returning car is a new track: the first one was dropped.
    let mut config = TrackConfig::default();
    config.dormant.memory = 0.0;
    let out = run(config, &[parked], 45, visible);
    let before = near(&out[9], parked.center(0.0)).expect("seen").0;
    let after = near(&out[44], parked.center(0.0)).expect("seen again").0;
    assert_ne!(
        before, after,
        "the track survived the occlusion: nothing was remembered"
    );
}

#[test]
fn a_person_stepping_up_beside_a_tracked_person_is_a_second_track() {
    // The second person stops 0.7 m beside the first (centre to centre), inside the first
    // track's box and margin: not a fragment of it, but another person.
    let (a, b) = (pedestrian((20.0, 2.0)), pedestrian((20.0, 2.7)));
    let out = run(TrackConfig::default(), &[a, b], 12, |k, i| i == 0 || k >= 5);
    for (k, reported) in out.iter().enumerate().skip(7) {
        let (first, _, _) = near(reported, a.center(0.0)).expect("first person reported");
        let second = reported
            .iter()
            .find(|(_, _, c)| (c.xy() - b.center(0.0)).norm() < 0.3)
            .unwrap_or_else(|| panic!("scan {k}: second person not reported: {reported:?}"));
        assert_ne!(first, second.0);
        assert_eq!(second.1, ObjectClass::Pedestrian);
    }
}

#[test]
fn a_person_walking_past_a_hidden_post_is_not_taken_for_it() {
    // A post 20 m ahead, seen up to where the highest beam passes (2 degrees up: cut by the
    // field of view), is hidden for 1.2 s, as behind a passing car. After 0.7 s a person walks
    // out of that shadow 1.7 m beside it, inside the gate the post's track has grown while it
    // coasted: a person, whole and 0.7 m lower than the post's cut top, is no view of it.
    // Taken for the post, the person was reported six scans late, once the post's votes faded.
    let post = Body {
        start: Vector2::new(20.0, 0.0),
        velocity: Vector2::zeros(),
        size: Vector3::new(0.2, 0.2, 1.73 + 20.0 * 2.0f64.to_radians().tan()),
        rider: false,
    };
    let person = Body {
        velocity: Vector2::new(0.0, 1.0),
        ..pedestrian((20.0, -2.0))
    };
    let visible = |k: usize, i: usize| {
        if i == 0 {
            !(30..42).contains(&k)
        } else {
            k >= 37
        }
    };
    let out = run(TrackConfig::default(), &[post, person], 50, visible);
    assert!(out[29].is_empty(), "the post was reported: {:?}", out[29]);
    for (k, reported) in out.iter().enumerate().skip(39) {
        let (_, class, _) = near(reported, person.center(k as f64 * 0.1))
            .unwrap_or_else(|| panic!("scan {k}: the person is not reported: {reported:?}"));
        assert_eq!(class, ObjectClass::Pedestrian);
    }
}

/// A tree standing at `(x, y)`: a trunk 0.2 m wide up to 1.5 m and a crown 1.6 m wide from
/// 1.5 m to 3 m, the faces that look at the sensor at the origin.
fn tree(x: f64, y: f64) -> Vec<Point> {
    let mut out = Vec::new();
    for row in 0..29 {
        let z = 0.2 + 0.1 * f64::from(row);
        let half: f64 = if z < 1.5 { 0.1 } else { 0.8 };
        for i in 0..=(2.0 * half / 0.1).round() as i32 {
            let across = y - half + 0.1 * f64::from(i);
            out.push(Point::new(x as f32, across as f32, z as f32, 0.0));
        }
    }
    out
}

/// A person stands 20 m ahead for a second, then steps 0.5 m aside as a tree comes into view
/// right where they stood; returns the id of the track reported on the person in each scan.
fn ids_of_a_person_stepping_away_from_a_tree(config: TrackConfig) -> Vec<u64> {
    let person = |k: usize| pedestrian((20.0, if k < 10 { 2.0 } else { 1.5 }));
    let clouds = |k: usize| {
        let mut clouds = vec![person(k).visible_points(0.0, scan_spacing(20.0))];
        if k >= 10 {
            clouds.push(tree(20.0, 2.0));
        }
        clouds
    };
    let out = drive_clouds(&mut Tracker::new(config), 16, clouds, f64::INFINITY);
    out.iter()
        .enumerate()
        .map(|(k, reported)| {
            let (id, class, _) = near(reported, person(k).center(0.0))
                .unwrap_or_else(|| panic!("scan {k}: the person is not reported: {reported:?}"));
            assert_eq!(class, ObjectClass::Pedestrian);
            id
        })
        .collect()
}

#[test]
fn a_pedestrian_track_keeps_the_person_over_a_tree_where_it_expected_them() {
    // The tree's view lies nearer the track's prediction, but a person shows no tree of
    // themselves.
    let ids = ids_of_a_person_stepping_away_from_a_tree(TrackConfig::default());
    assert!(
        ids.iter().all(|&id| id == ids[0]),
        "the person's ids per scan: {ids:?}"
    );
    // Without the cost of such a view, the track takes the tree and the person a new id.
    let mut config = TrackConfig::default();
    config.association.unlike_structure_cost = 0.0;
    let ids = ids_of_a_person_stepping_away_from_a_tree(config);
    assert_ne!(
        ids[9], ids[15],
        "the track kept the person without the cost"
    );
}

#[test]
fn a_person_stepping_up_beside_tracked_structure_is_reported() {
    // A kiosk taller than any car (an object only if it moves: tracked, never reported), and a
    // person who stops 0.2 m beside it, inside its track's box and margin: no fragment of an
    // object, but a person.
    let kiosk = Body {
        start: Vector2::new(20.0, 2.0),
        velocity: Vector2::zeros(),
        size: Vector3::new(2.0, 1.5, 2.6),
        rider: false,
    };
    let person = pedestrian((20.0, 0.8));
    let out = run(TrackConfig::default(), &[kiosk, person], 14, |k, i| {
        i == 0 || k >= 5
    });
    assert!(out[4].is_empty(), "the kiosk was reported: {:?}", out[4]);
    for (k, reported) in out.iter().enumerate().skip(9) {
        let (_, class, _) = near(reported, person.center(0.0))
            .unwrap_or_else(|| panic!("scan {k}: the person is not reported: {reported:?}"));
        assert_eq!(class, ObjectClass::Pedestrian);
    }
}

#[test]
fn a_car_driving_off_keeps_its_class_while_the_range_limit_cuts_its_views() {
    // Identified up close, then 18 scans at the 45 m limit: such views tell nothing of what
    // the object is, and do not outvote the views that did.
    let body = car((35.0, 0.0), (5.0, 0.0));
    let out = run_within(TrackConfig::default(), &[body], 40, |_, _| true, 45.0);
    let mut ids = Vec::new();
    for (k, reported) in out.iter().enumerate().skip(1) {
        let truth = body.center(k as f64 * 0.1);
        let (id, class, _) = near(reported, truth).unwrap_or_else(|| panic!("scan {k}: lost"));
        assert_eq!(class, ObjectClass::Car, "scan {k}");
        ids.push(id);
    }
    ids.dedup();
    assert_eq!(ids.len(), 1, "one id: {ids:?}");
}

#[test]
fn a_pedestrian_track_does_not_grow_into_the_wall_it_walks_along() {
    // A person identified alone, then seen in one cluster with a wall behind them that shows
    // more of itself every scan (the sensor driving past): the person's track must not take
    // ever longer pieces of the wall and walk off along it.
    let person = pedestrian((15.0, 3.0));
    let mut tracker = Tracker::new(TrackConfig::default());
    let cdf = FLAT.cdf();
    let ground = Ground::horizontal(0.0);
    let mut person_id = None;
    for k in 0..30 {
        let t = k as f64 * 0.1;
        let mut cloud = person.visible_points(t, scan_spacing(15.0));
        if k >= 5 {
            let wall = Body {
                start: Vector2::new(15.5, 3.0 + 0.25 * (k - 5) as f64),
                velocity: Vector2::zeros(),
                size: Vector3::new(0.2, 0.6 + 0.5 * (k - 5) as f64, 2.2),
                rider: false,
            };
            cloud.extend(wall.visible_points(t, scan_spacing(15.0)));
        }
        let clouds = [cloud];
        let clusters = flat_clusters(&clouds, &cdf);
        let scan = ScanContext {
            timestamp: t,
            pose: Isometry3::translation(0.0, 0.0, 1.73),
            ground: &ground,
            range_limit: f64::INFINITY,
            views: None,
        };
        tracker.step(&scan, &clusters);
        if k == 4 {
            let (id, class, _) = tracker
                .reported()
                .map(|tr| {
                    let s = tr.state();
                    (s.id, s.class, s.center)
                })
                .find(|(_, _, c)| (c.xy() - person.center(0.0)).norm() < 0.5)
                .expect("the person is reported");
            assert_eq!(class, ObjectClass::Pedestrian);
            person_id = Some(id);
        }
        if let Some(track) = tracker
            .tracks()
            .iter()
            .find(|tr| Some(tr.id()) == person_id)
        {
            let s = track.state();
            let length = s.size.x.max(s.size.y);
            assert!(
                length < 2.0,
                "scan {k}: the person's track is {length:.1} m long"
            );
        }
    }
}

#[test]
fn a_second_track_on_a_car_claims_none_of_it_and_is_not_reported() {
    // A car track that comes within 0.6 m of a parked car's (a car seen in two pieces for a
    // while leaves two tracks on it): only the parked car's, matched as often and older,
    // guides the splitting of the cluster there, and only it is reported.
    let parked = car((20.0, 5.0), (0.0, 0.0));
    let second = car((15.0, 5.0), (1.0, 0.0));
    let mut tracker = Tracker::new(TrackConfig::default());
    let out = drive(&mut tracker, &[parked, second], 57, |_, _| true, 50.0);
    let parked_id = near(&out[2], parked.start).unwrap().0;
    assert_eq!(tracker.tracks().len(), 2, "two tracks live on the car");
    let last: Vec<u64> = out.last().unwrap().iter().map(|r| r.0).collect();
    assert_eq!(last, vec![parked_id]);
    let boxes: Vec<u64> = tracker.predicted_boxes(5.7).map(|b| b.id).collect();
    assert_eq!(boxes, vec![parked_id]);
    // Two cars parked side by side, 1.9 m apart, each keep their box and are reported.
    let beside = car((20.0, 6.9), (0.0, 0.0));
    let mut tracker = Tracker::new(TrackConfig::default());
    let out = drive(&mut tracker, &[parked, beside], 8, |_, _| true, 50.0);
    assert_eq!(tracker.predicted_boxes(0.8).count(), 2);
    assert_eq!(out.last().unwrap().len(), 2);
}

#[test]
fn a_parked_cars_heading_outlasts_a_few_views_that_read_it_crosswise() {
    // A car parked along x, seen as it is for 12 scans, then for 5 as if it stood across
    // (its outline 4.4 m along y): a parked track keeps its heading through them.
    let parked = car((20.0, 5.0), (0.0, 0.0));
    let mut crosswise = parked;
    crosswise.size = Vector3::new(1.8, 4.4, 1.5);
    let heading_after = |scans| {
        let mut tracker = Tracker::new(TrackConfig::default());
        let seen = |k: usize, i: usize| (i == 1) == (k >= 12);
        drive(&mut tracker, &[parked, crosswise], scans, seen, 50.0);
        let reported: Vec<_> = tracker.reported().map(|t| t.state()).collect();
        assert_eq!(reported.len(), 1, "{reported:?}");
        let yaw = reported[0].yaw.rem_euclid(std::f64::consts::PI);
        yaw.min(std::f64::consts::PI - yaw)
    };
    assert!(heading_after(17) < 0.1, "{}", heading_after(17));
    // Seen crosswise for longer, it is taken as a wrong start.
    let turned = heading_after(24);
    assert!(
        (turned - std::f64::consts::FRAC_PI_2).abs() < 0.1,
        "{turned}"
    );
}

/// The id of a parked car 30 m ahead, reported before it is hidden (from scan 20, as behind a
/// passing truck), and what is reported near a person who walks out 2.3 m before its box half
/// a second later, inside the gate the car's track has grown while it coasted, once the
/// person has been seen for 1.4 s (scan 38). Taken for the car, the person was reported as a
/// car, then late and 0.7 m behind.
fn ids_of_a_car_and_a_person_stepping_out_before_it(
    config: TrackConfig,
) -> (u64, Option<(u64, ObjectClass)>) {
    let parked = car((30.0, 0.0), (0.0, 0.0));
    let person = Body {
        velocity: Vector2::new(0.0, -1.0),
        ..pedestrian((25.5, 2.8))
    };
    let visible = |k: usize, i: usize| if i == 0 { k < 20 } else { k >= 25 };
    let out = run(config, &[parked, person], 39, visible);
    let (car_id, class, _) = near(&out[19], parked.center(0.0)).expect("the car is reported");
    assert_eq!(class, ObjectClass::Car);
    let seen = near(&out[38], person.center(3.8)).map(|(id, class, _)| (id, class));
    (car_id, seen)
}

#[test]
fn a_hidden_parked_cars_track_does_not_take_a_person_beside_it() {
    let (car_id, person) = ids_of_a_car_and_a_person_stepping_out_before_it(TrackConfig::default());
    let (person_id, class) = person.expect("the person is reported");
    assert_ne!(person_id, car_id, "the car's track took the person");
    assert_eq!(class, ObjectClass::Pedestrian);
    // Without the bound on a parked car's reach, the gate its coasting has grown lets it jump.
    let mut config = TrackConfig::default();
    config.motion.parked_max_acceleration = f64::INFINITY;
    let (car_id, person) = ids_of_a_car_and_a_person_stepping_out_before_it(config);
    assert_eq!(
        person.map(|(id, _)| id),
        Some(car_id),
        "the gate alone no longer lets the car's track jump"
    );
}

/// The ids of the tracks reported near a car parked 20 m ahead that comes into view corner
/// first: its near corner alone (1 × 1 m) in scan 0, a little more of it (1.7 × 1.6 m) in
/// scan 1, the whole car from scan 2 on; one list per scan.
fn ids_on_a_car_coming_into_view_corner_first() -> Vec<Vec<u64>> {
    let whole = car((20.0, 5.0), (0.0, 0.0));
    let corner = |l: f64, w: f64| Body {
        start: Vector2::new(17.8 + l / 2.0, 4.1 + w / 2.0),
        size: Vector3::new(l, w, 1.5),
        ..whole
    };
    let bodies = [corner(1.0, 1.0), corner(1.7, 1.6), whole];
    let shown = |k: usize, i: usize| i == k.min(2);
    let out = run(TrackConfig::default(), &bodies, 10, shown);
    out.iter()
        .map(|reported| {
            reported
                .iter()
                .filter(|(_, _, c)| (c.xy() - whole.start).norm() < 3.5)
                .map(|(id, _, _)| *id)
                .collect()
        })
        .collect()
}

#[test]
fn a_car_coming_into_view_corner_first_keeps_one_track() {
    let ids = ids_on_a_car_coming_into_view_corner_first();
    let first = ids[1]
        .first()
        .copied()
        .expect("the car is reported in scan 1");
    for (k, scan) in ids.iter().enumerate().skip(1) {
        assert_eq!(scan, &[first], "scan {k}: {ids:?}");
    }
}
