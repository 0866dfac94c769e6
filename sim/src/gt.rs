//! Ground truth per frame: every object near a vehicle, its box in the Velodyne frame, its
//! velocity and how many points of the scan are on it; and its `gt_tracks.csv` file.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use nalgebra::{Isometry3, Point3, Vector2, Vector3};

use crate::class::Class;
use crate::error::SimError;
use crate::label::PointLabel;
use crate::world::World;

/// Objects within this horizontal distance of the Velodyne are in a frame's ground truth.
pub const GT_RANGE: f64 = 80.0;

/// Header line of `gt_tracks.csv`.
pub const GT_CSV_HEADER: &str = "frame,id,class,x,y,z,l,w,h,yaw,vx,vy,npoints";

/// One object in one frame's ground truth.
#[derive(Clone, Debug, PartialEq)]
pub struct GtObject {
    /// Frame index within the vehicle's drive.
    pub frame: usize,
    /// Global object id (the same for every vehicle).
    pub id: u32,
    /// KITTI class.
    pub class: Class,
    /// Box centre in that frame's Velodyne frame (metres).
    pub center: Vector3<f64>,
    /// Box size: length, width, height (metres).
    pub size: [f64; 3],
    /// Heading of the box's length axis in the Velodyne frame (radians, about z).
    pub yaw: f64,
    /// Velocity over ground in the world frame (m/s).
    pub velocity: Vector2<f64>,
    /// Points of the scan on the object.
    pub npoints: usize,
}

impl GtObject {
    /// The object's `gt_tracks.csv` line (no newline).
    pub fn csv_row(&self) -> String {
        let c = &self.center;
        let [l, w, h] = self.size;
        format!(
            "{},{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{}",
            self.frame,
            self.id,
            self.class.kitti_name(),
            c.x,
            c.y,
            c.z,
            l,
            w,
            h,
            self.yaw,
            self.velocity.x,
            self.velocity.y,
            self.npoints
        )
    }

    /// Whether a Velodyne-frame point lies in the box (with `margin` metres added).
    pub fn contains(&self, p: &Vector3<f64>, margin: f64) -> bool {
        let d = p - self.center;
        let (sin, cos) = self.yaw.sin_cos();
        let (x, y) = (cos * d.x + sin * d.y, -sin * d.x + cos * d.y);
        x.abs() <= self.size[0] / 2.0 + margin
            && y.abs() <= self.size[1] / 2.0 + margin
            && d.z.abs() <= self.size[2] / 2.0 + margin
    }
}

/// The ground truth of vehicle `vehicle`'s frame `frame`, taken at time `t` from the
/// Velodyne pose `velodyne_pose`, counting points by the scan's `labels`.
pub fn ground_truth(
    world: &World,
    vehicle: usize,
    frame: usize,
    t: f64,
    velodyne_pose: &Isometry3<f64>,
    labels: &[PointLabel],
) -> Vec<GtObject> {
    let mut counts: HashMap<u32, usize> = HashMap::new();
    for id in labels.iter().filter_map(PointLabel::object_id) {
        *counts.entry(id).or_default() += 1;
    }
    let own = world.vehicle(vehicle).id;
    let to_velo = velodyne_pose.inverse();
    world
        .actors
        .iter()
        .filter(|a| a.id != own)
        .filter_map(|actor| {
            let pose = actor.pose_at(t, &world.terrain);
            let center = to_velo.transform_point(&Point3::from(pose.center)).coords;
            if center.xy().norm() > GT_RANGE {
                return None;
            }
            let heading = to_velo.rotation * Vector3::new(pose.yaw.cos(), pose.yaw.sin(), 0.0);
            Some(GtObject {
                frame,
                id: actor.id,
                class: actor.class,
                center,
                size: actor.size,
                yaw: heading.y.atan2(heading.x),
                velocity: pose.velocity,
                npoints: counts.get(&actor.id).copied().unwrap_or(0),
            })
        })
        .collect()
}

