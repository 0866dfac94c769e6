//! KITTI calibration files: a raw drive's date folder (`calib_imu_to_velo.txt`,
//! `calib_velo_to_cam.txt`, `calib_cam_to_cam.txt`), a tracking sequence's `calib/<seq>.txt`
//! and an odometry sequence's `calib.txt`. All are `key: numbers` lines.

use std::path::{Path, PathBuf};

use nalgebra::{
    Isometry3, Matrix3, Matrix3x4, Matrix4, Rotation3, Translation3, UnitQuaternion, Vector3,
};

use crate::error::{DatasetError, parse_f64, read_text, write_bytes};
use crate::numfmt::c_exp;

/// File names of a raw drive's calibration, in its date folder.
pub const IMU_TO_VELO_FILE: &str = "calib_imu_to_velo.txt";
/// See [`IMU_TO_VELO_FILE`].
pub const VELO_TO_CAM_FILE: &str = "calib_velo_to_cam.txt";
/// See [`IMU_TO_VELO_FILE`].
pub const CAM_TO_CAM_FILE: &str = "calib_cam_to_cam.txt";

/// One camera of `calib_cam_to_cam.txt` (KITTI's names: `S_0i`, `K_0i`, …).
#[derive(Clone, Debug, PartialEq)]
pub struct CameraCalib {
    /// Image size before rectification (width, height, pixels).
    pub s: [f64; 2],
    /// Intrinsics before rectification.
    pub k: Matrix3<f64>,
    /// Distortion coefficients.
    pub d: [f64; 5],
    /// Rotation from camera 0 to this camera.
    pub r: Matrix3<f64>,
    /// Translation from camera 0 to this camera (metres).
    pub t: Vector3<f64>,
    /// Image size after rectification.
    pub s_rect: [f64; 2],
    /// Rectifying rotation (makes the image planes co-planar).
    pub r_rect: Matrix3<f64>,
    /// Projection matrix after rectification (from the rectified camera-0 frame).
    pub p_rect: Matrix3x4<f64>,
}

/// The four cameras of `calib_cam_to_cam.txt`.
#[derive(Clone, Debug, PartialEq)]
pub struct CamToCam {
    /// Corner distance of the calibration checkerboard (metres).
    pub corner_dist: f64,
    /// Cameras 00 (left grey), 01 (right grey), 02 (left colour), 03 (right colour).
    pub cameras: [CameraCalib; 4],
}

impl CamToCam {
    /// `R_rect_00`: the rectifying rotation of the reference camera.
    pub fn r_rect_00(&self) -> Matrix3<f64> {
        self.cameras[0].r_rect
    }

    /// `P_rect_0i` for camera `i` (0..4).
    pub fn p_rect(&self, i: usize) -> Matrix3x4<f64> {
        self.cameras[i].p_rect
    }
}

/// A raw drive's calibration (the three files of its date folder).
#[derive(Clone, Debug, PartialEq)]
pub struct RawCalib {
    /// Pose of the IMU frame in the Velodyne frame: maps IMU coordinates to Velodyne ones.
    pub imu_to_velo: Isometry3<f64>,
    /// Maps Velodyne coordinates to (unrectified) camera-0 coordinates.
    pub velo_to_cam: Isometry3<f64>,
    /// The cameras.
    pub cam_to_cam: CamToCam,
}

/// What writing results in KITTI's camera frame needs: Velodyne -> rectified camera 0, and the
/// left colour camera's projection (boxes in `label_02` are in image 2).
#[derive(Clone, Debug, PartialEq)]
pub struct RectifiedCamera {
    /// `R0_rect · Tr_velo_to_cam` as a 4x4 homogeneous matrix.
    pub velo_to_rect_cam: Matrix4<f64>,
    /// `P2` (= `P_rect_02`): rectified camera-0 coordinates to image-2 pixels.
    pub p2: Matrix3x4<f64>,
}

