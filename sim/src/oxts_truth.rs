//! The exact OXTS packet of a vehicle's true motion, field by field as KITTI defines them
//! (`oxts/dataformat.txt`).

use nalgebra::{UnitQuaternion, Vector3};
use trackd_perception::geo::GeoOrigin;
use trackd_perception::oxts::Oxts;

use crate::ego::EgoState;

/// Standard gravity (m/s²).
pub const GRAVITY: f64 = 9.81;

/// Status fields of a packet with a good GPS fix: navigating, 10 satellites, differential
/// GPS position, velocity and orientation modes.
pub const GOOD_FIX: Status = Status {
    navstat: 4,
    numsats: 10,
    posmode: 4,
    velmode: 4,
    orimode: 4,
    pos_accuracy: 0.5,
    vel_accuracy: 0.05,
};

/// The status and accuracy fields of a packet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Status {
    /// Navigation status.
    pub navstat: i32,
    /// Satellites tracked.
    pub numsats: i32,
    /// GPS position mode.
    pub posmode: i32,
    /// GPS velocity mode.
    pub velmode: i32,
    /// Orientation mode.
    pub orimode: i32,
    /// Position accuracy (m).
    pub pos_accuracy: f64,
    /// Velocity accuracy (m/s).
    pub vel_accuracy: f64,
}

/// The motion quantities a packet is made from, in the world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// IMU position (m).
    pub position: Vector3<f64>,
    /// IMU orientation.
    pub orientation: UnitQuaternion<f64>,
    /// Velocity (m/s).
    pub velocity: Vector3<f64>,
    /// Specific force in the body frame (m/s², what accelerometers read: a − g).
    pub specific_force: Vector3<f64>,
    /// Angular rate in the body frame (rad/s).
    pub angular_rate: Vector3<f64>,
}

impl Motion {
    /// The true motion of a vehicle state.
    pub fn of(state: &EgoState) -> Self {
        let q = state.imu_pose.rotation;
        let f = state.acceleration + Vector3::new(0.0, 0.0, GRAVITY);
        Self {
            position: state.imu_pose.translation.vector,
            orientation: q,
            velocity: state.velocity,
            specific_force: q.inverse() * f,
            angular_rate: q.inverse() * state.angular_velocity,
        }
    }

    /// The packet reporting this motion with the given status.
    pub fn packet(&self, origin: &GeoOrigin, status: &Status) -> Oxts {
        let (lat, lon, alt) = origin.to_geodetic(&self.position);
        let (roll, pitch, yaw) = self.orientation.euler_angles();
        // The level frame: forward/left/up with the heading, not tilted with the vehicle.
        let heading = UnitQuaternion::from_euler_angles(0.0, 0.0, yaw);
        let tilt = heading.inverse() * self.orientation;
        let v = heading.inverse() * self.velocity;
        let a = tilt * self.specific_force;
        let w = tilt * self.angular_rate;
        Oxts {
            lat,
            lon,
            alt,
            roll,
            pitch,
            yaw,
            vn: self.velocity.y,
            ve: self.velocity.x,
            vf: v.x,
            vl: v.y,
            vu: v.z,
            ax: self.specific_force.x,
            ay: self.specific_force.y,
            az: self.specific_force.z,
            af: a.x,
            al: a.y,
            au: a.z,
            wx: self.angular_rate.x,
            wy: self.angular_rate.y,
            wz: self.angular_rate.z,
            wf: w.x,
            wl: w.y,
            wu: w.z,
            pos_accuracy: status.pos_accuracy,
            vel_accuracy: status.vel_accuracy,
            navstat: status.navstat,
            numsats: status.numsats,
            posmode: status.posmode,
            velmode: status.velmode,
            orimode: status.orimode,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ego::{Mount, ego_state};
    use crate::path::{Path, Pose2};
    use crate::speed::SpeedProfile;
    use crate::terrain::Terrain;
    use crate::trajectory::Trajectory;
    use nalgebra::Vector2;

    const ORIGIN: GeoOrigin = GeoOrigin::new(49.0, 8.4, 115.0);

    #[test]
    fn a_packet_s_pose_is_the_imu_pose() {
        let terrain = Terrain::new(0.0, Vector2::new(0.02, -0.03), Vec::new());
        let traj = Trajectory::new(
            Path::from(Pose2::new(10.0, 20.0, 0.7))
                .arc(30.0, 1.0)
                .build(),
            SpeedProfile::constant(8.0),
        );
        let state = ego_state(&terrain, &traj, &Mount::kitti(), 2.0);
        let packet = Motion::of(&state).packet(&ORIGIN, &GOOD_FIX);
        let pose = packet.raw_imu_pose(&ORIGIN);
        assert!((pose.translation.vector - state.imu_pose.translation.vector).norm() < 1e-6);
        assert!(pose.rotation.angle_to(&state.imu_pose.rotation) < 1e-9);
        assert!(((packet.vn.powi(2) + packet.ve.powi(2)).sqrt() - 8.0).abs() < 0.5);
    }

    #[test]
    fn standing_still_on_a_slope_reads_gravity_in_body_and_level_frames() {
        let terrain = Terrain::new(0.0, Vector2::new(0.1, 0.0), Vec::new());
        let traj = Trajectory::parked(Pose2::new(0.0, 0.0, 0.0));
        let state = ego_state(&terrain, &traj, &Mount::kitti(), 0.0);
        let p = Motion::of(&state).packet(&ORIGIN, &GOOD_FIX);
        // Nose up by atan(0.1): the accelerometer's x axis sees −g·sin(pitch).
        assert!(
            (p.ax - GRAVITY * (0.1f64.atan()).sin()).abs() < 1e-3,
            "{}",
            p.ax
        );
        assert!(p.af.abs() < 1e-3 && (p.au - GRAVITY).abs() < 1e-3, "{p:?}");
        assert!(p.vf.abs() < 1e-9 && p.wz.abs() < 1e-9);
    }

    #[test]
    fn turning_shows_in_yaw_rate_and_lateral_acceleration() {
        let traj = Trajectory::new(
            Path::from(Pose2::new(0.0, 0.0, 0.0)).arc(25.0, 2.0).build(),
            SpeedProfile::constant(10.0),
        );
        let state = ego_state(&Terrain::flat(), &traj, &Mount::kitti(), 1.0);
        let p = Motion::of(&state).packet(&ORIGIN, &GOOD_FIX);
        assert!((p.wu - 0.4).abs() < 1e-6 && (p.wz - 0.4).abs() < 1e-6);
        assert!((p.al - 4.0).abs() < 1e-3 && (p.ay - 4.0).abs() < 1e-3);
        assert!((p.vf - 10.0).abs() < 1e-4 && p.vl.abs() < 1e-4);
    }
}