/// Writes `gt_tracks.csv`: the header, then one line per object per frame.
pub fn write_gt_csv(path: &Path, objects: &[GtObject]) -> Result<(), SimError> {
    let mut text = String::with_capacity(64 * (objects.len() + 1));
    text.push_str(GT_CSV_HEADER);
    text.push('\n');
    for o in objects {
        let _ = writeln!(text, "{}", o.csv_row());
    }
    std::fs::write(path, text).map_err(|source| SimError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Reads a `gt_tracks.csv` written by [`write_gt_csv`].
pub fn read_gt_csv(path: &Path) -> Result<Vec<GtObject>, SimError> {
    let text = std::fs::read_to_string(path).map_err(|source| SimError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let err = |line: usize, message: String| SimError::Parse {
        path: path.to_path_buf(),
        line,
        message,
    };
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, header)) if header.trim() == GT_CSV_HEADER => {}
        _ => return Err(err(1, format!("expected the header {GT_CSV_HEADER:?}"))),
    }
    let mut objects = Vec::new();
    for (i, line) in lines {
        let n = i + 1;
        if line.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != 13 {
            return Err(err(
                n,
                format!("expected 13 fields, found {}", fields.len()),
            ));
        }
        let num = |k: usize| -> Result<f64, SimError> {
            fields[k]
                .parse::<f64>()
                .map_err(|e| err(n, format!("field {k} ({:?}): {e}", fields[k])))
        };
        let int = |k: usize| -> Result<u64, SimError> {
            fields[k]
                .parse::<u64>()
                .map_err(|e| err(n, format!("field {k} ({:?}): {e}", fields[k])))
        };
        let class = Class::from_kitti_name(fields[2])
            .ok_or_else(|| err(n, format!("unknown class {:?}", fields[2])))?;
        let id = u32::try_from(int(1)?).map_err(|e| err(n, format!("id: {e}")))?;
        objects.push(GtObject {
            frame: int(0)? as usize,
            id,
            class,
            center: Vector3::new(num(3)?, num(4)?, num(5)?),
            size: [num(6)?, num(7)?, num(8)?],
            yaw: num(9)?,
            velocity: Vector2::new(num(10)?, num(11)?),
            npoints: int(12)? as usize,
        });
    }
    Ok(objects)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn object() -> GtObject {
        GtObject {
            frame: 3,
            id: 17,
            class: Class::Cyclist,
            center: Vector3::new(12.5, -3.25, -0.85),
            size: [1.8, 0.6, 1.75],
            yaw: 0.1234567,
            velocity: Vector2::new(4.5, -0.25),
            npoints: 321,
        }
    }

    #[test]
    fn csv_round_trip() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("gt_tracks.csv");
        write_gt_csv(&path, &[object(), object()]).unwrap();
        let back = read_gt_csv(&path).unwrap();
        assert_eq!(back.len(), 2);
        let b = &back[0];
        let o = object();
        assert_eq!(
            (b.frame, b.id, b.class, b.npoints),
            (o.frame, o.id, o.class, o.npoints)
        );
        assert!((b.center - o.center).norm() < 1e-6 && (b.yaw - o.yaw).abs() < 1e-6);
    }

    #[test]
    fn malformed_lines_name_the_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("gt_tracks.csv");
        std::fs::write(
            &path,
            format!(
                "{GT_CSV_HEADER}\n1,2,Car,0,0,0,4,2,1.5,0,0,0,5\n1,2,Tram,0,0,0,4,2,1.5,0,0,0,5\n"
            ),
        )
        .unwrap();
        let e = read_gt_csv(&path).unwrap_err().to_string();
        assert!(e.contains(":3:") && e.contains("Tram"), "{e}");
    }

    #[test]
    fn box_containment_follows_yaw() {
        let mut o = object();
        o.yaw = std::f64::consts::FRAC_PI_2;
        // Length 1.8 now runs along y.
        assert!(o.contains(&(o.center + Vector3::new(0.0, 0.85, 0.0)), 0.0));
        assert!(!o.contains(&(o.center + Vector3::new(0.85, 0.0, 0.0)), 0.0));
    }
}
