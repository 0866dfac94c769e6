//! A crossroads of two city streets: crossing and turning traffic, pedestrians waiting at and
//! walking over the crossings, parked cars, traffic lights. The first vehicle turns left.

use nalgebra::{Rotation2, Vector2};

use crate::class::Class;
use crate::error::SimError;
use crate::path::{Path, Pose2};
use crate::random::{between, chance, pick};
use crate::scenario::builder::WorldBuilder;
use crate::scenario::props;
use crate::scenario::street::{Roadside, dress};
use crate::scenario::{Candidates, place_vehicles};
use crate::speed::SpeedProfile;
use crate::trajectory::Trajectory;

/// Lane centre offset from a road's centreline.
const LANE: f64 = 1.75;
/// Kerb offset from a road's centreline.
const KERB: f64 = 5.6;
/// Parking strip offset.
const PARKING: f64 = 4.5;
/// Distance of the crosswalks from the crossing's centre.
const CROSSWALK: f64 = 9.0;
/// Radii of left and right turns.
const LEFT_RADIUS: f64 = 9.0;
const RIGHT_RADIUS: f64 = 6.0;

/// What a vehicle does at the crossing.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Turn {
    Straight,
    Left,
    Right,
}

/// Builds the scenario with `vehicles` vehicles.
pub fn build(b: &mut WorldBuilder, vehicles: usize) -> Result<(), SimError> {
    let d = b.duration;
    let arm = 60.0 + 12.0 * d;

    // The first vehicle comes from the west and turns left; the others try every approach.
    let mut candidates: Candidates = vec![vehicle_route(b, 0, Turn::Left, 45.0, 8.0, 0.0)];
    for start in [55.0, 85.0, 35.0, 120.0, 160.0] {
        for (a, turn) in [
            (2, Turn::Straight),
            (1, Turn::Right),
            (3, Turn::Straight),
            (2, Turn::Left),
            (1, Turn::Straight),
            (0, Turn::Straight),
        ] {
            let v = between(&mut b.rng, 7.0, 10.0);
            candidates.push(vehicle_route(b, a, turn, start, v, 0.0));
        }
    }
    place_vehicles(b, vehicles, candidates)?;

    // Streets: west-east and south-north through the origin, clear of the crossing.
    let ew = Path::line(Pose2::new(-arm, 0.0, 0.0), 2.0 * arm);
    let sn = Path::line(
        Pose2::new(0.0, -arm, std::f64::consts::FRAC_PI_2),
        2.0 * arm,
    );
    for road in [&ew, &sn] {
        for side in [1.0, -1.0] {
            let mut r = Roadside::city(side, KERB);
            r.buildings = Some((KERB + 5.0, KERB + 8.0));
            r.lamps = Some(25.0);
            r.walkers = 2;
            dress(b, road, 0.0, arm - 16.0, &r);
            dress(b, road, arm + 16.0, 2.0 * arm, &r);
            let parking = Roadside {
                buildings: None,
                lamps: None,
                trees: None,
                parking: Some((PARKING, 0.6)),
                walkers: 0,
                ..r
            };
            dress(b, road, 0.0, arm - 22.0, &parking);
            dress(b, road, arm + 22.0, 2.0 * arm, &parking);
        }
    }
    for a in 0..4 {
        let rot = Rotation2::new(heading(a));
        // Each approach's light stands at the kerb on its right, before the crossing.
        props::traffic_light(
            b,
            rot * Vector2::new(-7.0, -7.0),
            heading(a) + std::f64::consts::PI,
        );
    }

    // Traffic through the crossing, placed where it meets nobody.
    let tries = (30.0 + 3.0 * d).min(120.0) as usize;
    for _ in 0..tries {
        let a = pick(&mut b.rng, 4);
        let turn = match pick(&mut b.rng, 4) {
            0 => Turn::Left,
            1 => Turn::Right,
            _ => Turn::Straight,
        };
        let start = between(&mut b.rng, 15.0, 150.0);
        let v = between(&mut b.rng, 6.0, 12.0);
        let wait = if chance(&mut b.rng, 0.3) {
            between(&mut b.rng, 0.0, d)
        } else {
            0.0
        };
        let class = match pick(&mut b.rng, 12) {
            0 => Class::Truck,
            1 | 2 => Class::Van,
            _ => Class::Car,
        };
        let trajectory = vehicle_route(b, a, turn, start, v, wait);
        b.place(class, None, trajectory);
    }

    // Pedestrians who wait at a crossing, walk over and go on.
    for _ in 0..(8.0 + d).min(40.0) as usize {
        let a = pick(&mut b.rng, 4);
        let trajectory = crossing_walk(b, a);
        b.place(Class::Pedestrian, None, trajectory);
    }
    Ok(())
}

