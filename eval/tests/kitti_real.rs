//! The protocol on real KITTI ground truth: the first 40 frames of tracking sequence 0000 (with
//! scans), the labels of sequence 0001 (no scans) and the tracklets of raw drive 0001.

use std::path::Path;

use trackd_dataset::shared_data_dir;
use trackd_eval::{
    EvalConfig, GroundTruth, TrackRow, evaluate,
    gt::{
        kitti::{KittiRules, KittiTrackingFiles, read_kitti_tracking_ground_truth},
        tracklets::{KittiRawFiles, read_kitti_raw_ground_truth},
    },
};

/// The counted GT objects as a tracker's output.
fn as_tracks(gt: &GroundTruth) -> Vec<TrackRow> {
    gt.frames
        .iter()
        .flat_map(|f| {
            f.objects.iter().map(|o| TrackRow {
                frame: f.frame,
                track_id: o.id + 1000,
                centre: o.centre,
                size: [4.0, 1.8, 1.5],
                yaw: 0.0,
                velocity: [0.0, 0.0],
                confidence: 1.0,
                class: o.class.clone(),
            })
        })
        .collect()
}

/// Scoring the ground truth against itself is perfect.
fn assert_self_score_is_perfect(gt: &GroundTruth) {
    let tracks = as_tracks(gt);
    let m = evaluate(gt, &tracks, &EvalConfig::default());
    assert_eq!(m.clear.num_objects, tracks.len());
    assert_eq!(m.clear.mota, 1.0);
    assert_eq!(m.clear.motp, 0.0);
    assert_eq!(m.identity.idf1, 1.0);
    assert!((m.hota.hota - 1.0).abs() < 1e-12, "{:?}", m.hota);
    assert_eq!((m.clear.false_positives, m.clear.misses), (0, 0));
    assert_eq!(m.clear.switches, 0);
    assert_eq!(m.hypotheses_excused.outside_view, 0);
}

#[test]
fn tracking_0000_first_40_frames() {
    let Some(data) = shared_data_dir("eval on KITTI tracking 0000") else {
        return;
    };
    let training = data.join("kitti-tracking-0000-first40/training");
    let files = KittiTrackingFiles::beside(&training.join("label_02/0000.txt"));
    assert!(files.scans.is_some(), "velodyne/0000 beside the labels");
    let gt = read_kitti_tracking_ground_truth(&files, &KittiRules::default()).unwrap();
    assert_eq!(gt.frames.len(), 40);
    assert!(gt.filtering.points_checked);
    // The sequence: a cyclist riding ahead, vans, a pedestrian; 121 counted boxes, 64 DontCare.
    let kept = gt.num_objects();
    let dropped = gt.filtering.outside_view + gt.filtering.too_few_points;
    assert_eq!(kept + dropped, 121);
    assert!(
        (60..=121).contains(&kept),
        "{kept} kept, {:?}",
        gt.filtering
    );
    assert_eq!(
        gt.frames
            .iter()
            .map(|f| f.ignore_regions.len())
            .sum::<usize>(),
        64
    );
    // The cyclist ahead (track 1) is labelled in every frame, close, with many points.
    let cyclist_frames = gt
        .frames
        .iter()
        .filter(|f| f.objects.iter().any(|o| o.id == 1 && o.class == "Cyclist"))
        .count();
    assert_eq!(cyclist_frames, 40);
    let view = gt.view.as_ref().unwrap();
    for o in gt.frames.iter().flat_map(|f| &f.objects) {
        assert!(view.contains(o.centre));
        // Box centres sit about a metre below the sensor (1.73 m above the road).
        assert!((-1.6..0.5).contains(&o.centre[2]), "{o:?}");
    }
    assert_self_score_is_perfect(&gt);

    // A track behind the car is outside the camera's view: not scored.
    let mut tracks = as_tracks(&gt);
    tracks.push(TrackRow {
        centre: [-8.0, 0.0, -0.8],
        track_id: 1,
        ..tracks[0].clone()
    });
    let m = evaluate(&gt, &tracks, &EvalConfig::default());
    assert_eq!(m.hypotheses_excused.outside_view, 1);
    assert_eq!(m.clear.false_positives, 0);
}

#[test]
fn tracking_0001_labels_without_scans() {
    let Some(data) = shared_data_dir("eval on KITTI tracking 0001 labels") else {
        return;
    };
    let tracking = data.join("kitti-format-samples/tracking");
    let files = KittiTrackingFiles::beside(&tracking.join("label_02/0001.txt"));
    assert_eq!(files.scans, None);
    let gt = read_kitti_tracking_ground_truth(&files, &KittiRules::default()).unwrap();
    assert!(!gt.filtering.points_checked);
    assert_eq!(gt.filtering.too_few_points, 0);
    // 3010 counted-class boxes (Car, Van, Truck, Pedestrian); those past 40 m or out of the
    // image are dropped; 20 Misc boxes excuse hypotheses near them.
    let kept = gt.num_objects();
    assert_eq!(kept + gt.filtering.outside_view, 2681 + 140 + 77 + 112);
    assert!(
        kept > 1000 && gt.filtering.outside_view > 100,
        "{kept} kept"
    );
    let misc: usize = gt.frames.iter().map(|f| f.ignore_near.len()).sum();
    assert_eq!(misc, 20 + gt.filtering.outside_view);
    assert_self_score_is_perfect(&gt);
}

#[test]
fn raw_drive_0001_tracklets() {
    let Some(data) = shared_data_dir("eval on KITTI raw 0001 tracklets") else {
        return;
    };
    let drive = data.join("kitti-format-samples/raw/2011_09_26/2011_09_26_drive_0001_sync");
    let files = KittiRawFiles::beside(&drive.join("tracklet_labels.xml"));
    assert!(files.calib_dir.is_some());
    assert_eq!(files.scans, None);
    let gt = read_kitti_raw_ground_truth(&files, &KittiRules::default()).unwrap();
    assert_eq!(gt.frames.len(), 108);
    assert!(gt.view.as_ref().is_some_and(|v| v.camera.is_some()));
    assert!(gt.num_objects() > 100, "{} kept", gt.num_objects());
    assert_self_score_is_perfect(&gt);
    // Without the calibration only the 40 m range bounds the view: more boxes count.
    let range_only = KittiRawFiles {
        calib_dir: None,
        ..files
    };
    let wide = read_kitti_raw_ground_truth(&range_only, &KittiRules::default()).unwrap();
    assert!(wide.num_objects() > gt.num_objects());
    assert!(Path::new(&range_only.tracklets).is_file());
}
