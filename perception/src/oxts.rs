//! One KITTI OXTS packet: the GPS/IMU measurement the ego-pose EKF consumes.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::geo::GeoOrigin;

/// The 30 fields of a KITTI OXTS packet, in `oxts/dataformat.txt` order.
///
/// Angles in radians, velocities in m/s, accelerations in m/s², angular rates in rad/s.
/// `f`/`l`/`u` are the vehicle's forward/left/up axes; `n`/`e` north/east.
#[allow(missing_docs)] // the field names are KITTI's own, documented in dataformat.txt
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Oxts {
    pub lat: f64,
    pub lon: f64,
    pub alt: f64,
    pub roll: f64,
    pub pitch: f64,
    pub yaw: f64,
    pub vn: f64,
    pub ve: f64,
    pub vf: f64,
    pub vl: f64,
    pub vu: f64,
    pub ax: f64,
    pub ay: f64,
    pub az: f64,
    pub af: f64,
    pub al: f64,
    pub au: f64,
    pub wx: f64,
    pub wy: f64,
    pub wz: f64,
    pub wf: f64,
    pub wl: f64,
    pub wu: f64,
    pub pos_accuracy: f64,
    pub vel_accuracy: f64,
    pub navstat: i32,
    pub numsats: i32,
    pub posmode: i32,
    pub velmode: i32,
    pub orimode: i32,
}

impl Oxts {
    /// Number of values in a packet.
    pub const FIELDS: usize = 30;

    /// A packet from its 30 values in dataformat order (the last five are integers).
    pub fn from_values(v: &[f64; Self::FIELDS]) -> Self {
        Self {
            lat: v[0],
            lon: v[1],
            alt: v[2],
            roll: v[3],
            pitch: v[4],
            yaw: v[5],
            vn: v[6],
            ve: v[7],
            vf: v[8],
            vl: v[9],
            vu: v[10],
            ax: v[11],
            ay: v[12],
            az: v[13],
            af: v[14],
            al: v[15],
            au: v[16],
            wx: v[17],
            wy: v[18],
            wz: v[19],
            wf: v[20],
            wl: v[21],
            wu: v[22],
            pos_accuracy: v[23],
            vel_accuracy: v[24],
            navstat: v[25] as i32,
            numsats: v[26] as i32,
            posmode: v[27] as i32,
            velmode: v[28] as i32,
            orimode: v[29] as i32,
        }
    }

    /// The 30 values in dataformat order.
    pub fn to_values(&self) -> [f64; Self::FIELDS] {
        [
            self.lat,
            self.lon,
            self.alt,
            self.roll,
            self.pitch,
            self.yaw,
            self.vn,
            self.ve,
            self.vf,
            self.vl,
            self.vu,
            self.ax,
            self.ay,
            self.az,
            self.af,
            self.al,
            self.au,
            self.wx,
            self.wy,
            self.wz,
            self.wf,
            self.wl,
            self.wu,
            self.pos_accuracy,
            self.vel_accuracy,
            f64::from(self.navstat),
            f64::from(self.numsats),
            f64::from(self.posmode),
            f64::from(self.velmode),
            f64::from(self.orimode),
        ]
    }

    /// The IMU's orientation in the world frame: Rz(yaw) · Ry(pitch) · Rx(roll), as KITTI's
    /// devkit composes it.
    pub fn orientation(&self) -> UnitQuaternion<f64> {
        UnitQuaternion::from_euler_angles(self.roll, self.pitch, self.yaw)
    }

    /// The IMU's pose in the world frame of `origin`, taken as the packet says (no filtering).
    pub fn raw_imu_pose(&self, origin: &GeoOrigin) -> Isometry3<f64> {
        let t: Vector3<f64> = origin.to_local(self.lat, self.lon, self.alt);
        Isometry3::from_parts(Translation3::from(t), self.orientation())
    }
}

/// Conversions both ways between the packet and its protobuf message, which have the same
/// 30 fields.
macro_rules! convert_fields {
    ($($field:ident),* $(,)?) => {
        impl From<&trackd_proto::Oxts> for Oxts {
            fn from(o: &trackd_proto::Oxts) -> Self {
                Self { $($field: o.$field),* }
            }
        }

        impl From<&Oxts> for trackd_proto::Oxts {
            fn from(o: &Oxts) -> Self {
                Self { $($field: o.$field),* }
            }
        }
    };
}

convert_fields!(
    lat,
    lon,
    alt,
    roll,
    pitch,
    yaw,
    vn,
    ve,
    vf,
    vl,
    vu,
    ax,
    ay,
    az,
    af,
    al,
    au,
    wx,
    wy,
    wz,
    wf,
    wl,
    wu,
    pos_accuracy,
    vel_accuracy,
    navstat,
    numsats,
    posmode,
    velmode,
    orimode,
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_round_trip() {
        let mut v = [0.0; Oxts::FIELDS];
        for (i, x) in v.iter_mut().enumerate() {
            *x = if i >= 25 { i as f64 } else { i as f64 + 0.5 };
        }
        assert_eq!(Oxts::from_values(&v).to_values(), v);
    }

    #[test]
    fn orientation_is_yaw_about_up() {
        let o = Oxts {
            yaw: std::f64::consts::FRAC_PI_2,
            ..Default::default()
        };
        let forward = o.orientation() * nalgebra::Vector3::x();
        assert!((forward - nalgebra::Vector3::y()).norm() < 1e-12);
    }
}