/// Heading of traffic arriving on approach `a` (0 from the west, 1 from the south, 2 from
/// the east, 3 from the north).
fn heading(a: usize) -> f64 {
    a as f64 * std::f64::consts::FRAC_PI_2
}

/// A vehicle's route: arrive on approach `a`, starting `start` metres before the centre at
/// `v` m/s (after waiting `wait` s), then go straight or turn, slowing for turns.
fn vehicle_route(
    b: &mut WorldBuilder,
    a: usize,
    turn: Turn,
    start: f64,
    v: f64,
    wait: f64,
) -> Trajectory {
    let rot = Rotation2::new(heading(a));
    let p = rot * Vector2::new(-start, -LANE);
    let begin = Path::from(Pose2 {
        position: p,
        heading: heading(a),
    });
    let tail = 80.0 + 15.0 * b.duration;
    let (path, approach, arc) = match turn {
        Turn::Straight => (begin.line(start + tail).build(), start + tail, 0.0),
        Turn::Left => {
            let line = start + LANE - LEFT_RADIUS;
            let arc = LEFT_RADIUS * std::f64::consts::FRAC_PI_2;
            let path = begin
                .line(line)
                .arc(LEFT_RADIUS, std::f64::consts::FRAC_PI_2)
                .line(tail)
                .build();
            (path, line, arc)
        }
        Turn::Right => {
            let line = start - LANE - RIGHT_RADIUS;
            let arc = RIGHT_RADIUS * std::f64::consts::FRAC_PI_2;
            let path = begin
                .line(line)
                .arc(RIGHT_RADIUS, -std::f64::consts::FRAC_PI_2)
                .line(tail)
                .build();
            (path, line, arc)
        }
    };
    let mut speed = SpeedProfile::starting(if wait > 0.0 { 0.0 } else { v });
    let mut covered = 0.0;
    if wait > 0.0 {
        speed = speed.hold(wait).to(v, 2.0);
        covered = v * v / 4.0;
    }
    if turn != Turn::Straight {
        let v_turn = if turn == Turn::Left { 4.5 } else { 3.5 };
        let brake = (v * v - v_turn * v_turn).max(0.0) / 3.0;
        let hold = ((approach - covered - brake - 2.0) / v).max(0.0);
        let v_out = between(&mut b.rng, 7.0, 11.0);
        speed = speed
            .hold(hold)
            .to(v_turn, 1.5)
            .hold(arc / v_turn + 0.5)
            .to(v_out, 1.2);
    }
    Trajectory::new(path, speed.build())
}

/// A pedestrian on approach `a`'s crosswalk: walks up the sidewalk, waits at the kerb,
/// crosses, walks on.
fn crossing_walk(b: &mut WorldBuilder, a: usize) -> Trajectory {
    let rot = Rotation2::new(heading(a));
    let side = if chance(&mut b.rng, 0.5) { 1.0 } else { -1.0 };
    let walk = KERB + 1.5;
    let x = -CROSSWALK - between(&mut b.rng, -0.8, 0.8);
    let lead_in = between(&mut b.rng, 4.0, 25.0);
    let points = [
        Vector2::new(x - lead_in, -side * walk),
        Vector2::new(x, -side * walk),
        Vector2::new(x, side * walk),
        Vector2::new(x - 60.0, side * walk),
    ]
    .map(|p| rot * p);
    let path = Path::through(&points, 1.0);
    let v = between(&mut b.rng, 1.0, 1.6);
    let wait = between(&mut b.rng, 0.0, b.duration);
    let speed = SpeedProfile::starting(v)
        .hold((lead_in - 0.5).max(0.0) / v)
        .to(0.0, 2.0)
        .hold(wait)
        .to(v, 1.5)
        .build();
    Trajectory::new(path, speed)
}
