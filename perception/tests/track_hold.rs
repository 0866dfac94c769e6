//! A parked car seen from farther and farther shows less of itself: after a few clear views
//! only a corner that could be anything. The tracker keeps calling it a car while it stays
//! put; a car-shaped start whose unclear views slide along (the visible part of a hedge as
//! the vehicle passes) loses the identity. And a car is reported from its first view, but
//! coasts through missed scans only once seen twice. A far car's track does not take the post
//! or the sign beside it in the scans that miss the car, and keeps its identity through views
//! of a low piece of it.

mod track_support;

use nalgebra::Vector2;
use track_support::{nearest_distances, reported_per_scan, reported_states_per_scan};
use trackd_perception::Point;

/// The rear (x = 33 m) and the near side (y = 4.1 m) of a 4.5 x 1.8 m car, 0.2 m to 1.5 m
/// above the ground (world frame, ground at z = 0), every 0.1 m.
fn car() -> Vec<Point> {
    let mut out = Vec::new();
    for row in 0..14 {
        let z = 0.2 + 0.1 * f64::from(row);
        for i in 0..=18 {
            out.push(Point::new(
                33.0,
                (4.1 + 0.1 * f64::from(i)) as f32,
                z as f32,
                0.0,
            ));
        }
        for i in 1..=45 {
            out.push(Point::new(
                (33.0 + 0.1 * f64::from(i)) as f32,
                4.1,
                z as f32,
                0.0,
            ));
        }
    }
    out
}

/// A 1.2 x 1.1 m block face-on, 0.3 m to 1.5 m above the ground, its near corner at
/// (33, 4.1 + `shift`): wider at the top than a person, smaller than a car.
fn corner(shift: f64) -> Vec<Point> {
    let mut out = Vec::new();
    for row in 0..13 {
        let z = 0.3 + 0.1 * f64::from(row);
        for i in 0..=11 {
            let y = 4.1 + shift + 0.1 * f64::from(i);
            out.push(Point::new(33.0, y as f32, z as f32, 0.0));
        }
        for i in 1..=12 {
            out.push(Point::new(
                (33.0 + 0.1 * f64::from(i)) as f32,
                (4.1 + shift) as f32,
                z as f32,
                0.0,
            ));
        }
    }
    out
}

/// Runs 8 scans of the car at 10 Hz, then 16 of `later(k)` (k from 0); returns, per scan,
/// whether a track is reported.
fn reported(later: impl Fn(u32) -> Vec<Point>) -> Vec<bool> {
    reported_after(8, later)
}

/// Runs `first` scans of the car, then `24 - first` of `later(k)`.
fn reported_after(first: u32, later: impl Fn(u32) -> Vec<Point>) -> Vec<bool> {
    reported_per_scan(24, |k| if k < first { car() } else { later(k - first) })
}

#[test]
fn a_parked_car_seen_only_in_part_stays_a_car() {
    let out = reported(|_| corner(0.0));
    assert!(out[2..8].iter().all(|&r| r), "the car itself: {out:?}");
    assert!(out[8..].iter().all(|&r| r), "{out:?}");
}

#[test]
fn a_car_shaped_start_sliding_away_in_unclear_views_is_dropped() {
    let out = reported(|k| corner(0.5 * f64::from(k + 1)));
    assert!(out[2..8].iter().all(|&r| r), "the car itself: {out:?}");
    assert!(out[14..].iter().all(|&r| !r), "{out:?}");
}

#[test]
fn a_car_seen_in_one_scan_is_reported_in_that_scan_only() {
    // Identified in its first view, but one view may be a fragment: no coasting on it.
    let out = reported_after(1, |_| Vec::new());
    assert!(out[0], "{out:?}");
    assert!(out[1..].iter().all(|&r| !r), "{out:?}");
    // Seen twice, it coasts through two missed scans.
    let out = reported_after(2, |_| Vec::new());
    assert_eq!(&out[..5], [true, true, true, true, false], "{out:?}");
}

