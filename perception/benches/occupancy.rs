//! The occupancy map's update on real scans: the 40 scans of KITTI tracking sequence 0000
//! (shared data folder, with its ground-truth poses), run through the pipeline once to get each
//! scan's obstacle and ground points in the world frame, then integrated one after the other
//! into a fresh map. Skipped, saying so, without the data.
//!
//! `trackd run` does the same on its occupancy thread (`occupancy_thread` in timings.csv).

use std::{hint::black_box, sync::OnceLock};

use nalgebra::Isometry3;
use trackd_dataset::{OpenOptions, open};
use trackd_perception::{
    Pipeline, Vehicle,
    config::Config,
    occupancy::{OccupancyMap, OccupancyScan},
};

/// Each scan's update, in order.
fn scans() -> Option<&'static [OccupancyScan]> {
    static SCANS: OnceLock<Option<Vec<OccupancyScan>>> = OnceLock::new();
    SCANS
        .get_or_init(|| {
            let data = trackd_dataset::shared_data_dir("occupancy bench")?;
            let drive = data.join("kitti-tracking-0000-first40/training");
            let options = OpenOptions {
                seq: Some("0000".into()),
                poses: Some(drive.join("poses/0000.txt")),
            };
            let source = open(&drive, &options).ok()?;
            let vehicle = Vehicle {
                id: "bench".into(),
                origin: None,
                imu_to_velo: source.imu_to_velo().unwrap_or_else(Isometry3::identity),
            };
            let mut pipeline = Pipeline::new(Config::default(), vehicle);
            pipeline.hand_out_occupancy();
            let mut scans = Vec::new();
            for frame in source.frames() {
                let output = pipeline.process(frame.ok()?).ok()?;
                scans.push(output.occupancy_scan?);
            }
            Some(scans)
        })
        .as_deref()
}

fn main() {
    if scans().is_none() {
        eprintln!("occupancy bench: no real scans to run on, nothing measured");
        return;
    }
    divan::main();
}

/// All 40 scans into a fresh map.
#[divan::bench(sample_count = 10)]
fn integrate_40_scans(bencher: divan::Bencher) {
    let scans = scans().expect("checked in main");
    bencher.bench_local(|| {
        let mut map = OccupancyMap::new(Default::default());
        for scan in scans {
            map.integrate(scan.sensor, black_box(&scan.obstacles), &scan.ground);
        }
        map.known_voxels()
    });
}
