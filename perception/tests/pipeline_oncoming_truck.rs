//! An oncoming truck at highway speed is an object only once seen moving, and its motion is
//! judged on where it stands now: free space in the scans before it came into view. Judged
//! against the scan from before its track's birth, it is reported from its second view on,
//! not from its fourth.

use nalgebra::{Isometry3, Point3};
use trackd_perception::config::Config;
use trackd_perception::{Ego, Frame, ObjectClass, Pipeline, Vehicle};
use trackd_sim::{Scenario, SimConfig, Simulation};

/// Truck 110 of the seed-6 `highway` drive comes the other way at 24 m/s beside the
/// vehicle's lanes; it enters the 50 m range in scan 4.
const SEED: u64 = 6;
const TRUCK: u32 = 110;
/// The drive's length (the scenario is laid out for it).
const FRAMES: usize = 100;
/// The range band's outer limit (m): the truck's first view is the first scan it is nearer.
const MAX_RANGE: f64 = 48.0;
/// Scans checked from its second view on.
const CHECKED: usize = 5;

#[test]
fn an_oncoming_truck_is_reported_from_its_second_view() {
    let sim = Simulation::new(&SimConfig::new(Scenario::Highway, FRAMES, SEED)).expect("sim");
    let vehicle = Vehicle {
        id: "car-1".into(),
        origin: None,
        imu_to_velo: Isometry3::identity(),
    };
    let mut pipeline = Pipeline::new(Config::default(), vehicle);
    let mut first_view = None;
    let mut reported = Vec::new();
    for index in 0..FRAMES {
        let scan = sim.frame(0, index);
        let truck = scan.objects.iter().find(|o| o.id == TRUCK).map(|o| {
            let c = scan.velodyne_pose * Point3::from(o.center);
            let seen = scan.velodyne_pose.inverse() * c;
            (c.x, c.y, seen.coords.xy().norm())
        });
        let output = pipeline
            .process(Frame {
                timestamp: scan.timestamp,
                points: scan.points,
                ego: Ego::Pose(scan.velodyne_pose),
            })
            .expect("scan processed");
        let Some((x, y, range)) = truck else {
            continue;
        };
        if first_view.is_none() && range < MAX_RANGE {
            first_view = Some(index);
            continue;
        }
        let Some(first) = first_view else {
            continue;
        };
        let found = output
            .tracks
            .iter()
            .any(|t| t.class == ObjectClass::Car && (t.center.x - x).hypot(t.center.y - y) < 2.0);
        reported.push((index, found));
        if index >= first + CHECKED {
            break;
        }
    }
    assert_eq!(
        reported.len(),
        CHECKED,
        "the truck came into view: {first_view:?}"
    );
    assert!(
        reported.iter().all(|&(_, found)| found),
        "scans after its first view and whether it was reported: {reported:?}"
    );
}
