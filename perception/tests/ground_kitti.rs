//! Ground removal and clustering on real KITTI scans (tracking sequence 0000, every 4th of
//! frames 0-39), judged with the sequence's labelled boxes:
//! - over-removal: of the points inside labelled objects more than 0.3 m above the box
//!   bottom, at most 2 % are taken for ground;
//! - ground leaks: at most 3 clusters per scan, on average, that are flat (under 0.25 m tall),
//!   low (top below the sensor's -1.3 m) and outside every labelled box;
//! - every labelled object with 20 or more non-ground points keeps at least 90 % of them in one
//!   cluster (default eps and min_points).

use nalgebra::{Point3, Vector3};
use trackd_dataset::{bin::read_bin, calib::read_tracking_calib, labels::read_label_02};
use trackd_perception::{
    Point,
    cluster::{ClusterConfig, NOISE, dbscan},
    filter::{Filter, FilterConfig},
    ground::GroundRemoval,
};

/// A labelled box in the rectified camera frame (KITTI: y down, origin at the bottom centre).
struct Box3 {
    h: f64,
    w: f64,
    l: f64,
    center: Vector3<f64>,
    rotation_y: f64,
}

impl Box3 {
    /// Height above the box bottom if `p` (camera frame) is inside the box grown by
    /// `margin` metres, else `None`.
    fn height_inside(&self, p: &Point3<f64>, margin: f64) -> Option<f64> {
        let d = p.coords - self.center;
        let (c, s) = (self.rotation_y.cos(), self.rotation_y.sin());
        let (lx, lz) = (c * d.x - s * d.z, s * d.x + c * d.z);
        let up = -d.y;
        (lx.abs() <= self.l / 2.0 + margin
            && lz.abs() <= self.w / 2.0 + margin
            && up >= -margin
            && up <= self.h + margin)
            .then_some(up)
    }
}

#[test]
fn real_scans_keep_objects_and_leak_little_ground() {
    let Some(data) = trackd_dataset::shared_data_dir("ground removal on real KITTI scans") else {
        return;
    };
    let root = data.join("kitti-tracking-0000-first40/training");
    let calib = read_tracking_calib(&root.join("calib/0000.txt")).expect("calibration");
    let to_camera = calib.velo_to_rect_cam();
    let labels = read_label_02(&root.join("label_02/0000.txt")).expect("labels");
    let mut filter = Filter::new(FilterConfig::default());
    let mut removal = GroundRemoval::default();
    let (mut object_points, mut object_removed, mut leaks, mut scans) = (0, 0, 0, 0);
    let mut kept_together = Vec::new();
    for frame in (0..40).step_by(4) {
        let scan = read_bin(&root.join(format!("velodyne/0000/{frame:06}.bin"))).expect("scan");
        let boxes: Vec<Box3> = labels
            .iter()
            .filter(|l| l.frame == frame && !l.is_dont_care() && l.object_type != "Misc")
            .map(|l| Box3 {
                h: l.h,
                w: l.w,
                l: l.l,
                center: Vector3::new(l.x, l.y, l.z),
                rotation_y: l.rotation_y,
            })
            .collect();
        let mut points = Vec::new();
        filter.run(&scan, &mut points);
        let mut ground = Vec::new();
        removal.segment(&points, &mut ground);
        let camera: Vec<Point3<f64>> = points
            .iter()
            .map(|p| to_camera.transform_point(&Point3::new(p.x as f64, p.y as f64, p.z as f64)))
            .collect();
        let non_ground: Vec<(usize, Point)> = points
            .iter()
            .enumerate()
            .filter(|(i, _)| !ground[*i])
            .map(|(i, p)| (i, *p))
            .collect();
        let cloud: Vec<Point> = non_ground.iter().map(|(_, p)| *p).collect();
        let clustering = dbscan(&cloud, &ClusterConfig::default()).expect("dbscan");

        for b in &boxes {
            let mut members = Vec::new();
            for (i, p) in camera.iter().enumerate() {
                if let Some(up) = b.height_inside(p, 0.1)
                    && up > 0.3
                {
                    object_points += 1;
                    object_removed += usize::from(ground[i]);
                }
            }
            for (k, (i, _)) in non_ground.iter().enumerate() {
                if b.height_inside(&camera[*i], 0.1).is_some() && clustering.labels[k] != NOISE {
                    members.push(clustering.labels[k]);
                }
            }
            if members.len() >= 20 {
                members.sort_unstable();
                let largest = members
                    .chunk_by(|a, b| a == b)
                    .map(<[i32]>::len)
                    .max()
                    .unwrap_or(0);
                kept_together.push(largest as f64 / members.len() as f64);
            }
        }
        for members in clustering.clusters() {
            let (lo, hi) =
                members
                    .iter()
                    .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &k| {
                        let z = cloud[k as usize].z;
                        (lo.min(z), hi.max(z))
                    });
            let in_a_box = members.iter().any(|&k| {
                let i = non_ground[k as usize].0;
                boxes
                    .iter()
                    .any(|b| b.height_inside(&camera[i], 0.1).is_some())
            });
            if hi - lo < 0.25 && hi < -1.3 && !in_a_box {
                leaks += 1;
            }
        }
        scans += 1;
    }
    let removed = object_removed as f64 / object_points as f64;
    let leaks_per_scan = leaks as f64 / scans as f64;
    let worst_split = kept_together.iter().copied().fold(1.0, f64::min);
    eprintln!(
        "{scans} scans: {object_removed} of {object_points} object points above 0.3 m taken for \
         ground ({:.2} %), {leaks_per_scan:.1} flat low clusters per scan, {} objects, worst \
         share in one cluster {worst_split:.3}",
        100.0 * removed,
        kept_together.len()
    );
    assert!(object_points > 5_000);
    assert!(removed <= 0.02);
    assert!(leaks_per_scan <= 3.0);
    assert!(kept_together.len() >= 20);
    assert!(worst_split >= 0.9);
}
