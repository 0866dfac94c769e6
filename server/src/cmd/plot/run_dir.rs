//! A `trackd run` output folder placed in the world frame: `tracks.csv` holds each box in the
//! Velodyne frame of its scan, `ego_poses.txt` that frame's pose in the world frame (one line
//! per scan, KITTI odometry format).

use std::path::Path;

use anyhow::Context;
use nalgebra::{Isometry3, Point3, Vector3};
use trackd_dataset::poses::read_poses;
use trackd_eval::{TrackRow, read_tracks_csv};

/// A track's box at one frame, in the world frame (bird's-eye view).
#[derive(Clone, Debug, PartialEq)]
pub struct WorldBox {
    /// Frame index.
    pub frame: u32,
    /// Box centre: x, y (metres).
    pub centre: [f64; 2],
    /// Length and width (metres).
    pub size: [f64; 2],
    /// Heading about z (radians).
    pub yaw: f64,
}

impl WorldBox {
    /// The four corners, in order around the box.
    pub fn corners(&self) -> [[f64; 2]; 4] {
        let (c, s) = (self.yaw.cos(), self.yaw.sin());
        let (hl, hw) = (self.size[0] / 2.0, self.size[1] / 2.0);
        [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)].map(|(a, b)| {
            [
                self.centre[0] + c * a * hl - s * b * hw,
                self.centre[1] + s * a * hl + c * b * hw,
            ]
        })
    }
}

/// One track over the drive.
#[derive(Clone, Debug, PartialEq)]
pub struct WorldTrack {
    /// Track id.
    pub id: u64,
    /// Class of its last row.
    pub class: String,
    /// Its boxes, by frame.
    pub boxes: Vec<WorldBox>,
}

/// What a run folder holds, in the world frame.
#[derive(Clone, Debug)]
pub struct WorldDrive {
    /// The Velodyne pose of each scan in the world frame.
    pub ego: Vec<Isometry3<f64>>,
    /// The tracks, by id.
    pub tracks: Vec<WorldTrack>,
}

/// Reads `tracks.csv` and `ego_poses.txt` from `dir`.
pub fn read(dir: &Path) -> anyhow::Result<WorldDrive> {
    anyhow::ensure!(
        dir.is_dir(),
        "{}: not a folder (expected what `trackd run --out DIR` writes)",
        dir.display()
    );
    let poses = dir.join("ego_poses.txt");
    let ego = read_poses(&poses)?;
    let tracks_csv = dir.join("tracks.csv");
    let rows = read_tracks_csv(&tracks_csv)?;
    let tracks = place(&rows, &ego).with_context(|| format!("placing {}", tracks_csv.display()))?;
    Ok(WorldDrive { ego, tracks })
}

/// The rows grouped by track and moved into the world frame with their frame's pose.
pub fn place(rows: &[TrackRow], ego: &[Isometry3<f64>]) -> anyhow::Result<Vec<WorldTrack>> {
    let mut tracks: Vec<WorldTrack> = Vec::new();
    let mut sorted: Vec<&TrackRow> = rows.iter().collect();
    sorted.sort_by_key(|r| (r.track_id, r.frame));
    for row in sorted {
        let Some(pose) = ego.get(row.frame as usize) else {
            anyhow::bail!(
                "frame {} (track {}) has no ego pose: ego_poses.txt holds {} poses",
                row.frame,
                row.track_id,
                ego.len()
            );
        };
        let [x, y, z] = row.centre;
        let centre = pose * Point3::new(x, y, z);
        let heading = pose.rotation * Vector3::new(row.yaw.cos(), row.yaw.sin(), 0.0);
        let world = WorldBox {
            frame: row.frame,
            centre: [centre.x, centre.y],
            size: [row.size[0], row.size[1]],
            yaw: heading.y.atan2(heading.x),
        };
        match tracks.last_mut() {
            Some(track) if track.id == row.track_id => {
                track.class.clone_from(&row.class);
                track.boxes.push(world);
            }
            _ => tracks.push(WorldTrack {
                id: row.track_id,
                class: row.class.clone(),
                boxes: vec![world],
            }),
        }
    }
    Ok(tracks)
}

#[cfg(test)]
mod tests {
    use std::f64::consts::FRAC_PI_2;

    use nalgebra::{Translation3, UnitQuaternion};

    use super::*;

    fn row(frame: u32, id: u64, x: f64, y: f64, yaw: f64) -> TrackRow {
        TrackRow {
            frame,
            track_id: id,
            centre: [x, y, 0.0],
            size: [4.0, 2.0, 1.5],
            yaw,
            velocity: [0.0, 0.0],
            confidence: 0.9,
            class: "car".into(),
        }
    }

    #[test]
    fn boxes_are_moved_by_their_frames_pose() {
        // Frame 1: the sensor 10 m east, turned to face north.
        let ego = vec![
            Isometry3::identity(),
            Isometry3::from_parts(
                Translation3::new(10.0, 0.0, 0.0),
                UnitQuaternion::from_euler_angles(0.0, 0.0, FRAC_PI_2),
            ),
        ];
        let rows = [row(1, 3, 5.0, 0.0, 0.0), row(0, 3, 15.0, 0.0, 0.0)];
        let tracks = place(&rows, &ego).unwrap();
        assert_eq!(tracks.len(), 1);
        let boxes = &tracks[0].boxes;
        assert_eq!(boxes[0].frame, 0);
        assert!((boxes[0].centre[0] - 15.0).abs() < 1e-9);
        // 5 m ahead of a sensor facing north at (10, 0) is (10, 5), heading north.
        assert!((boxes[1].centre[0] - 10.0).abs() < 1e-9, "{:?}", boxes[1]);
        assert!((boxes[1].centre[1] - 5.0).abs() < 1e-9, "{:?}", boxes[1]);
        assert!((boxes[1].yaw - FRAC_PI_2).abs() < 1e-9);
    }

    #[test]
    fn a_frame_without_pose_is_an_error() {
        let err = place(&[row(2, 9, 0.0, 0.0, 0.0)], &[Isometry3::identity()]).unwrap_err();
        assert!(err.to_string().contains("frame 2 (track 9)"), "{err}");
    }

    #[test]
    fn corners_go_around_the_box() {
        let b = WorldBox {
            frame: 0,
            centre: [1.0, 1.0],
            size: [4.0, 2.0],
            yaw: 0.0,
        };
        assert_eq!(
            b.corners(),
            [[3.0, 2.0], [-1.0, 2.0], [-1.0, 0.0], [3.0, 0.0]]
        );
    }
}
