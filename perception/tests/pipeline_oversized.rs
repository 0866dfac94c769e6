//! A person walking along a facade is one DBSCAN cluster with it, larger than any object: the
//! pipeline leaves such clusters to the map, but first peels moving people and newcomers off
//! them.

mod drive_support;

use drive_support::assert_walker_reported_in_most_scans;
use trackd_sim::{Scenario, SimConfig};

/// Pedestrian 11 of the seed-2 `crowd` drive walks along the wall of a building from scan 75
/// on, beside it, 11-14 m from the sensor: the wall and they make one cluster, and without the
/// peel they went unreported in every scan to the drive's end.
const SEED: u64 = 2;
const WALKER: u32 = 11;
const FIRST: usize = 78;
const LAST: usize = 95;

#[test]
fn a_person_walking_along_a_facade_is_peeled_off_it() {
    let drive = SimConfig::new(Scenario::Crowd, LAST + 1, SEED);
    assert_walker_reported_in_most_scans(
        &drive,
        WALKER,
        FIRST..=LAST,
        "the walker along the facade",
    );
}
