//! An oncoming truck at highway speed is an object only once seen moving, and its motion is
//! judged on where it stands now: free space in the scans before it came into view. Judged
//! against the scan from before its track's birth, it is reported from its second view on,
//! not from its fourth.

mod drive_support;

use drive_support::{reports, run_drive};
use trackd_perception::ObjectClass;
use trackd_sim::{Scenario, SimConfig};

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
    let drive = SimConfig::new(Scenario::Highway, FRAMES, SEED);
    let mut first_view = None;
    let mut reported = Vec::new();
    run_drive(&drive, FRAMES, TRUCK, |index, truck, output| {
        let Some(truck) = truck else {
            return true;
        };
        let Some(first) = first_view else {
            if truck.range < MAX_RANGE {
                first_view = Some(index);
            }
            return true;
        };
        reported.push((index, reports(output, ObjectClass::Car, truck, 2.0)));
        index < first + CHECKED
    });
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
