//! The ego-pose EKF on every simulated scenario: the simulator's noisy OXTS in, its true
//! Velodyne poses to score against.

mod pose_support;

use nalgebra::Isometry3;
use pose_support::{frame_to_frame_error, position_error, rms, yaw_error};
use trackd_perception::pose::{FixOutcome, PoseConfig, PoseEstimator};
use trackd_sim::{
    ego::Mount,
    scenario::Scenario,
    simulation::{SimConfig, Simulation},
};

/// Seconds after the first packet that count as convergence, left out of the metrics.
const WARM_UP: f64 = 5.0;
/// Frames per drive (10 Hz).
const FRAMES: usize = 450;

struct Score {
    raw_rms: f64,
    ekf_rms: f64,
    worst_frame_to_frame: f64,
    yaw_rms: f64,
    outage_frames: usize,
    good_fixes: usize,
    rejected: usize,
}

fn score(sim: &Simulation, vehicle: usize) -> Score {
    let mount = Mount::kitti();
    let origin = sim.world().origin;
    let oxts = sim.oxts(vehicle);
    let truth = sim.velodyne_poses(vehicle);
    let mut estimator = PoseEstimator::new(PoseConfig::default(), Some(origin), mount.imu_to_velo);
    let start = sim.timestamp(vehicle, 0);
    let mut poses: Vec<Isometry3<f64>> = Vec::new();
    let (mut raw, mut ekf, mut yaw) = (Vec::new(), Vec::new(), Vec::new());
    let (mut worst, mut outage_frames, mut rejected) = (0.0_f64, 0, 0);
    for (i, packet) in oxts.iter().enumerate() {
        let t = sim.timestamp(vehicle, i);
        let pose = estimator
            .update(t, packet)
            .expect("the simulator's first packet has a fix");
        poses.push(pose);
        rejected += usize::from(estimator.gps_rejected());
        let good_fix = packet.navstat == 4;
        outage_frames += usize::from(!good_fix);
        if !good_fix {
            assert!(
                matches!(estimator.last_step().position, FixOutcome::Dropout(_)),
                "frame {i}: an outage fix was used"
            );
        }
        if t - start < WARM_UP {
            continue;
        }
        ekf.push(position_error(&pose, &truth[i]));
        yaw.push(yaw_error(&pose, &truth[i]));
        if good_fix {
            let raw_pose = packet.raw_imu_pose(&origin) * mount.imu_to_velo.inverse();
            raw.push(position_error(&raw_pose, &truth[i]));
        }
        let f2f = frame_to_frame_error((&poses[i - 1], &pose), (&truth[i - 1], &truth[i]), 40.0);
        worst = worst.max(f2f);
    }
    Score {
        raw_rms: rms(&raw),
        ekf_rms: rms(&ekf),
        worst_frame_to_frame: worst,
        yaw_rms: rms(&yaw),
        outage_frames,
        good_fixes: oxts.len() - outage_frames,
        rejected,
    }
}

#[test]
fn every_scenario_beats_raw_gps_twice_and_holds_objects_at_40_m_within_0_3_m() {
    for scenario in Scenario::ALL {
        for seed in [1, 2] {
            let config = SimConfig::new(scenario, FRAMES, seed).with_vehicles(2);
            let sim = Simulation::new(&config).expect("a valid simulation");
            for vehicle in 0..2 {
                let s = score(&sim, vehicle);
                let name = format!("{} seed {seed} vehicle {vehicle}", scenario.name());
                eprintln!(
                    "{name}: RMS raw GPS {:.3} m, EKF {:.3} m (gain {:.2}x); worst 40 m \
                     frame-to-frame {:.3} m; yaw RMS {:.3}°; {} outage frames, {} rejected",
                    s.raw_rms,
                    s.ekf_rms,
                    s.raw_rms / s.ekf_rms,
                    s.worst_frame_to_frame,
                    s.yaw_rms.to_degrees(),
                    s.outage_frames,
                    s.rejected,
                );
                assert!(
                    s.outage_frames > 0,
                    "{name}: the drive should have GPS outages"
                );
                assert!(
                    s.raw_rms >= 2.0 * s.ekf_rms,
                    "{name}: raw GPS RMS {:.3} m is not twice the EKF's {:.3} m",
                    s.raw_rms,
                    s.ekf_rms
                );
                assert!(
                    s.yaw_rms < 0.3_f64.to_radians(),
                    "{name}: yaw RMS {}",
                    s.yaw_rms
                );
                // a 99.9 % gate rejects almost no honest fix
                assert!(
                    s.rejected * 100 <= s.good_fixes,
                    "{name}: {} rejected",
                    s.rejected
                );
                assert!(
                    s.worst_frame_to_frame <= 0.3,
                    "{name}: a static object 40 m away moved {:.3} m between frames",
                    s.worst_frame_to_frame
                );
            }
        }
    }
}
