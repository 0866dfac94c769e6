//! What the pipeline's tests on simulated drives share: a drive run scan by scan through a
//! pipeline with the default configuration and the simulator's true poses, and where one of
//! its objects stands in each scan.

#![allow(dead_code)] // each test file uses its own part of this module

use std::ops::RangeInclusive;

use nalgebra::{Isometry3, Point3};
use trackd_perception::config::Config;
use trackd_perception::{Ego, Frame, FrameOutput, ObjectClass, Pipeline, Vehicle};
use trackd_sim::{SimConfig, Simulation};

/// Where a drive's object stands in one scan.
#[derive(Clone, Copy, Debug)]
pub struct Seen {
    /// World x of its centre (m).
    pub x: f64,
    /// World y of its centre (m).
    pub y: f64,
    /// Its centre's distance from the sensor in the ground plane (m).
    pub range: f64,
}

/// Runs the first `scans` scans of the drive `sim` through a fresh pipeline and hands `visit`
/// each scan's index, where object `id` stands in it (`None`: not in the ground truth) and
/// the pipeline's output; stops early when `visit` returns `false`.
pub fn run_drive(
    sim: &SimConfig,
    scans: usize,
    id: u32,
    mut visit: impl FnMut(usize, Option<Seen>, &FrameOutput) -> bool,
) {
    let sim = Simulation::new(sim).expect("sim");
    let vehicle = Vehicle {
        id: "car-1".into(),
        origin: None,
        imu_to_velo: Isometry3::identity(),
    };
    let mut pipeline = Pipeline::new(Config::default(), vehicle);
    for index in 0..scans {
        let scan = sim.frame(0, index);
        let seen = scan.objects.iter().find(|o| o.id == id).map(|o| {
            let c = scan.velodyne_pose * Point3::from(o.center);
            Seen {
                x: c.x,
                y: c.y,
                range: o.center.xy().norm(),
            }
        });
        let output = pipeline
            .process(Frame {
                timestamp: scan.timestamp,
                points: scan.points,
                ego: Ego::Pose(scan.velodyne_pose),
            })
            .expect("scan processed");
        if !visit(index, seen, &output) {
            break;
        }
    }
}

/// Whether `output` reports an object of `class` within `within` metres (ground plane) of
/// where `seen` stands.
pub fn reports(output: &FrameOutput, class: ObjectClass, seen: Seen, within: f64) -> bool {
    output
        .tracks
        .iter()
        .any(|t| t.class == class && (t.center.x - seen.x).hypot(t.center.y - seen.y) < within)
}

/// Asserts that the drive `sim`'s pedestrian `walker` (in the ground truth in each of the scans
/// `checked`) is reported as a pedestrian within 1 m of where they walk in at least 80 % of
/// those scans; `who` names them in the failure message.
pub fn assert_walker_reported_in_most_scans(
    sim: &SimConfig,
    walker: u32,
    checked: RangeInclusive<usize>,
    who: &str,
) {
    let mut reported = 0;
    run_drive(sim, checked.end() + 1, walker, |index, seen, output| {
        if checked.contains(&index) {
            let seen = seen.expect("the walker is in the ground truth");
            reported += usize::from(reports(output, ObjectClass::Pedestrian, seen, 1.0));
        }
        true
    });
    let scans = checked.count();
    assert!(
        reported * 10 >= scans * 8,
        "{who} was reported in {reported} of {scans} scans"
    );
}
