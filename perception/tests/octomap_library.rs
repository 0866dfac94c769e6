//! Cross-check of the `.bt` export with the real OctoMap library: a map of a wall, a moving
//! car and a road is written; `tests/octomap/bt_check` (C++, built against liboctomap by
//! `.ci/run`, path in `TRACKD_BT_CHECK`) must read it and find every voxel in its state.

use std::{fmt::Write as _, process::Command};

use nalgebra::Vector3;
use trackd_perception::{
    Point,
    occupancy::{OccupancyConfig, OccupancyMap},
};

#[test]
fn octomap_reads_our_bt_files() {
    let Some(checker) = std::env::var_os("TRACKD_BT_CHECK") else {
        eprintln!(
            "SKIPPED octomap_reads_our_bt_files: TRACKD_BT_CHECK (the liboctomap checker built by .ci/run) is not set"
        );
        return;
    };
    let mut map = OccupancyMap::new(OccupancyConfig::default());
    let sensor = Vector3::new(0.0, 0.0, 1.73);
    let mut wall = Vec::new();
    for iy in -60..=60 {
        for iz in 0..=40 {
            wall.push(Point::new(15.0, iy as f32 * 0.05, iz as f32 * 0.05, 0.0));
        }
    }
    let road: Vec<Point> = (0..3000)
        .map(|i| {
            Point::new(
                2.0 + (i % 60) as f32 * 0.4,
                (i / 60) as f32 * 0.25 - 6.0,
                -0.02,
                0.0,
            )
        })
        .collect();
    for step in 0..12 {
        let mut scan = wall.clone();
        scan.extend((0..200).map(|i| {
            Point::new(
                8.0,
                step as f32 * 0.3 + (i % 10) as f32 * 0.1,
                (i / 10) as f32 * 0.08,
                0.0,
            )
        }));
        map.integrate(sensor, &scan, &road);
    }
    let dir = tempfile::tempdir().unwrap();
    let bt = dir.path().join("map.bt");
    std::fs::write(&bt, map.to_bt()).unwrap();

    // Expected states: sample voxel centres across the mapped volume.
    let res = map.config().resolution;
    let mut expected = String::new();
    let mut n = 0;
    for ix in 0..80 {
        for iy in -30..30 {
            for iz in -1..12 {
                let c = Vector3::new(
                    (ix as f64 + 0.5) * res,
                    (iy as f64 + 0.5) * res,
                    (iz as f64 + 0.5) * res,
                );
                if let Some(v) = map.voxel(&c) {
                    writeln!(
                        expected,
                        "{} {} {} {}",
                        c.x,
                        c.y,
                        c.z,
                        u8::from(v.probability >= 0.5)
                    )
                    .unwrap();
                    n += 1;
                }
            }
        }
    }
    assert!(n > 1000, "the sample must cover known voxels ({n})");
    let list = dir.path().join("expected.txt");
    std::fs::write(&list, expected).unwrap();
    let out = Command::new(checker)
        .arg(&bt)
        .arg(&list)
        .output()
        .expect("run bt_check");
    let report = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "liboctomap disagrees:\n{report}");
    eprintln!("{report}");
}
