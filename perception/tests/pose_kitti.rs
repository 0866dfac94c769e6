//! The ego-pose filter on KITTI's own OXTS packet and calibration (2011_09_26, drive 0001):
//! a check of the field conventions (units, axes, signs) against real data.

use nalgebra::Vector3;
use trackd_dataset::{calib::read_raw_calib, oxts::read_oxts, shared_data_dir};
use trackd_perception::pose::{Dropout, FixOutcome, PoseConfig, PoseEstimator};

#[test]
fn a_real_packet_starts_the_filter_and_dead_reckons_along_its_own_velocity() {
    let Some(data) = shared_data_dir("KITTI's real OXTS packet and calibration") else {
        return;
    };
    let date = data.join("kitti-format-samples/raw/2011_09_26");
    let calib = read_raw_calib(&date).expect("real calibration");
    let packet = read_oxts(&date.join("2011_09_26_drive_0001_sync/oxts/data/0000000000.txt"))
        .expect("real packet");

    // A real locked fix is usable under the default rules.
    let mut estimator = PoseEstimator::new(PoseConfig::default(), None, calib.imu_to_velo);
    let first = estimator.update(0.0, &packet).expect("a usable fix");
    assert_eq!(estimator.last_step().position, FixOutcome::Initialised);
    assert_eq!(estimator.last_step().velocity, FixOutcome::Initialised);
    let origin = estimator.origin().expect("the first fix is the origin");
    let want = packet.raw_imu_pose(&origin) * calib.imu_to_velo.inverse();
    assert!((first.translation.vector - want.translation.vector).norm() < 1e-6);
    // KITTI's Velodyne sits about 0.8 m above the IMU.
    assert!((first.translation.z - 0.8).abs() < 0.05, "{first}");

    // The receiver then repeats that fix for a second: a stale fix, predicted through on the
    // packet's IMU. A sign or unit slip in the accelerations (az ≈ +10.2 m/s², gravity
    // included) or in the heading convention would throw the pose metres off.
    let start = estimator
        .imu_pose()
        .expect("initialised")
        .translation
        .vector;
    for k in 1..=10 {
        estimator
            .update(f64::from(k) * 0.1, &packet)
            .expect("predicts");
        assert_eq!(
            estimator.last_step().position,
            FixOutcome::Dropout(Dropout::Stale)
        );
    }
    let moved = estimator
        .imu_pose()
        .expect("initialised")
        .translation
        .vector
        - start;
    let velocity = Vector3::new(packet.ve, packet.vn, packet.vu);
    assert!(
        (moved - velocity).norm() < 0.5,
        "moved {moved} in 1 s at {velocity}"
    );
    let (_, _, yaw) = estimator
        .imu_pose()
        .expect("initialised")
        .rotation
        .euler_angles();
    assert!(
        (yaw - packet.yaw).abs() < 0.5_f64.to_radians(),
        "{yaw} vs {}",
        packet.yaw
    );
}