/// A 4.5 x 1.8 m car parked 44 m ahead: its rear (x = 44 m) and near side (y = 3.2 m).
fn far_car() -> Vec<Point> {
    car()
        .into_iter()
        .map(|p| Point::new(p.x + 11.0, p.y - 0.9, p.z, 0.0))
        .collect()
}

/// Its rear as a far scan shows it: its ends one or two columns short (1.5 m of it) and
/// only up to 0.8 m high, the beams above missing the rear window.
fn far_rear_strip() -> Vec<Point> {
    far_car()
        .into_iter()
        .filter(|p| p.x == 44.0 && p.y <= 4.75 && p.z <= 0.85)
        .collect()
}

#[test]
fn a_far_parked_car_whose_views_alternate_with_its_low_rear_stays_a_car() {
    // Seen whole once in three scans, in between only the low strip of its rear: the strip,
    // a column or two short of a car's width at 44 m, is the car's, not a low thing.
    let out = reported_per_scan(24, |k| {
        if k % 3 == 0 {
            far_car()
        } else {
            far_rear_strip()
        }
    });
    assert!(out[3..].iter().all(|&r| r), "{out:?}");
}

/// A metre of its rear from `bottom` to `top` metres above the ground: all a far scan may
/// show of it for a while (some beams missing the rear window, its ends dropping out).
fn far_rear_piece(bottom: f32, top: f32) -> Vec<Point> {
    far_car()
        .into_iter()
        .filter(|p| p.x == 44.0 && p.y < 4.25 && p.z > bottom && p.z < top)
        .collect()
}

#[test]
fn a_far_parked_car_seen_in_pieces_for_a_while_stays_a_car() {
    // Identified in its first eight views, then 14 scans of a low piece (0.3-0.8 m up: too
    // low for any object, too short for a car's even as tall as the car was seen) or of an
    // upper one (1.1-1.3 m up: floating): pieces of a car it holds as such tell nothing of
    // what it is, and do not vote it structure.
    let out = reported_per_scan(22, |k| match k {
        0..8 => far_car(),
        _ if k % 2 == 0 => far_rear_piece(0.25, 0.85),
        _ => far_rear_piece(1.05, 1.35),
    });
    assert!(out[3..].iter().all(|&r| r), "{out:?}");
}

/// A post 3 m tall, 0.1 m across, 1.5 m from the far car's near side, level with its rear.
fn post_beside_far_car() -> Vec<Point> {
    (0..29)
        .flat_map(|row| {
            let z = 0.2 + 0.1 * row as f32;
            [(44.0, 1.6), (44.0, 1.7), (44.1, 1.6), (44.1, 1.7)]
                .map(|(x, y)| Point::new(x, y, z, 0.0))
        })
        .collect()
}

/// A sign board 1.2 m wide, 1.8 m to 3 m above the ground, 1 m from the far car's near side,
/// level with its rear.
fn sign_beside_far_car() -> Vec<Point> {
    (0..13)
        .flat_map(|row| {
            let z = 1.8 + 0.1 * row as f32;
            (0..13).map(move |i| Point::new(44.0, 1.0 + 0.1 * i as f32, z, 0.0))
        })
        .collect()
}

/// Asserts that when, after four clear views of the far car, scans that show the car
/// alternate with scans that show only `other` (far away, the car's sparse returns come and
/// go), the nearest reported track stays within 0.5 m of the car's centre.
fn assert_track_stays_on_far_car(other: fn() -> Vec<Point>) {
    let reported = reported_states_per_scan(20, |k| {
        if k < 4 || k % 2 == 0 {
            far_car()
        } else {
            other()
        }
    });
    let errors = nearest_distances(&reported, |_| Vector2::new(46.25, 4.1));
    assert!(
        errors[1..].iter().all(|&e| e < 0.5),
        "distance (m) of the nearest reported track from the car, per scan: {errors:.2?}"
    );
}

#[test]
fn a_far_cars_track_does_not_take_the_post_beside_it() {
    assert_track_stays_on_far_car(post_beside_far_car);
}

#[test]
fn a_far_cars_track_does_not_take_the_sign_beside_it() {
    assert_track_stays_on_far_car(sign_beside_far_car);
}
