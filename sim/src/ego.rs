//! The vehicles' own motion: IMU and Velodyne poses in the world and the IMU's kinematics.
//!
//! A vehicle drives its trajectory on the ground: heading from the path, pitch and roll from
//! the ground's normal under it. The IMU sits above the trajectory point; the Velodyne is
//! where KITTI's calibration puts it relative to the IMU, 1.73 m above level ground.

use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector2, Vector3};

use crate::terrain::Terrain;
use crate::trajectory::Trajectory;

/// Height of the Velodyne above the road, as in KITTI.
pub const VELODYNE_HEIGHT: f64 = 1.73;

/// How the sensors are mounted on a vehicle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mount {
    /// Maps IMU coordinates to Velodyne coordinates (KITTI's `calib_imu_to_velo.txt`).
    pub imu_to_velo: Isometry3<f64>,
    /// Height of the IMU above the ground, chosen so that the Velodyne is
    /// [`VELODYNE_HEIGHT`] above level ground.
    pub imu_height: f64,
}

impl Mount {
    /// A mount with the given IMU-to-Velodyne calibration.
    pub fn new(imu_to_velo: Isometry3<f64>) -> Self {
        let velo_in_imu = imu_to_velo.inverse().translation.vector;
        Self {
            imu_to_velo,
            imu_height: VELODYNE_HEIGHT - velo_in_imu.z,
        }
    }

    /// The mount of KITTI's recording car (its 2011-09-26 calibration).
    pub fn kitti() -> Self {
        Self::new(trackd_dataset::calib::RawCalib::kitti_2011_09_26().imu_to_velo)
    }

    /// The Velodyne's pose in the world given the IMU's.
    pub fn velodyne_pose(&self, imu_pose: &Isometry3<f64>) -> Isometry3<f64> {
        imu_pose * self.imu_to_velo.inverse()
    }
}

/// A vehicle's true motion at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EgoState {
    /// Pose of the IMU (the OXTS unit) in the world.
    pub imu_pose: Isometry3<f64>,
    /// Pose of the Velodyne in the world: maps Velodyne coordinates to world coordinates.
    pub velodyne_pose: Isometry3<f64>,
    /// Velocity of the IMU (m/s, world frame).
    pub velocity: Vector3<f64>,
    /// Acceleration of the IMU (m/s², world frame, gravity not included).
    pub acceleration: Vector3<f64>,
    /// Angular velocity (rad/s, world frame).
    pub angular_velocity: Vector3<f64>,
}

/// The orientation of a vehicle heading `heading` on ground with upward normal `normal`.
pub fn orientation_on(heading: f64, normal: &Vector3<f64>) -> UnitQuaternion<f64> {
    let along = Vector3::new(heading.cos(), heading.sin(), 0.0);
    // Forward: the heading direction tilted into the ground plane.
    let forward = (along - normal * along.dot(normal)).normalize();
    let left = normal.cross(&forward);
    let m = Matrix3::from_columns(&[forward, left, *normal]);
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m))
}

/// The IMU's pose at time `t` for a vehicle driving `trajectory` on `terrain`.
pub fn imu_pose(
    terrain: &Terrain,
    trajectory: &Trajectory,
    mount: &Mount,
    t: f64,
) -> Isometry3<f64> {
    let s = trajectory.state(t);
    let xy: Vector2<f64> = s.pose.position;
    let normal = terrain.normal(xy);
    let ground = Vector3::new(xy.x, xy.y, terrain.height(xy));
    Isometry3::from_parts(
        Translation3::from(ground + normal * mount.imu_height),
        orientation_on(s.pose.heading, &normal),
    )
}

/// The true motion at time `t` (derivatives by central differences of the exact pose).
pub fn ego_state(terrain: &Terrain, trajectory: &Trajectory, mount: &Mount, t: f64) -> EgoState {
    let pose = |t: f64| imu_pose(terrain, trajectory, mount, t);
    let at = pose(t);
    let h = 1e-3;
    let (before, after) = (pose(t - h), pose(t + h));
    let p = |i: &Isometry3<f64>| i.translation.vector;
    let velocity = (p(&after) - p(&before)) / (2.0 * h);
    let h2 = 1e-2;
    let acceleration = (p(&pose(t + h2)) - 2.0 * p(&at) + p(&pose(t - h2))) / (h2 * h2);
    let angular_velocity = (after.rotation * before.rotation.inverse()).scaled_axis() / (2.0 * h);
    EgoState {
        imu_pose: at,
        velodyne_pose: mount.velodyne_pose(&at),
        velocity,
        acceleration,
        angular_velocity,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::{Path, Pose2};
    use crate::speed::SpeedProfile;

    #[test]
    fn velodyne_is_1_73_m_above_level_ground() {
        let mount = Mount::kitti();
        let traj = Trajectory::parked(Pose2::new(3.0, 4.0, 0.5));
        let imu = imu_pose(&Terrain::flat(), &traj, &mount, 0.0);
        let velo = mount.velodyne_pose(&imu);
        assert!(
            (velo.translation.z - VELODYNE_HEIGHT).abs() < 1e-9,
            "{velo}"
        );
        // KITTI's Velodyne is about 0.8 m above and 0.8 m ahead of the IMU.
        let ahead = imu.inverse_transform_point(&velo.translation.vector.into());
        assert!(
            (ahead.x - 0.81).abs() < 0.02 && (ahead.z - 0.8).abs() < 0.02,
            "{ahead}"
        );
    }

    #[test]
    fn turning_at_constant_speed_gives_centripetal_acceleration_and_yaw_rate() {
        let r = 20.0;
        let v = 10.0;
        let traj = Trajectory::new(
            Path::from(Pose2::new(0.0, 0.0, 0.0)).arc(r, 3.0).build(),
            SpeedProfile::constant(v),
        );
        let s = ego_state(&Terrain::flat(), &traj, &Mount::kitti(), 1.0);
        assert!((s.velocity.norm() - v).abs() < 1e-4);
        assert!(
            (s.acceleration.norm() - v * v / r).abs() < 1e-3,
            "{}",
            s.acceleration
        );
        assert!((s.angular_velocity - Vector3::new(0.0, 0.0, v / r)).norm() < 1e-6);
    }

    #[test]
    fn the_vehicle_pitches_up_a_climbing_road() {
        let terrain = Terrain::new(0.0, Vector2::new(0.05, 0.0), Vec::new());
        let traj = Trajectory::parked(Pose2::new(0.0, 0.0, 0.0));
        let pose = imu_pose(&terrain, &traj, &Mount::kitti(), 0.0);
        let (roll, pitch, yaw) = pose.rotation.euler_angles();
        // KITTI: positive pitch = front down, so climbing is negative.
        assert!((pitch + 0.05f64.atan()).abs() < 1e-9, "{pitch}");
        assert!(roll.abs() < 1e-12 && yaw.abs() < 1e-12);
    }
}