impl RectifiedCamera {
    /// A Velodyne point in rectified camera-0 coordinates (x right, y down, z forward).
    pub fn velo_to_cam(&self, p: &Vector3<f64>) -> Vector3<f64> {
        (self.velo_to_rect_cam * p.push(1.0)).xyz()
    }

    /// Inverse of [`Self::velo_to_cam`]. `None` if the matrix is singular.
    pub fn cam_to_velo(&self, p: &Vector3<f64>) -> Option<Vector3<f64>> {
        Some((self.velo_to_rect_cam.try_inverse()? * p.push(1.0)).xyz())
    }

    /// Pixel (u, v) in image 2 of a rectified camera-0 point; `None` behind the camera.
    pub fn project(&self, p_cam: &Vector3<f64>) -> Option<[f64; 2]> {
        let h = self.p2 * p_cam.push(1.0);
        (h.z > 1e-6).then(|| [h.x / h.z, h.y / h.z])
    }
}

impl RawCalib {
    /// The real calibration of KITTI's 2011-09-26 drives (the values of that date folder's
    /// three files), so simulated drives are calibrated like KITTI.
    pub fn kitti_2011_09_26() -> Self {
        let m3 = |v: [f64; 9]| Matrix3::from_row_slice(&v);
        let p = |v: [f64; 12]| Matrix3x4::from_row_slice(&v);
        let camera = |k: [f64; 9],
                      d: [f64; 5],
                      r: [f64; 9],
                      t: [f64; 3],
                      r_rect: [f64; 9],
                      p_rect: [f64; 12]| CameraCalib {
            s: [1.392e3, 5.12e2],
            k: m3(k),
            d,
            r: m3(r),
            t: Vector3::from(t),
            s_rect: [1.242e3, 3.75e2],
            r_rect: m3(r_rect),
            p_rect: p(p_rect),
        };
        Self {
            imu_to_velo: isometry(
                &m3([
                    9.999976e-01,
                    7.553071e-04,
                    -2.035826e-03,
                    -7.854027e-04,
                    9.998898e-01,
                    -1.482298e-02,
                    2.024406e-03,
                    1.482454e-02,
                    9.998881e-01,
                ]),
                &Vector3::new(-8.086759e-01, 3.195559e-01, -7.997231e-01),
            ),
            velo_to_cam: isometry(
                &m3([
                    7.533745e-03,
                    -9.999714e-01,
                    -6.166020e-04,
                    1.480249e-02,
                    7.280733e-04,
                    -9.998902e-01,
                    9.998621e-01,
                    7.523790e-03,
                    1.480755e-02,
                ]),
                &Vector3::new(-4.069766e-03, -7.631618e-02, -2.717806e-01),
            ),
            cam_to_cam: CamToCam {
                corner_dist: 9.95e-02,
                cameras: [
                    camera(
                        [
                            9.842439e+02,
                            0.0,
                            6.9e+02,
                            0.0,
                            9.808141e+02,
                            2.331966e+02,
                            0.0,
                            0.0,
                            1.0,
                        ],
                        [
                            -3.728755e-01,
                            2.037299e-01,
                            2.219027e-03,
                            1.383707e-03,
                            -7.233722e-02,
                        ],
                        [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
                        [2.573699e-16, -1.059758e-16, 1.614870e-16],
                        [
                            9.999239e-01,
                            9.837760e-03,
                            -7.445048e-03,
                            -9.869795e-03,
                            9.999421e-01,
                            -4.278459e-03,
                            7.402527e-03,
                            4.351614e-03,
                            9.999631e-01,
                        ],
                        [
                            7.215377e+02,
                            0.0,
                            6.095593e+02,
                            0.0,
                            0.0,
                            7.215377e+02,
                            1.728540e+02,
                            0.0,
                            0.0,
                            0.0,
                            1.0,
                            0.0,
                        ],
                    ),
                    camera(
                        [
                            9.895267e+02,
                            0.0,
                            7.02e+02,
                            0.0,
                            9.878386e+02,
                            2.455590e+02,
                            0.0,
                            0.0,
                            1.0,
                        ],
                        [
                            -3.644661e-01,
                            1.790019e-01,
                            1.148107e-03,
                            -6.298563e-04,
                            -5.314062e-02,
                        ],
                        [
                            9.993513e-01,
                            1.860866e-02,
                            -3.083487e-02,
                            -1.887662e-02,
                            9.997863e-01,
                            -8.421873e-03,
                            3.067156e-02,
                            8.998467e-03,
                            9.994890e-01,
                        ],
                        [-5.370000e-01, 4.822061e-03, -1.252488e-02],
                        [
                            9.996878e-01,
                            -8.976826e-03,
                            2.331651e-02,
                            8.876121e-03,
                            9.999508e-01,
                            4.418952e-03,
                            -2.335503e-02,
                            -4.210612e-03,
                            9.997184e-01,
                        ],
                        [
                            7.215377e+02,
                            0.0,
                            6.095593e+02,
                            -3.875744e+02,
                            0.0,
                            7.215377e+02,
                            1.728540e+02,
                            0.0,
                            0.0,
                            0.0,
                            1.0,
                            0.0,
                        ],
                    ),
                    camera(
                        [
                            9.597910e+02,
                            0.0,
                            6.960217e+02,
                            0.0,
                            9.569251e+02,
                            2.241806e+02,
                            0.0,
                            0.0,
                            1.0,
                        ],
                        [
                            -3.691481e-01,
                            1.968681e-01,
                            1.353473e-03,
                            5.677587e-04,
                            -6.770705e-02,
                        ],
                        [
                            9.999758e-01,
                            -5.267463e-03,
                            -4.552439e-03,
                            5.251945e-03,
                            9.999804e-01,
                            -3.413835e-03,
                            4.570332e-03,
                            3.389843e-03,
                            9.999838e-01,
                        ],
                        [5.956621e-02, 2.900141e-04, 2.577209e-03],
                        [
                            9.998817e-01,
                            1.511453e-02,
                            -2.841595e-03,
                            -1.511724e-02,
                            9.998853e-01,
                            -9.338510e-04,
                            2.827154e-03,
                            9.766976e-04,
                            9.999955e-01,
                        ],
                        [
                            7.215377e+02,
                            0.0,
                            6.095593e+02,
                            4.485728e+01,
                            0.0,
                            7.215377e+02,
                            1.728540e+02,
                            2.163791e-01,
                            0.0,
                            0.0,
                            1.0,
                            2.745884e-03,
                        ],
                    ),
                    camera(
                        [
                            9.037596e+02,
                            0.0,
                            6.957519e+02,
                            0.0,
                            9.019653e+02,
                            2.242509e+02,
                            0.0,
                            0.0,
                            1.0,
                        ],
                        [
                            -3.639558e-01,
                            1.788651e-01,
                            6.029694e-04,
                            -3.922424e-04,
                            -5.382460e-02,
                        ],
                        [
                            9.995599e-01,
                            1.699522e-02,
                            -2.431313e-02,
                            -1.704422e-02,
                            9.998531e-01,
                            -1.809756e-03,
                            2.427880e-02,
                            2.223358e-03,
                            9.997028e-01,
                        ],
                        [-4.731050e-01, 5.551470e-03, -5.250882e-03],
                        [
                            9.998321e-01,
                            -7.193136e-03,
                            1.685599e-02,
                            7.232804e-03,
                            9.999712e-01,
                            -2.293585e-03,
                            -1.683901e-02,
                            2.415116e-03,
                            9.998553e-01,
                        ],
                        [
                            7.215377e+02,
                            0.0,
                            6.095593e+02,
                            -3.395242e+02,
                            0.0,
                            7.215377e+02,
                            1.728540e+02,
                            2.199936e+00,
                            0.0,
                            0.0,
                            1.0,
                            2.729905e-03,
                        ],
                    ),
                ],
            },
        }
    }

    /// Velodyne -> rectified camera 0 (`R_rect_00 · velo_to_cam`) and `P_rect_02`.
    pub fn rectified_camera(&self) -> RectifiedCamera {
        RectifiedCamera {
            velo_to_rect_cam: homogeneous(&self.cam_to_cam.r_rect_00())
                * self.velo_to_cam.to_homogeneous(),
            p2: self.cam_to_cam.p_rect(2),
        }
    }
}

/// Reads the three calibration files of a raw drive's date folder.
pub fn read_raw_calib(date_dir: &Path) -> Result<RawCalib, DatasetError> {
    let rigid = |file: &str| -> Result<Isometry3<f64>, DatasetError> {
        let kv = KeyValues::read(&date_dir.join(file))?;
        Ok(isometry(
            &Matrix3::from_row_slice(&kv.floats::<9>("R")?),
            &Vector3::from(kv.floats::<3>("T")?),
        ))
    };
    let imu_to_velo = rigid(IMU_TO_VELO_FILE)?;
    let velo_to_cam = rigid(VELO_TO_CAM_FILE)?;
    let kv = KeyValues::read(&date_dir.join(CAM_TO_CAM_FILE))?;
    let camera = |i: usize| -> Result<CameraCalib, DatasetError> {
        let key = |name: &str| format!("{name}_0{i}");
        Ok(CameraCalib {
            s: kv.floats::<2>(&key("S"))?,
            k: Matrix3::from_row_slice(&kv.floats::<9>(&key("K"))?),
            d: kv.floats::<5>(&key("D"))?,
            r: Matrix3::from_row_slice(&kv.floats::<9>(&key("R"))?),
            t: Vector3::from(kv.floats::<3>(&key("T"))?),
            s_rect: kv.floats::<2>(&key("S_rect"))?,
            r_rect: Matrix3::from_row_slice(&kv.floats::<9>(&key("R_rect"))?),
            p_rect: Matrix3x4::from_row_slice(&kv.floats::<12>(&key("P_rect"))?),
        })
    };
    Ok(RawCalib {
        imu_to_velo,
        velo_to_cam,
        cam_to_cam: CamToCam {
            corner_dist: kv.floats::<1>("corner_dist")?[0],
            cameras: [camera(0)?, camera(1)?, camera(2)?, camera(3)?],
        },
    })
}

/// Writes the three calibration files into a raw drive's date folder (which must exist), in
/// KITTI's layout and number format (`%e`, 7 significant digits).
pub fn write_raw_calib(date_dir: &Path, calib: &RawCalib) -> Result<(), DatasetError> {
    const STAMP: &str = "calib_time: written by trackd\n";
    let rigid = |iso: &Isometry3<f64>| {
        let r = iso.rotation.to_rotation_matrix().into_inner();
        format!(
            "R: {}\nT: {}\n",
            row_major(r.transpose().as_slice()),
            row_major(iso.translation.vector.as_slice())
        )
    };
    write_bytes(
        &date_dir.join(IMU_TO_VELO_FILE),
        (STAMP.to_string() + &rigid(&calib.imu_to_velo)).as_bytes(),
    )?;
    let velo = format!(
        "{STAMP}{}delta_f: {}\ndelta_c: {}\n",
        rigid(&calib.velo_to_cam),
        row_major(&[0.0; 2]),
        row_major(&[0.0; 2])
    );
    write_bytes(&date_dir.join(VELO_TO_CAM_FILE), velo.as_bytes())?;
    let mut cams = format!(
        "{STAMP}corner_dist: {}\n",
        c_exp(calib.cam_to_cam.corner_dist, 6)
    );
    for (i, c) in calib.cam_to_cam.cameras.iter().enumerate() {
        let t = |m: &Matrix3<f64>| row_major(m.transpose().as_slice());
        cams += &format!("S_0{i}: {}\n", row_major(&c.s));
        cams += &format!("K_0{i}: {}\n", t(&c.k));
        cams += &format!("D_0{i}: {}\n", row_major(&c.d));
        cams += &format!("R_0{i}: {}\n", t(&c.r));
        cams += &format!("T_0{i}: {}\n", row_major(c.t.as_slice()));
        cams += &format!("S_rect_0{i}: {}\n", row_major(&c.s_rect));
        cams += &format!("R_rect_0{i}: {}\n", t(&c.r_rect));
        cams += &format!(
            "P_rect_0{i}: {}\n",
            row_major(c.p_rect.transpose().as_slice())
        );
    }
    write_bytes(&date_dir.join(CAM_TO_CAM_FILE), cams.as_bytes())
}

/// A tracking sequence's `calib/<seq>.txt` (`P0`..`P3`, `R0_rect`, `Tr_velo_to_cam`,
/// `Tr_imu_to_velo`) or an odometry sequence's `calib.txt` (`P0`..`P3`, `Tr`; its images are
/// rectified already, so `R0_rect` is the identity).
#[derive(Clone, Debug, PartialEq)]
pub struct TrackingCalib {
    /// Projection matrices of cameras 0..3 from rectified camera-0 coordinates.
    pub p: [Matrix3x4<f64>; 4],
    /// Rectifying rotation of camera 0.
    pub r0_rect: Matrix3<f64>,
    /// Velodyne -> camera 0 (3x4, rigid).
    pub tr_velo_to_cam: Matrix3x4<f64>,
    /// IMU -> Velodyne (3x4, rigid), when the file has it (tracking, not odometry).
    pub tr_imu_to_velo: Option<Matrix3x4<f64>>,
}

impl TrackingCalib {
    /// `R0_rect · Tr_velo_to_cam` as a 4x4 homogeneous matrix.
    pub fn velo_to_rect_cam(&self) -> Matrix4<f64> {
        homogeneous(&self.r0_rect) * extend(&self.tr_velo_to_cam)
    }

