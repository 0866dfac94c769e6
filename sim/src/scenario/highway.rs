//! A motorway: three lanes each way between guard rails, cars, vans and lorries at 21–33 m/s,
//! sign gantries, noise barriers and trees. The first vehicle speeds up and changes lanes.

use crate::class::Class;
use crate::error::SimError;
use crate::path::{Path, Pose2};
use crate::random::{between, chance};
use crate::scenario::builder::WorldBuilder;
use crate::scenario::props::{self, beside};
use crate::scenario::street::lane_path;
use crate::scenario::{Candidates, place_vehicles};
use crate::speed::SpeedProfile;
use crate::trajectory::Trajectory;

/// Half-width of the median strip (metres).
const MEDIAN: f64 = 1.0;
/// Lane width.
const LANE_WIDTH: f64 = 3.75;
/// Outer guard rails.
const OUTER_RAIL: f64 = MEDIAN + 3.0 * LANE_WIDTH + 2.5;
/// Where the first vehicle starts along the road.
const START: f64 = 200.0;

/// Offset of lane `i` (0 the fast lane next to the median) of the carriageway going the
/// road's way (negative: right of the centreline).
fn lane(i: usize) -> f64 {
    -(MEDIAN + LANE_WIDTH * (i as f64 + 0.5))
}

/// Speed range of lane `i`.
fn lane_speed(i: usize) -> (f64, f64) {
    match i {
        0 => (29.0, 33.0),
        1 => (25.0, 29.0),
        _ => (21.0, 25.0),
    }
}

/// Builds the scenario with `vehicles` vehicles.
pub fn build(b: &mut WorldBuilder, vehicles: usize) -> Result<(), SimError> {
    let d = b.duration;
    let road = Path::from(Pose2::new(-START, 0.0, between(&mut b.rng, -0.5, 0.5)))
        .line(START + 250.0)
        .arc(
            between(&mut b.rng, 900.0, 1500.0),
            between(&mut b.rng, -0.2, 0.2),
        )
        .line((36.0 * d).max(300.0) + 300.0)
        .build();
    let len = road.length();

    // The first vehicle: middle lane, speeds up, moves to the fast lane after ~3 s.
    let change_at = START + 75.0 + between(&mut b.rng, 0.0, 30.0);
    let change_len = 90.0;
    let ramp = move |s: f64| {
        let u = ((s - change_at) / change_len).clamp(0.0, 1.0);
        lane(1) + (lane(0) - lane(1)) * (1.0 - (std::f64::consts::PI * u).cos()) / 2.0
    };
    let first = lane_path(&road, 0.0, len, 15.0, ramp);
    let speed = SpeedProfile::starting(25.0)
        .hold(1.5)
        .to(29.5, 0.8)
        .hold(between(&mut b.rng, 3.0, 6.0))
        .to(27.0, 0.5)
        .build();
    let mut candidates: Candidates = vec![Trajectory::new(first, speed).starting_at(START)];
    for k in 1..10 {
        let k = k as f64;
        candidates.push(
            Trajectory::new(road.offset(lane(2)), SpeedProfile::constant(24.0))
                .starting_at(START - 35.0 * k),
        );
        candidates.push(
            Trajectory::new(
                road.offset(-lane(1)).reversed(),
                SpeedProfile::constant(27.0),
            )
            .starting_at(len - START - 150.0 - 60.0 * k),
        );
        candidates.push(
            Trajectory::new(road.offset(lane(1)), SpeedProfile::constant(26.0))
                .starting_at(START + 60.0 * k),
        );
    }
    place_vehicles(b, vehicles, candidates)?;

    // Traffic both ways in every lane, spaced along the whole road.
    for i in 0..3 {
        for forward in [true, false] {
            let path = if forward {
                road.offset(lane(i))
            } else {
                road.offset(-lane(i)).reversed()
            };
            let (lo, hi) = lane_speed(i);
            let mut s = between(&mut b.rng, 0.0, 40.0);
            while s < len {
                let v = between(&mut b.rng, lo, hi);
                let class = match (i, crate::random::pick(&mut b.rng, 10)) {
                    (2, 0..=3) => Class::Truck,
                    (_, 0) => Class::Van,
                    _ => Class::Car,
                };
                let v = if class == Class::Truck {
                    v.min(24.0)
                } else {
                    v
                };
                let speed = SpeedProfile::starting(v)
                    .hold(between(&mut b.rng, 1.0, 8.0))
                    .to(v + between(&mut b.rng, -1.5, 1.5), 0.5)
                    .build();
                b.place(
                    class,
                    None,
                    Trajectory::new(path.clone(), speed).starting_at(s),
                );
                s += between(&mut b.rng, 30.0, 110.0);
            }
        }
    }

    // Guard rails: a double one on the median, one on each outer edge.
    for offset in [MEDIAN - 0.5, -(MEDIAN - 0.5), OUTER_RAIL, -OUTER_RAIL] {
        props::guard_rail(b, &road, 0.0, len, offset);
    }
    // Sign gantries across the road.
    let mut s = between(&mut b.rng, 100.0, 300.0);
    while s < len {
        gantry(b, &road, s);
        s += between(&mut b.rng, 350.0, 600.0);
    }
    // Beyond the rails: noise barriers on some stretches, trees and bushes elsewhere.
    for side in [1.0, -1.0] {
        let mut s = 0.0;
        while s < len {
            let stretch = between(&mut b.rng, 80.0, 250.0);
            if chance(&mut b.rng, 0.35) {
                let offset = side * (OUTER_RAIL + 4.0);
                let mut u = s;
                while u < (s + stretch).min(len) {
                    let (a, _) = beside(&road, u, offset);
                    let (c, _) = beside(&road, (u + 10.0).min(len), offset);
                    props::wall(b, a, c, 4.0, 0.3, crate::material::Material::CONCRETE);
                    u += 10.0;
                }
            } else {
                let mut u = s;
                while u < (s + stretch).min(len) {
                    let (xy, _) = beside(
                        &road,
                        u,
                        side * (OUTER_RAIL + between(&mut b.rng, 3.0, 25.0)),
                    );
                    if chance(&mut b.rng, 0.6) {
                        props::tree(b, xy);
                    } else {
                        props::bush(b, xy);
                    }
                    u += between(&mut b.rng, 4.0, 14.0);
                }
            }
            s += stretch;
        }
    }
    Ok(())
}

/// A sign gantry across the whole road at arc length `s`.
fn gantry(b: &mut WorldBuilder, road: &Path, s: f64) {
    let span = 2.0 * OUTER_RAIL + 2.0;
    for side in [1.0, -1.0] {
        let (xy, _) = beside(road, s, side * (OUTER_RAIL + 1.0));
        b.add_static(
            crate::geometry::Shape::cylinder(0.3, 7.5),
            xy,
            0.0,
            0.0,
            crate::material::Material::POLE,
        );
    }
    let (xy, heading) = beside(road, s, 0.0);
    b.add_static(
        crate::geometry::Shape::cuboid(0.6, span, 1.0),
        xy,
        6.5,
        heading,
        crate::material::Material::POLE,
    );
    for offset in [lane(1), -lane(1)] {
        let (xy, heading) = beside(road, s + 0.4, offset);
        b.add_static(
            crate::geometry::Shape::cuboid(0.08, 4.5, 2.2),
            xy,
            5.5,
            heading,
            crate::material::Material::SIGN,
        );
    }
}
