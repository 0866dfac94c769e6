//! Where something is on the ground at a time: a path driven with a speed profile.

use nalgebra::Vector2;

use crate::path::{Path, Pose2};
use crate::speed::SpeedProfile;

/// Planar motion at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanarState {
    /// Position and heading.
    pub pose: Pose2,
    /// Speed along the path (m/s, never negative).
    pub speed: f64,
    /// Longitudinal acceleration (m/s²).
    pub accel: f64,
    /// Curvature of the path here (1/m): yaw rate = curvature × speed.
    pub curvature: f64,
    /// Arc length along the path.
    pub distance: f64,
}

impl PlanarState {
    /// Velocity over ground (m/s, world frame).
    pub fn velocity(&self) -> Vector2<f64> {
        self.pose.forward() * self.speed
    }
}

/// A path driven with a speed profile, starting `start_s` metres into the path at time 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    /// The path followed.
    pub path: Path,
    /// Speed over time.
    pub speed: SpeedProfile,
    /// Arc length on the path at time 0.
    pub start_s: f64,
}

impl Trajectory {
    /// Drives `path` from its start with `speed`.
    pub fn new(path: Path, speed: SpeedProfile) -> Self {
        Self {
            path,
            speed,
            start_s: 0.0,
        }
    }

    /// Standing still at `pose`.
    pub fn parked(pose: Pose2) -> Self {
        Self::new(Path::line(pose, 1.0), SpeedProfile::constant(0.0))
    }

    /// The same, starting `s` metres into the path at time 0.
    pub fn starting_at(mut self, s: f64) -> Self {
        self.start_s = s;
        self
    }

    /// The motion at time `t` (seconds since the drive's start).
    pub fn state(&self, t: f64) -> PlanarState {
        let p = self.speed.at(t);
        let distance = self.start_s + p.s;
        let point = self.path.sample(distance);
        PlanarState {
            pose: point.pose,
            speed: p.v,
            accel: p.a,
            curvature: point.curvature,
            distance,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn velocity_is_the_derivative_of_position() {
        let path = Path::from(Pose2::new(0.0, 0.0, 0.2))
            .line(10.0)
            .arc(20.0, 1.0)
            .build();
        let traj = Trajectory::new(path, SpeedProfile::starting(5.0).to(9.0, 2.0).build())
            .starting_at(3.0);
        for i in 0..30 {
            let t = 0.05 + i as f64 * 0.2;
            let h = 1e-5;
            let d = (traj.state(t + h).pose.position - traj.state(t - h).pose.position) / (2.0 * h);
            assert!((d - traj.state(t).velocity()).norm() < 1e-6, "t {t}");
        }
        assert_eq!(traj.state(0.0).distance, 3.0);
    }
}
