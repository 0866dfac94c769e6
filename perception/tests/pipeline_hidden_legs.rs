//! A person walking behind parked cars shows only their upper body: its lowest point is far
//! above a person's feet, and what hides the legs is nearer along the same rays. Once seen
//! walking, such a view is a person's.

use nalgebra::{Isometry3, Point3};
use trackd_perception::config::Config;
use trackd_perception::{Ego, Frame, ObjectClass, Pipeline, Vehicle};
use trackd_sim::{Scenario, SimConfig, Simulation};

/// Pedestrian 45 of the seed-6 `paper` drive walks along the parked cars, behind them, 14-20 m
/// from the sensor from scan 48 on: before hidden legs counted, they went unreported from
/// scan 52 to 72.
const SEED: u64 = 6;
const WALKER: u32 = 45;
const FIRST: usize = 52;
const LAST: usize = 72;
/// The drive's length (the scenario is laid out for it).
const FRAMES: usize = 100;

#[test]
fn a_person_walking_behind_parked_cars_is_reported() {
    let sim = Simulation::new(&SimConfig::new(Scenario::Paper, FRAMES, SEED)).expect("sim");
    let vehicle = Vehicle {
        id: "car-1".into(),
        origin: None,
        imu_to_velo: Isometry3::identity(),
    };
    let mut pipeline = Pipeline::new(Config::default(), vehicle);
    let mut reported = 0;
    for index in 0..=LAST {
        let scan = sim.frame(0, index);
        let walker = scan.objects.iter().find(|o| o.id == WALKER).map(|o| {
            let c = scan.velodyne_pose * Point3::from(o.center);
            (c.x, c.y)
        });
        let output = pipeline
            .process(Frame {
                timestamp: scan.timestamp,
                points: scan.points,
                ego: Ego::Pose(scan.velodyne_pose),
            })
            .expect("scan processed");
        if index < FIRST {
            continue;
        }
        let (x, y) = walker.expect("the walker is in the ground truth");
        let found = output.tracks.iter().any(|t| {
            t.class == ObjectClass::Pedestrian && (t.center.x - x).hypot(t.center.y - y) < 1.0
        });
        reported += usize::from(found);
    }
    let scans = LAST - FIRST + 1;
    assert!(
        reported * 10 >= scans * 8,
        "the walker behind the parked cars was reported in {reported} of {scans} scans"
    );
}
