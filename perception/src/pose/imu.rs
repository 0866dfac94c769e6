//! The inertial part of an OXTS packet.

use nalgebra::Vector3;

use crate::oxts::Oxts;

/// One IMU sample in the IMU frame (x forward, y left, z up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ImuSample {
    /// Specific force (acceleration minus gravity, so about +9.81 on z at rest), m/s².
    pub accel: Vector3<f64>,
    /// Angular rate, rad/s.
    pub gyro: Vector3<f64>,
}

impl ImuSample {
    /// The packet's `ax, ay, az` and `wx, wy, wz`, or `None` when any is NaN or infinite.
    pub fn from_oxts(oxts: &Oxts) -> Option<Self> {
        let accel = Vector3::new(oxts.ax, oxts.ay, oxts.az);
        let gyro = Vector3::new(oxts.wx, oxts.wy, oxts.wz);
        let finite = accel.iter().chain(gyro.iter()).all(|v| v.is_finite());
        finite.then_some(Self { accel, gyro })
    }
}
