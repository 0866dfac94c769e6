//! KITTI odometry-format poses (`poses/<seq>.txt`): line i is the 3x4 row-major pose of the
//! (rectified left) camera of frame i in the camera frame of frame 0.

use std::path::Path;

use nalgebra::{Isometry3, Matrix3x4, Matrix4, Vector3};

use crate::calib::{extend, isometry};
use crate::error::{DatasetError, parse_f64, read_text, write_bytes};
use crate::numfmt::c_exp;

/// Reads the poses as 4x4 homogeneous matrices, as written (not re-orthonormalised).
pub fn read_pose_matrices(path: &Path) -> Result<Vec<Matrix4<f64>>, DatasetError> {
    let text = read_text(path)?;
    let mut poses = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let tokens: Vec<&str> = line.split_whitespace().collect();
        if tokens.is_empty() {
            continue;
        }
        if tokens.len() != 12 {
            return Err(DatasetError::parse(
                path,
                i + 1,
                format!("{} values, a pose line has 12", tokens.len()),
            ));
        }
        let mut v = [0.0; 12];
        for (k, (x, t)) in v.iter_mut().zip(tokens).enumerate() {
            *x = parse_f64(path, i + 1, &format!("pose value {}", k + 1), t)?;
        }
        poses.push(extend(&Matrix3x4::from_row_slice(&v)));
    }
    Ok(poses)
}

/// Reads the poses as rigid transforms (rotations made exactly orthonormal).
pub fn read_poses(path: &Path) -> Result<Vec<Isometry3<f64>>, DatasetError> {
    Ok(read_pose_matrices(path)?.iter().map(to_isometry).collect())
}

/// Writes rigid poses in KITTI odometry format (`%e`, 12 values a line).
pub fn write_poses(path: &Path, poses: &[Isometry3<f64>]) -> Result<(), DatasetError> {
    let mut text = String::new();
    for pose in poses {
        let m = pose.to_homogeneous();
        let row: Vec<String> = (0..3)
            .flat_map(|r| (0..4).map(move |c| (r, c)))
            .map(|(r, c)| c_exp(m[(r, c)], 9))
            .collect();
        text += &row.join(" ");
        text.push('\n');
    }
    write_bytes(path, text.as_bytes())
}

/// Velodyne poses from camera poses: `inv(V)·T_i·V`, with `V` the Velodyne -> camera transform
/// the poses' camera frame uses (`R0_rect·Tr_velo_to_cam`), then expressed in the Velodyne
/// frame of the first pose (so the first is the identity). `None` if `V` or the first pose is
/// singular.
pub fn velodyne_poses(
    camera_poses: &[Matrix4<f64>],
    velo_to_cam: &Matrix4<f64>,
) -> Option<Vec<Isometry3<f64>>> {
    let cam_to_velo = velo_to_cam.try_inverse()?;
    let velo: Vec<Matrix4<f64>> = camera_poses
        .iter()
        .map(|t| cam_to_velo * t * velo_to_cam)
        .collect();
    let first_inv = velo
        .first()
        .map_or(Some(Matrix4::identity()), |p| p.try_inverse())?;
    Some(velo.iter().map(|p| to_isometry(&(first_inv * p))).collect())
}

/// A homogeneous matrix as a rigid transform (nearest rotation).
fn to_isometry(m: &Matrix4<f64>) -> Isometry3<f64> {
    let r = m.fixed_view::<3, 3>(0, 0).into_owned();
    let t: Vector3<f64> = m.fixed_view::<3, 1>(0, 3).into_owned();
    isometry(&r, &t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calib::read_tracking_calib;
    use crate::shared_data_dir;
    use nalgebra::{Translation3, UnitQuaternion};

    #[test]
    fn write_then_read_round_trips() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("00.txt");
        let poses: Vec<Isometry3<f64>> = (0..5)
            .map(|i| {
                Isometry3::from_parts(
                    Translation3::new(0.1 * i as f64, -2.0, 13.5 * i as f64),
                    UnitQuaternion::from_euler_angles(0.01, -0.2 * i as f64, 0.3),
                )
            })
            .collect();
        write_poses(&path, &poses).unwrap();
        let back = read_poses(&path).unwrap();
        assert_eq!(back.len(), 5);
        for (a, b) in poses.iter().zip(&back) {
            assert!((a.to_homogeneous() - b.to_homogeneous()).abs().max() < 1e-8);
        }
    }

    #[test]
    fn velodyne_poses_conjugate_by_the_calibration() {
        // A camera (x right, y down, z forward) moving 1 m forward per frame is a Velodyne
        // (x forward, y left, z up) moving 1 m along its x.
        let mut v = Matrix4::zeros();
        v[(0, 1)] = -1.0;
        v[(1, 2)] = -1.0;
        v[(2, 0)] = 1.0;
        v[(3, 3)] = 1.0;
        v[(1, 3)] = -0.08; // the camera sits 8 cm below the Velodyne
        let cams: Vec<Matrix4<f64>> = (0..3)
            .map(|i| Matrix4::new_translation(&Vector3::new(0.0, 0.0, i as f64)))
            .collect();
        let velo = velodyne_poses(&cams, &v).unwrap();
        assert!(
            (velo[2].translation.vector - Vector3::new(2.0, 0.0, 0.0)).norm() < 1e-12,
            "{}",
            velo[2]
        );
        assert!(velo[2].rotation.angle() < 1e-12);
        assert!(velodyne_poses(&cams, &Matrix4::zeros()).is_none());
    }

    #[test]
    fn real_tracking_poses_drive_forward_on_the_ground() {
        let Some(data) = shared_data_dir("poses::real_tracking_poses_drive_forward_on_the_ground")
        else {
            return;
        };
        let root = data.join("kitti-tracking-0000-first40/training");
        let cams = read_pose_matrices(&root.join("poses/0000.txt")).unwrap();
        assert_eq!(cams.len(), 40);
        let calib = read_tracking_calib(&root.join("calib/0000.txt")).unwrap();
        let velo = velodyne_poses(&cams, &calib.velo_to_rect_cam()).unwrap();
        assert!(velo[0].translation.vector.norm() < 1e-9);
        let last = velo[39].translation.vector;
        // Sequence 0000 drives slowly forward (~13 m in 4 s) bending left, on flat ground.
        assert!(
            last.x > 5.0 && last.y.abs() < 0.5 * last.x && last.z.abs() < 0.05 * last.x,
            "{last}"
        );
        assert!(
            velo.windows(2)
                .all(|w| w[1].translation.x >= w[0].translation.x - 0.02)
        );
    }

    #[test]
    fn bad_pose_lines_are_errors() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("00.txt");
        std::fs::write(&path, "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n").unwrap();
        assert!(matches!(
            read_poses(&path).unwrap_err(),
            DatasetError::Parse { line: 2, .. }
        ));
        std::fs::write(&path, "1 0 0 0 0 1 0 0 0 0 1 q\n").unwrap();
        assert!(
            read_poses(&path)
                .unwrap_err()
                .to_string()
                .contains("00.txt:1: pose value 12")
        );
    }
}
