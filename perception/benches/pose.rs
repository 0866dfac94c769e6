//! One ego-pose EKF update (predict + GPS position, GPS velocity, non-holonomic and tilt
//! corrections) on a warmed-up filter. The paper's EKF took 15.87 ms per frame.

use std::hint::black_box;

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use trackd_perception::{
    geo::GeoOrigin,
    oxts::Oxts,
    pose::{PoseConfig, PoseEstimator},
};

fn main() {
    divan::main();
}

const ORIGIN: GeoOrigin = GeoOrigin::new(49.011, 8.423, 112.8);

/// The packet of a car circling at 10 m/s on a 50 m radius, `t` seconds in.
fn packet(t: f64) -> Oxts {
    let (speed, radius) = (10.0, 50.0);
    let rate = speed / radius;
    let heading = rate * t + std::f64::consts::FRAC_PI_2;
    let position = Vector3::new(radius * (rate * t).cos(), radius * (rate * t).sin(), 0.0);
    let (lat, lon, alt) = ORIGIN.to_geodetic(&position);
    Oxts {
        lat,
        lon,
        alt,
        yaw: heading,
        ve: speed * heading.cos(),
        vn: speed * heading.sin(),
        vf: speed,
        ay: speed * rate,
        az: 9.81,
        wz: rate,
        pos_accuracy: 0.5,
        vel_accuracy: 0.1,
        navstat: 4,
        numsats: 9,
        ..Default::default()
    }
}

#[divan::bench]
fn update(bencher: divan::Bencher) {
    let calibration = Isometry3::from_parts(
        Translation3::new(-0.81, 0.32, -0.80),
        UnitQuaternion::identity(),
    );
    let mut warm = PoseEstimator::new(PoseConfig::default(), Some(ORIGIN), calibration);
    for k in 0..100 {
        let t = k as f64 * 0.1;
        warm.update(t, &packet(t)).expect("usable packet");
    }
    let next = packet(10.0);
    bencher
        .with_inputs(|| warm.clone())
        .bench_local_refs(|estimator| {
            black_box(estimator.update(black_box(10.0), black_box(&next)))
        });
}
