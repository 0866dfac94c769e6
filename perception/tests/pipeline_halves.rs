//! The pipeline's two halves overlap in `trackd run`: scans are segmented a few ahead of the
//! one being tracked. Segmentation reads nothing the tracker writes, so running the halves
//! that way gives exactly what [`Pipeline::process`] gives scan after scan.

use std::collections::VecDeque;

use nalgebra::Isometry3;
use trackd_perception::config::Config;
use trackd_perception::pipeline::Segmented;
use trackd_perception::{Ego, Frame, FrameOutput, Pipeline, Vehicle};
use trackd_sim::{Scenario, SimConfig, Simulation};

const FRAMES: usize = 15;
/// Scans segmented before the oldest of them is tracked.
const AHEAD: usize = 3;

fn vehicle() -> Vehicle {
    Vehicle {
        id: "car-1".into(),
        origin: None,
        imu_to_velo: Isometry3::identity(),
    }
}

fn frames() -> Vec<Frame> {
    let sim = Simulation::new(&SimConfig::new(Scenario::Paper, FRAMES, 3)).expect("simulation");
    (0..FRAMES)
        .map(|i| {
            let scan = sim.frame(0, i);
            Frame {
                timestamp: scan.timestamp,
                points: scan.points,
                ego: Ego::Pose(scan.velodyne_pose),
            }
        })
        .collect()
}

/// What must not differ between the two ways of running.
fn summary(output: &FrameOutput) -> String {
    format!(
        "{} {:?} {:?} {:?} {}",
        output.index,
        output.ego_pose,
        output.counts,
        output.tracks,
        output.superframe.is_some()
    )
}

#[test]
fn halves_run_scans_ahead_give_what_the_whole_pipeline_gives() {
    let frames = frames();
    let mut whole = Pipeline::new(Config::default(), vehicle());
    let expected: Vec<String> = frames
        .iter()
        .map(|f| summary(&whole.process(f.clone()).expect("scan processed")))
        .collect();
    assert!(
        expected.iter().any(|s| s.contains("TrackState")),
        "the drive should yield tracks"
    );

    let (mut segmentation, mut tracking) =
        Pipeline::new(Config::default(), vehicle()).into_halves();
    let mut ahead: VecDeque<Segmented> = VecDeque::new();
    let mut spare: Vec<Segmented> = Vec::new();
    let mut got = Vec::new();
    for frame in &frames {
        let mut scan = spare.pop().unwrap_or_default();
        segmentation
            .segment(frame, &mut scan)
            .expect("scan segmented");
        ahead.push_back(scan);
        if ahead.len() > AHEAD {
            let mut scan = ahead.pop_front().expect("a scan ahead");
            got.push(summary(&tracking.track(&mut scan)));
            spare.push(scan);
        }
    }
    while let Some(mut scan) = ahead.pop_front() {
        got.push(summary(&tracking.track(&mut scan)));
    }
    assert_eq!(got.len(), expected.len());
    for (i, (got, expected)) in got.iter().zip(&expected).enumerate() {
        assert_eq!(got, expected, "scan {i}");
    }
}
