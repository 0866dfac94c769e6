//! Reading one 120k-point scan, the way every offline command does: `.bin`, binary PCD,
//! compressed PCD, ascii PCD, and a whole `Source::frame` (scan + dropping invalid points).
//! Files are written to a temporary folder first (synthetic HDL-64E-sized scans).

use std::hint::black_box;
use std::path::{Path, PathBuf};

use trackd_dataset::{
    OpenOptions, bin,
    pcd::{self, PcdData},
};
use trackd_perception::Point;

fn main() {
    divan::main();
}

const POINTS: usize = 120_000;

/// A scan shaped like a Velodyne sweep: 64 rings, ranges 5-80 m.
fn scan() -> Vec<Point> {
    (0..POINTS)
        .map(|i| {
            let ring = (i % 64) as f32;
            let azimuth = (i / 64) as f32 * (std::f32::consts::TAU / (POINTS / 64) as f32);
            let range = 5.0 + (i % 751) as f32 * 0.1;
            let elevation = (-24.8 + ring * 0.42).to_radians();
            Point::new(
                range * elevation.cos() * azimuth.cos(),
                range * elevation.cos() * azimuth.sin(),
                range * elevation.sin(),
                (i % 100) as f32 / 100.0,
            )
        })
        .collect()
}

/// The folder holding one file per format, written once.
fn files() -> &'static Path {
    static DIR: std::sync::OnceLock<(tempfile::TempDir, PathBuf)> = std::sync::OnceLock::new();
    &DIR.get_or_init(|| {
        let dir = tempfile::tempdir().expect("temporary folder");
        let root = dir.path().to_path_buf();
        let points = scan();
        bin::write_bin(&root.join("scan.bin"), &points).expect("write .bin");
        for (name, data) in [
            ("binary", PcdData::Binary),
            ("compressed", PcdData::BinaryCompressed),
            ("ascii", PcdData::Ascii),
        ] {
            pcd::write_pcd(&root.join(format!("{name}.pcd")), &points, data).expect("write .pcd");
        }
        (dir, root)
    })
    .1
}

#[divan::bench]
fn bin_120k() -> usize {
    bin::read_bin(black_box(&files().join("scan.bin"))).map_or(0, |p| p.len())
}

#[divan::bench(args = ["binary", "compressed", "ascii"])]
fn pcd_120k(kind: &str) -> usize {
    pcd::read_pcd(black_box(&files().join(format!("{kind}.pcd")))).map_or(0, |p| p.len())
}

#[divan::bench]
fn source_frame_120k(bencher: divan::Bencher) {
    let source = trackd_dataset::open(&files().join("scan.bin"), &OpenOptions::default())
        .expect("open the scan");
    bencher.bench(|| source.frame(black_box(0)).map_or(0, |f| f.points.len()));
}
