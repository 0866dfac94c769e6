//! DBSCAN and VFH on real KITTI scans (tracking sequence 0000), after the default filter and
//! ground removal:
//! - the grid and the k-d tree DBSCAN give the identical partition and core points;
//! - every histogram has PCL's block sums (f1-f3 at most 100·n/(n-1), distance 0,
//!   viewpoint 100);
//! - a labelled object's cluster in frame t+1 is, by χ², nearer to its own cluster in frame t
//!   than the median other cluster is (what frame-to-frame association relies on).

use nalgebra::{Point3, Vector3};
use trackd_dataset::{bin::read_bin, calib::read_tracking_calib, labels::read_label_02};
use trackd_perception::{
    Point,
    cluster::{ClusterConfig, Clustering, NOISE, NeighbourIndex, dbscan},
    filter::{Filter, FilterConfig},
    ground::GroundRemoval,
    vfh::{ClusterVfh, VfhConfig, VfhEstimator, chi_squared},
};

/// One scan after filtering and ground removal, clustered and described.
struct Scan {
    points: Vec<Point>,
    clustering: Clustering,
    descriptors: Vec<ClusterVfh>,
}

fn process(path: &std::path::Path) -> Scan {
    let scan = read_bin(path).expect("scan");
    let mut filtered = Vec::new();
    Filter::new(FilterConfig::default()).run(&scan, &mut filtered);
    let mut points = Vec::new();
    GroundRemoval::default().remove(&filtered, &mut points);
    let clustering = dbscan(&points, &ClusterConfig::default()).expect("dbscan");
    let mut descriptors = Vec::new();
    VfhEstimator::default().compute_clusters(&points, &clustering, [0.0; 3], &mut descriptors);
    Scan {
        points,
        clustering,
        descriptors,
    }
}

#[test]
fn grid_and_kd_tree_agree_on_a_real_scan() {
    let Some(data) = trackd_dataset::shared_data_dir("DBSCAN on a real KITTI scan") else {
        return;
    };
    let scan = process(&data.join("kitti-tracking-0000-first40/training/velodyne/0000/000010.bin"));
    let tree = dbscan(
        &scan.points,
        &ClusterConfig {
            index: NeighbourIndex::KdTree,
            ..Default::default()
        },
    )
    .expect("dbscan");
    assert!(scan.clustering.len() > 50);
    assert_eq!(scan.clustering.core, tree.core);
    assert_eq!(scan.clustering.labels, tree.labels);
}

#[test]
fn histograms_have_pcl_block_sums_and_follow_objects() {
    let Some(data) = trackd_dataset::shared_data_dir("VFH on real KITTI scans") else {
        return;
    };
    let root = data.join("kitti-tracking-0000-first40/training");
    let calib = read_tracking_calib(&root.join("calib/0000.txt")).expect("calibration");
    let to_camera = calib.velo_to_rect_cam();
    let labels = read_label_02(&root.join("label_02/0000.txt")).expect("labels");
    // The cluster holding most of a labelled object's points, by track id.
    let object_clusters = |frame: usize, scan: &Scan| -> Vec<(i64, usize)> {
        let mut found = Vec::new();
        for l in labels
            .iter()
            .filter(|l| l.frame == frame && !l.is_dont_care())
        {
            let (c, s) = (l.rotation_y.cos(), l.rotation_y.sin());
            let mut votes: Vec<i32> = scan
                .points
                .iter()
                .zip(&scan.clustering.labels)
                .filter(|&(p, &label)| {
                    let q =
                        to_camera.transform_point(&Point3::new(p.x as f64, p.y as f64, p.z as f64));
                    let d = q.coords - Vector3::new(l.x, l.y, l.z);
                    let (lx, lz) = (c * d.x - s * d.z, s * d.x + c * d.z);
                    label != NOISE
                        && lx.abs() <= l.l / 2.0
                        && lz.abs() <= l.w / 2.0
                        && -d.y >= 0.0
                        && -d.y <= l.h
                })
                .map(|(_, &label)| label)
                .collect();
            if votes.len() < 30 {
                continue;
            }
            votes.sort_unstable();
            let best = votes
                .chunk_by(|a, b| a == b)
                .max_by_key(|run| run.len())
                .map(|run| run[0]);
            if let Some(cluster) = best {
                found.push((l.track_id, cluster as usize));
            }
        }
        found
    };

    let (mut pairs, mut nearer, mut nearest) = (0, 0, 0);
    let mut previous: Option<(usize, Scan)> = None;
    for frame in 0..12 {
        let scan = process(&root.join(format!("velodyne/0000/{frame:06}.bin")));
        for d in &scan.descriptors {
            // The points used: every `stride`-th of big clusters.
            let stride = VfhConfig::default().sample_stride(d.points);
            let n = d.points.div_ceil(stride) as f32;
            let bins = &d.vfh.bins;
            for block in 0..3 {
                let sum: f32 = bins[block * 45..block * 45 + 45].iter().sum();
                assert!(sum <= 100.0 * n / (n - 1.0) + 0.05, "block {block}: {sum}");
            }
            assert!(bins[135..180].iter().all(|&b| b == 0.0));
            let viewpoint: f32 = bins[180..].iter().sum();
            assert!((viewpoint - 100.0).abs() < 0.05);
        }
        if let Some((before, last)) = &previous {
            let vfh_of = |scan: &Scan, cluster: usize| {
                scan.descriptors
                    .iter()
                    .find(|d| d.cluster == cluster)
                    .map(|d| d.vfh)
            };
            let earlier = object_clusters(*before, last);
            for (track, cluster) in object_clusters(frame, &scan) {
                let Some(&(_, old)) = earlier.iter().find(|(t, _)| *t == track) else {
                    continue;
                };
                let (Some(now), Some(then)) = (vfh_of(&scan, cluster), vfh_of(last, old)) else {
                    continue;
                };
                let own = chi_squared(&now, &then);
                let mut others: Vec<f64> = last
                    .descriptors
                    .iter()
                    .filter(|d| d.cluster != old)
                    .map(|d| chi_squared(&now, &d.vfh))
                    .collect();
                others.sort_by(f64::total_cmp);
                pairs += 1;
                nearer += usize::from(own < others[others.len() / 2]);
                nearest += usize::from(own < others[0]);
            }
        }
        previous = Some((frame, scan));
    }
    eprintln!(
        "{nearer} of {pairs} objects nearer to themselves than to the median other cluster, \
         {nearest} nearer than to every other cluster"
    );
    assert!(pairs >= 20);
    assert!(nearer as f64 >= 0.9 * pairs as f64);
}
