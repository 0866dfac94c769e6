//! What each scenario promises: determinism, GPS outages, highway speeds, the paper's two
//! cyclists, moving and turning vehicles, and a fleet that sees some things together and
//! some alone.

use std::collections::HashSet;

use trackd_sim::{Class, Scenario, SimConfig, Simulation};

#[test]
fn the_same_seed_gives_the_same_drive() {
    let config = SimConfig::new(Scenario::Crowd, 5, 9).with_vehicles(2);
    let a = Simulation::new(&config).unwrap();
    let b = Simulation::new(&config).unwrap();
    assert_eq!(a.frame(1, 4), b.frame(1, 4));
    let c = Simulation::new(&SimConfig { seed: 10, ..config }).unwrap();
    assert_ne!(a.frame(1, 4).points, c.frame(1, 4).points);
    assert_ne!(a.oxts(0), c.oxts(0));
}

#[test]
fn gps_outages_occur_and_are_flagged() {
    for scenario in Scenario::ALL {
        let sim = Simulation::new(&SimConfig::new(scenario, 100, 21)).unwrap();
        let oxts = sim.oxts(0);
        let out = oxts.iter().filter(|o| o.posmode == 0).count();
        assert!(out > 5 && out < 60, "{scenario}: {out} frames without GPS");
        assert!(
            oxts.iter()
                .filter(|o| o.posmode == 0)
                .all(|o| o.numsats < 4 && o.navstat != 4)
        );
    }
}

#[test]
fn highway_traffic_reaches_30_metres_a_second() {
    let sim = Simulation::new(&SimConfig::new(Scenario::Highway, 30, 4)).unwrap();
    let f = sim.frame(0, 15);
    let fast = f
        .objects
        .iter()
        .filter(|o| o.velocity.norm() >= 28.0 && o.npoints > 0)
        .count();
    assert!(
        fast >= 1,
        "{:?}",
        f.objects
            .iter()
            .map(|o| o.velocity.norm())
            .collect::<Vec<_>>()
    );
    let top = sim
        .world()
        .actors
        .iter()
        .map(|a| a.planar(1.5).speed)
        .fold(0.0, f64::max);
    assert!(top >= 30.0, "{top}");
}

#[test]
fn the_paper_s_cyclists_ride_side_by_side_ahead() {
    let sim = Simulation::new(&SimConfig::new(Scenario::Paper, 100, 1)).unwrap();
    let mut close = 0;
    for i in (0..100).step_by(10) {
        let f = sim.frame(0, i);
        let bikes: Vec<_> = f
            .objects
            .iter()
            .filter(|o| o.class == Class::Cyclist)
            .collect();
        assert_eq!(bikes.len(), 2, "frame {i}");
        for b in &bikes {
            assert!(b.center.x > 3.0 && b.npoints > 20, "frame {i}: {b:?}");
            // Riding the vehicle's way.
            assert!(b.yaw.abs() < 0.5, "frame {i}: {b:?}");
        }
        let gap = (bikes[0].center - bikes[1].center).norm();
        assert!(gap > 0.5, "frame {i}: {gap}");
        close += usize::from(gap <= 1.5);
    }
    assert!(
        close >= 5,
        "{close} of 10 frames with the cyclists within 1.5 m"
    );
}

#[test]
fn vehicles_move_and_turn() {
    let sim = Simulation::new(&SimConfig::new(Scenario::Intersection, 120, 2)).unwrap();
    let poses = sim.velodyne_poses(0);
    let travelled = (poses[119].translation.vector - poses[0].translation.vector).norm();
    assert!(travelled > 40.0, "{travelled}");
    let yaw = |i: usize| poses[i].rotation.euler_angles().2;
    let turned = (yaw(119) - yaw(0)).abs();
    assert!(
        (turned - std::f64::consts::FRAC_PI_2).abs() < 0.2,
        "{turned}"
    );
    let speeds: Vec<f64> = sim.oxts(0).iter().map(|o| o.vf).collect();
    let (lo, hi) = speeds
        .iter()
        .fold((f64::MAX, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
    assert!(hi - lo > 2.0, "speed {lo}..{hi}");
}

#[test]
fn a_fleet_shares_some_objects_and_not_others() {
    for scenario in [Scenario::Paper, Scenario::Intersection] {
        let sim = Simulation::new(&SimConfig::new(scenario, 30, 8).with_vehicles(2)).unwrap();
        let seen = |k: usize| -> HashSet<u32> {
            sim.frame(k, 15)
                .objects
                .iter()
                .filter(|o| o.npoints >= 10)
                .map(|o| o.id)
                .collect()
        };
        let (a, b) = (seen(0), seen(1));
        let both = a.intersection(&b).count();
        let only = a.symmetric_difference(&b).count();
        assert!(
            both >= 2 && only >= 2,
            "{scenario}: both {both}, one only {only}"
        );
        // Each vehicle is an object the other may see, under its own id.
        let ids: Vec<u32> = (0..2).map(|k| sim.world().vehicle(k).id).collect();
        assert!(!sim.frame(0, 15).objects.iter().any(|o| o.id == ids[0]));
        assert_ne!(ids[0], ids[1]);
    }
}
