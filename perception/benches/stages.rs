//! The per-frame stages one by one on a real 120k-point KITTI scan (tracking sequence 0000,
//! frame 0, from the shared data folder): filter (with and without voxels), ground removal,
//! world transform, DBSCAN (grid and k-d tree), VFH of every cluster. Each stage gets the
//! output of the previous ones with default settings. Skipped, saying so, without the data.
//!
//! `trackd bench` times the same chain end to end.

use std::{hint::black_box, sync::OnceLock};

use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use trackd_perception::{
    Point,
    cluster::{ClusterConfig, Clustering, Dbscan, NeighbourIndex},
    filter::{Filter, FilterConfig},
    ground::GroundRemoval,
    transform::to_world,
    vfh::VfhEstimator,
};

/// The scan and every stage's output on it.
struct Inputs {
    scan: Vec<Point>,
    filtered: Vec<Point>,
    non_ground: Vec<Point>,
    clustering: Clustering,
}

fn inputs() -> Option<&'static Inputs> {
    static INPUTS: OnceLock<Option<Inputs>> = OnceLock::new();
    INPUTS
        .get_or_init(|| {
            let data = trackd_dataset::shared_data_dir("perception stage benches")?;
            let path = data.join("kitti-tracking-0000-first40/training/velodyne/0000/000000.bin");
            let scan = trackd_dataset::bin::read_bin(&path).ok()?;
            let mut filtered = Vec::new();
            Filter::new(FilterConfig::default()).run(&scan, &mut filtered);
            let mut non_ground = Vec::new();
            GroundRemoval::default().remove(&filtered, &mut non_ground);
            let mut clustering = Clustering::default();
            Dbscan::new(ClusterConfig::default())
                .run(&non_ground, &mut clustering)
                .ok()?;
            Some(Inputs {
                scan,
                filtered,
                non_ground,
                clustering,
            })
        })
        .as_ref()
}

fn main() {
    if inputs().is_none() {
        eprintln!("perception stage benches: no real scan to run on, nothing measured");
        return;
    }
    divan::main();
}

fn data() -> &'static Inputs {
    inputs().expect("checked in main")
}

#[divan::bench]
fn filter(bencher: divan::Bencher) {
    let mut filter = Filter::new(FilterConfig::default());
    let mut out = Vec::new();
    bencher.bench_local(|| {
        filter.run(black_box(&data().scan), &mut out);
        out.len()
    });
}

#[divan::bench]
fn filter_voxel_10cm(bencher: divan::Bencher) {
    let mut filter = Filter::new(FilterConfig {
        voxel_size: Some(0.1),
        ..Default::default()
    });
    let mut out = Vec::new();
    bencher.bench_local(|| {
        filter.run(black_box(&data().scan), &mut out);
        out.len()
    });
}

#[divan::bench]
fn ground(bencher: divan::Bencher) {
    let mut ground = GroundRemoval::default();
    let mut out = Vec::new();
    bencher.bench_local(|| {
        ground.remove(black_box(&data().filtered), &mut out);
        out.len()
    });
}

#[divan::bench]
fn transform(bencher: divan::Bencher) {
    let pose = Isometry3::from_parts(
        Translation3::new(512.0, -230.0, 3.0),
        UnitQuaternion::from_euler_angles(0.01, 0.02, 1.2),
    );
    let mut out = Vec::new();
    bencher.bench_local(|| {
        to_world(black_box(&data().non_ground), &pose, &mut out);
        out.len()
    });
}

#[divan::bench(args = [NeighbourIndex::Grid, NeighbourIndex::KdTree], sample_count = 20)]
fn dbscan(bencher: divan::Bencher, index: NeighbourIndex) {
    let mut dbscan = Dbscan::new(ClusterConfig {
        index,
        ..Default::default()
    });
    let mut out = Clustering::default();
    bencher.bench_local(|| {
        dbscan
            .run(black_box(&data().non_ground), &mut out)
            .map_or(0, |_| out.len())
    });
}

#[divan::bench]
fn vfh(bencher: divan::Bencher) {
    let mut vfh = VfhEstimator::default();
    let mut out = Vec::new();
    bencher.bench_local(|| {
        vfh.compute_clusters(
            black_box(&data().non_ground),
            &data().clustering,
            [0.0; 3],
            &mut out,
        );
        out.len()
    });
}