    /// `P2`: rectified camera-0 coordinates to image-2 pixels.
    pub fn p2(&self) -> Matrix3x4<f64> {
        self.p[2]
    }

    /// IMU -> Velodyne as a rigid transform, when the file has it.
    pub fn imu_to_velo(&self) -> Option<Isometry3<f64>> {
        self.tr_imu_to_velo.map(|m| {
            isometry(
                &m.fixed_view::<3, 3>(0, 0).into_owned(),
                &m.column(3).into_owned(),
            )
        })
    }

    /// What writing camera-frame results needs.
    pub fn rectified_camera(&self) -> RectifiedCamera {
        RectifiedCamera {
            velo_to_rect_cam: self.velo_to_rect_cam(),
            p2: self.p2(),
        }
    }
}

/// Reads a tracking `calib/<seq>.txt` or an odometry `calib.txt`. Accepts KITTI's older key
/// spellings too (`R_rect`, `Tr_velo_cam`, `Tr_imu_velo`).
pub fn read_tracking_calib(path: &Path) -> Result<TrackingCalib, DatasetError> {
    let kv = KeyValues::read(path)?;
    let p = |i: usize| -> Result<Matrix3x4<f64>, DatasetError> {
        Ok(Matrix3x4::from_row_slice(
            &kv.floats::<12>(&format!("P{i}"))?,
        ))
    };
    let first = |keys: &[&'static str]| keys.iter().copied().find(|k| kv.has(k));
    let tr_key = first(&["Tr_velo_to_cam", "Tr_velo_cam", "Tr"])
        .ok_or_else(|| DatasetError::format(path, "no Tr_velo_to_cam (or Tr) line"))?;
    let r0_rect = match first(&["R0_rect", "R_rect"]) {
        Some(key) => Matrix3::from_row_slice(&kv.floats::<9>(key)?),
        None => Matrix3::identity(),
    };
    let tr_imu_to_velo = match first(&["Tr_imu_to_velo", "Tr_imu_velo"]) {
        Some(key) => Some(Matrix3x4::from_row_slice(&kv.floats::<12>(key)?)),
        None => None,
    };
    Ok(TrackingCalib {
        p: [p(0)?, p(1)?, p(2)?, p(3)?],
        r0_rect,
        tr_velo_to_cam: Matrix3x4::from_row_slice(&kv.floats::<12>(tr_key)?),
        tr_imu_to_velo,
    })
}

/// A rigid transform from a rotation matrix (made exactly orthonormal: KITTI prints 7 digits)
/// and a translation.
pub fn isometry(r: &Matrix3<f64>, t: &Vector3<f64>) -> Isometry3<f64> {
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix(r));
    Isometry3::from_parts(Translation3::from(*t), rotation)
}

/// A 3x4 `[R | t]` as a 4x4 homogeneous matrix.
pub fn extend(m: &Matrix3x4<f64>) -> Matrix4<f64> {
    let mut h = Matrix4::identity();
    h.fixed_view_mut::<3, 4>(0, 0).copy_from(m);
    h
}

/// A 3x3 rotation as a 4x4 homogeneous matrix.
fn homogeneous(r: &Matrix3<f64>) -> Matrix4<f64> {
    let mut h = Matrix4::identity();
    h.fixed_view_mut::<3, 3>(0, 0).copy_from(r);
    h
}

/// Values as KITTI writes them: `%e` with 7 significant digits, separated by spaces.
fn row_major(values: &[f64]) -> String {
    values
        .iter()
        .map(|&v| c_exp(v, 6))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The `key: values` lines of a calibration file.
struct KeyValues {
    path: PathBuf,
    /// (key, values text, 1-based line).
    entries: Vec<(String, String, usize)>,
}

impl KeyValues {
    fn read(path: &Path) -> Result<Self, DatasetError> {
        let text = read_text(path)?;
        let mut entries = Vec::new();
        for (i, line) in text.lines().enumerate() {
            if line.trim().is_empty() {
                continue;
            }
            let (key, values) = line
                .split_once(':')
                .ok_or_else(|| DatasetError::parse(path, i + 1, "expected `key: values`"))?;
            entries.push((key.trim().to_string(), values.to_string(), i + 1));
        }
        Ok(Self {
            path: path.to_path_buf(),
            entries,
        })
    }

    fn has(&self, key: &str) -> bool {
        self.entries.iter().any(|(k, _, _)| k == key)
    }

    /// The `N` numbers of `key`.
    fn floats<const N: usize>(&self, key: &str) -> Result<[f64; N], DatasetError> {
        let (_, text, line) = self
            .entries
            .iter()
            .find(|(k, _, _)| k == key)
            .ok_or_else(|| DatasetError::format(&self.path, format!("no {key:?} line")))?;
        let tokens: Vec<&str> = text.split_whitespace().collect();
        if tokens.len() != N {
            return Err(DatasetError::parse(
                &self.path,
                *line,
                format!("{key}: {} values, expected {N}", tokens.len()),
            ));
        }
        let mut out = [0.0; N];
        for (v, token) in out.iter_mut().zip(tokens) {
            *v = parse_f64(&self.path, *line, key, token)?;
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shared_data_dir;

    fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
    }

    fn assert_calib_close(a: &RawCalib, b: &RawCalib, tol: f64) {
        for (x, y) in [
            (&a.imu_to_velo, &b.imu_to_velo),
            (&a.velo_to_cam, &b.velo_to_cam),
        ] {
            assert!(
                close(
                    x.to_homogeneous().as_slice(),
                    y.to_homogeneous().as_slice(),
                    tol
                ),
                "{x} vs {y}"
            );
        }
        assert!((a.cam_to_cam.corner_dist - b.cam_to_cam.corner_dist).abs() <= tol);
        for (x, y) in a.cam_to_cam.cameras.iter().zip(&b.cam_to_cam.cameras) {
            assert!(
                close(&x.s, &y.s, tol)
                    && close(&x.d, &y.d, tol)
                    && close(&x.s_rect, &y.s_rect, tol)
            );
            assert!(
                close(x.k.as_slice(), y.k.as_slice(), tol)
                    && close(x.r.as_slice(), y.r.as_slice(), tol)
            );
            assert!(
                close(x.t.as_slice(), y.t.as_slice(), tol)
                    && close(x.r_rect.as_slice(), y.r_rect.as_slice(), tol)
            );
            assert!(close(x.p_rect.as_slice(), y.p_rect.as_slice(), tol));
        }
    }

    #[test]
    fn write_then_read_round_trips() {
        let dir = tempfile::tempdir().unwrap();
        let calib = RawCalib::kitti_2011_09_26();
        write_raw_calib(dir.path(), &calib).unwrap();
        let back = read_raw_calib(dir.path()).unwrap();
        // 7 printed digits, and the rotation re-orthonormalised.
        assert_calib_close(&calib, &back, 2e-6);
        assert!(calib.imu_to_velo.translation.vector != Vector3::zeros());
    }

    #[test]
    fn constants_are_the_real_2011_09_26_files() {
        let Some(data) = shared_data_dir("calib::constants_are_the_real_2011_09_26_files") else {
            return;
        };
        let date = data.join("kitti-format-samples/raw/2011_09_26");
        let real = read_raw_calib(&date).unwrap();
        assert_eq!(real, RawCalib::kitti_2011_09_26());
        // What we write reads back as the real files, number for number.
        let dir = tempfile::tempdir().unwrap();
        write_raw_calib(dir.path(), &real).unwrap();
        for file in [IMU_TO_VELO_FILE, VELO_TO_CAM_FILE, CAM_TO_CAM_FILE] {
            let ours = KeyValues::read(&dir.path().join(file)).unwrap();
            let theirs = KeyValues::read(&date.join(file)).unwrap();
            let keys: Vec<&String> = theirs.entries.iter().map(|(k, _, _)| k).collect();
            assert_eq!(
                keys,
                ours.entries.iter().map(|(k, _, _)| k).collect::<Vec<_>>(),
                "{file}"
            );
            for ((key, a, _), (_, b, _)) in theirs.entries.iter().zip(&ours.entries) {
                if key == "calib_time" {
                    continue;
                }
                let nums = |s: &str| {
                    s.split_whitespace()
                        .map(|t| t.parse::<f64>().unwrap())
                        .collect::<Vec<_>>()
                };
                assert!(close(&nums(a), &nums(b), 2e-6), "{file} {key}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn tracking_calib_agrees_with_the_raw_calib_of_its_day() {
        let Some(data) =
            shared_data_dir("calib::tracking_calib_agrees_with_the_raw_calib_of_its_day")
        else {
            return;
        };
        let tracking =
            read_tracking_calib(&data.join("kitti-tracking-0000-first40/training/calib/0000.txt"))
                .unwrap();
        let raw = RawCalib::kitti_2011_09_26();
        let (a, b) = (tracking.rectified_camera(), raw.rectified_camera());
        assert!(close(
            a.velo_to_rect_cam.as_slice(),
            b.velo_to_rect_cam.as_slice(),
            2e-6
        ));
        assert_eq!(a.p2, b.p2);
        let imu = tracking.imu_to_velo().unwrap();
        assert!(close(
            imu.to_homogeneous().as_slice(),
            raw.imu_to_velo.to_homogeneous().as_slice(),
            1e-6
        ));
        let sample =
            read_tracking_calib(&data.join("kitti-format-samples/tracking/calib/0001.txt"))
                .unwrap();
        assert_eq!(sample.p2(), tracking.p2());
    }

    #[test]
    fn a_labelled_cyclist_projects_into_its_image_box() {
        let Some(data) = shared_data_dir("calib::a_labelled_cyclist_projects_into_its_image_box")
        else {
            return;
        };
        let calib =
            read_tracking_calib(&data.join("kitti-tracking-0000-first40/training/calib/0000.txt"))
                .unwrap();
        let camera = calib.rectified_camera();
        // label_02/0000.txt frame 0, track 1: Cyclist, bbox 737.6..931.1 x 161.5..374.0,
        // bottom centre (1.640400, 1.675660, 5.776261) in the rectified camera frame; the box is
        // cut by the image bottom (v = 374), the 3D bottom lies just below it.
        let bottom = Vector3::new(1.640400, 1.675660, 5.776261);
        let [u, v] = camera.project(&bottom).unwrap();
        assert!(
            (737.6..931.1).contains(&u) && (330.0..400.0).contains(&v),
            "{u} {v}"
        );
        // In the Velodyne frame it is ahead (x), a little right (y < 0) and on the road (z).
        let velo = camera.cam_to_velo(&bottom).unwrap();
        assert!(
            velo.x > 5.0 && velo.y < 0.0 && (velo.z + 1.73).abs() < 0.3,
            "{velo}"
        );
        assert!((camera.velo_to_cam(&velo) - bottom).norm() < 1e-9);
        assert!(camera.project(&Vector3::new(0.0, 0.0, -5.0)).is_none());
    }

    #[test]
    fn odometry_calib_has_tr_and_no_rectification() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("calib.txt");
        let p = "7.188560000000e+02 0.000000000000e+00 6.071928000000e+02 0.000000000000e+00 0.000000000000e+00 7.188560000000e+02 1.852157000000e+02 0.000000000000e+00 0.000000000000e+00 0.000000000000e+00 1.000000000000e+00 0.000000000000e+00";
        let tr = "4.276802385584e-04 -9.999672484946e-01 -8.084491683471e-03 -1.198459927713e-02 -7.210626507497e-03 8.081198471645e-03 -9.999413164504e-01 -5.403984729748e-02 9.999738645903e-01 4.859485810390e-04 -7.206933692422e-03 -2.921968648686e-01";
        std::fs::write(
            &path,
            format!("P0: {p}\nP1: {p}\nP2: {p}\nP3: {p}\nTr: {tr}\n"),
        )
        .unwrap();
        let calib = read_tracking_calib(&path).unwrap();
        assert_eq!(calib.r0_rect, Matrix3::identity());
        assert!(calib.tr_imu_to_velo.is_none() && calib.imu_to_velo().is_none());
        assert_eq!(calib.velo_to_rect_cam()[(0, 3)], -1.198459927713e-02);
        assert_eq!(calib.p2()[(1, 2)], 1.852157e2);
    }

    #[test]
    fn bad_calib_files_are_typed_errors() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("calib.txt");
        let twelve = "1 0 0 0 0 1 0 0 0 0 1 0";
        std::fs::write(
            &path,
            format!("P0: {twelve}\nP1: {twelve}\nP2: {twelve}\nP3: {twelve}\n"),
        )
        .unwrap();
        assert!(
            read_tracking_calib(&path)
                .unwrap_err()
                .to_string()
                .contains("Tr_velo_to_cam")
        );
        std::fs::write(
            &path,
            format!("P0: {twelve}\nP1: {twelve}\nP2: 1 2 3\nP3: {twelve}\nTr: {twelve}\n"),
        )
        .unwrap();
        let err = read_tracking_calib(&path).unwrap_err();
        assert!(matches!(err, DatasetError::Parse { line: 3, .. }), "{err}");
        std::fs::write(&path, format!("P0: {twelve}\nP1: {twelve}\nP2: {twelve}\nP3: {twelve}\nTr: 1 0 0 x 0 1 0 0 0 0 1 0\n")).unwrap();
        assert!(
            read_tracking_calib(&path)
                .unwrap_err()
                .to_string()
                .contains("calib.txt:5: Tr: \"x\" is not a number")
        );
        std::fs::write(&path, "no colon here\n").unwrap();
        assert!(matches!(
            read_tracking_calib(&path).unwrap_err(),
            DatasetError::Parse { line: 1, .. }
        ));
        assert!(matches!(
            read_raw_calib(dir.path()).unwrap_err(),
            DatasetError::Io { .. }
        ));
    }
}
