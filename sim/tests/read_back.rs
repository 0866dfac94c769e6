//! What the simulator writes is read back by the dataset crate's own readers, as written.

use trackd_dataset::calib::{RawCalib, read_raw_calib};
use trackd_dataset::source::{OpenOptions, SourceKind, open};
use trackd_dataset::tracklets::read_tracklets;
use trackd_perception::Ego;
use trackd_sim::write::DATE;
use trackd_sim::{Scenario, SimConfig, read_gt_csv, simulate, write_run};

#[test]
fn a_written_fleet_reads_back_frame_for_frame() {
    let config = SimConfig::new(Scenario::Paper, 8, 11).with_vehicles(2);
    let run = simulate(&config).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let drives = write_run(&run, dir.path()).unwrap();
    assert_eq!(drives.len(), 2);
    assert!(drives[1].ends_with(format!("{DATE}/{DATE}_drive_0002_sync")));
    assert_eq!(
        read_raw_calib(&dir.path().join(DATE)).unwrap().imu_to_velo,
        RawCalib::kitti_2011_09_26().imu_to_velo
    );

    for (k, drive) in drives.iter().enumerate() {
        let frames = &run.vehicles[k];
        let source = open(drive, &OpenOptions::default()).unwrap();
        assert_eq!(source.kind(), SourceKind::KittiRaw);
        assert_eq!(source.len(), frames.len());
        for (i, sim) in frames.iter().enumerate() {
            let read = source.frame(i).unwrap();
            assert_eq!(read.points, sim.points, "vehicle {k} frame {i}");
            assert!((read.timestamp - sim.timestamp).abs() < 1e-6);
            let Ego::Oxts(o) = read.ego else {
                panic!("frame {i} has no OXTS packet");
            };
            for (a, b) in o.to_values().iter().zip(sim.oxts.to_values()) {
                assert!((a - b).abs() <= 1e-9 * b.abs().max(1.0), "{a} vs {b}");
            }
        }

        // Ground truth: the CSV holds every row, the tracklets every row's box.
        let rows = read_gt_csv(&drive.join("gt_tracks.csv")).unwrap();
        let expected: usize = frames.iter().map(|f| f.objects.len()).sum();
        assert_eq!(rows.len(), expected);
        assert!(rows.iter().any(|r| r.npoints > 0));
        let tracklets = read_tracklets(&drive.join("tracklet_labels.xml")).unwrap();
        let poses: usize = tracklets.iter().map(|t| t.poses.len()).sum();
        assert_eq!(poses, expected);
        for row in &rows {
            let found = tracklets.iter().any(|t| {
                t.pose_at(row.frame).is_some_and(|p| {
                    t.object_type == row.class.kitti_name()
                        && (p.tx - row.center.x).abs() < 1e-4
                        && (p.ty - row.center.y).abs() < 1e-4
                        && (p.tz - (row.center.z - row.size[2] / 2.0)).abs() < 1e-4
                })
            });
            assert!(found, "no tracklet for {row:?}");
        }
    }
}
