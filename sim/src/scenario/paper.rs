//! The paper's drive: two cyclists riding side by side ahead of the vehicle, about a metre
//! apart and at times closer, a car coming the other way, a city street around them.

use crate::class::Class;
use crate::error::SimError;
use crate::path::{Path, Pose2};
use crate::random::between;
use crate::scenario::builder::WorldBuilder;
use crate::scenario::street::{Roadside, dress, lane_path};
use crate::scenario::{Candidates, place_vehicles};
use crate::speed::SpeedProfile;
use crate::trajectory::Trajectory;

/// Lane centres (metres left of the road's centreline).
const OUR_LANE: f64 = -1.75;
const ONCOMING_LANE: f64 = 1.75;
/// The right cyclist rides here; the left one 0.7–1.3 m to its left.
const BIKE_LINE: f64 = -4.6;
/// Where the vehicle starts along the road.
const START: f64 = 60.0;

/// Builds the scenario with `vehicles` vehicles.
pub fn build(b: &mut WorldBuilder, vehicles: usize) -> Result<(), SimError> {
    let d = b.duration;
    let rest = (16.0 * d).max(150.0);
    let road = Path::from(Pose2::new(-START, 0.0, between(&mut b.rng, -0.3, 0.3)))
        .line(130.0)
        .arc(
            between(&mut b.rng, 180.0, 300.0),
            between(&mut b.rng, 0.2, 0.35),
        )
        .line(70.0)
        .arc(
            between(&mut b.rng, 180.0, 300.0),
            -between(&mut b.rng, 0.2, 0.35),
        )
        .line(rest)
        .build();
    let len = road.length();

    // The two cyclists ride together at a varying speed.
    let v_bike = between(&mut b.rng, 4.0, 5.0);
    let bike_speed = wavy_speed(b, v_bike, 0.5, d);
    let bike_start = START + between(&mut b.rng, 13.0, 20.0);
    let right = road.offset(BIKE_LINE);
    b.place_unchecked(
        Class::Cyclist,
        None,
        Trajectory::new(right, bike_speed.clone()).starting_at(bike_start),
    );
    let gaps: Vec<f64> = (0..(len / 12.0) as usize + 2)
        .map(|i| {
            if i % 3 == 1 {
                between(&mut b.rng, 0.7, 0.85)
            } else {
                between(&mut b.rng, 0.85, 1.3)
            }
        })
        .collect();
    let gap = move |s: f64| gaps[((s / 12.0) as usize).min(gaps.len() - 1)];
    let left = lane_path(&road, 0.0, len, 12.0, |s| BIKE_LINE + gap(s));
    let lead = between(&mut b.rng, -0.4, 0.6);
    b.place_unchecked(
        Class::Cyclist,
        None,
        Trajectory::new(left, bike_speed).starting_at(bike_start + lead),
    );

    // Our lane, and the oncoming one.
    let ours = road.offset(OUR_LANE);
    let theirs = road.offset(ONCOMING_LANE).reversed();
    let mut candidates = Candidates::new();
    candidates.push(
        Trajectory::new(ours.clone(), wavy_speed(b, v_bike + 0.05, 0.6, d)).starting_at(START),
    );
    for k in 1..12 {
        let k = k as f64;
        let behind = Trajectory::new(ours.clone(), wavy_speed(b, v_bike + 0.3, 0.4, d))
            .starting_at(START - 22.0 * k);
        candidates.push(behind);
        let v = between(&mut b.rng, 7.0, 10.0);
        let oncoming = Trajectory::new(theirs.clone(), SpeedProfile::constant(v))
            .starting_at(len - START - 60.0 - 35.0 * k);
        candidates.push(oncoming);
    }
    place_vehicles(b, vehicles, candidates)?;

    // The car coming the other way passes the first vehicle mid-drive; more follow on long
    // drives.
    let v_car = between(&mut b.rng, 9.0, 12.0);
    let mut t_pass = (d / 2.0).clamp(3.0, 8.0);
    while t_pass < d + 5.0 {
        let meet = START + v_bike * t_pass;
        let start = len - meet - v_car * t_pass;
        b.place(
            Class::Car,
            None,
            Trajectory::new(theirs.clone(), SpeedProfile::constant(v_car)).starting_at(start),
        );
        t_pass += between(&mut b.rng, 9.0, 15.0);
    }

    let kerb_right = 5.2;
    let kerb_left = 5.6;
    let mut left_side = Roadside::city(1.0, kerb_left);
    left_side.parking = Some((4.5, 0.55));
    dress(b, &road, 0.0, len, &left_side);
    dress(b, &road, 0.0, len, &Roadside::city(-1.0, kerb_right));
    Ok(())
}

/// A speed that swings by ±`swing` around `v` every few seconds, over `duration` seconds.
fn wavy_speed(b: &mut WorldBuilder, v: f64, swing: f64, duration: f64) -> SpeedProfile {
    let mut p = SpeedProfile::starting(v).hold(between(&mut b.rng, 1.0, 3.0));
    let mut t = 0.0;
    let mut up = true;
    while t < duration + 5.0 {
        let target = v + if up { swing } else { -swing } * between(&mut b.rng, 0.5, 1.0);
        p = p.to(target, 0.4).hold(between(&mut b.rng, 2.0, 4.0));
        t += 6.0;
        up = !up;
    }
    p.build()
}
