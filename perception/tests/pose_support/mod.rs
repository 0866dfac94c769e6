//! Shared by the pose tests: a synthetic drive with ground truth and noisy OXTS packets, and
//! the metrics the ego-pose requirements are stated in.

#![allow(dead_code)] // each test file uses its own part of this module

use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use trackd_perception::{geo::GeoOrigin, oxts::Oxts};

/// KITTI 2011_09_26 `calib_imu_to_velo.txt`.
pub fn kitti_imu_to_velo() -> Isometry3<f64> {
    let r = Matrix3::new(
        9.999976e-01,
        7.553071e-04,
        -2.035826e-03,
        -7.854027e-04,
        9.998898e-01,
        -1.482298e-02,
        2.024406e-03,
        1.482454e-02,
        9.998881e-01,
    );
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix(&r));
    Isometry3::from_parts(
        Translation3::new(-8.086759e-01, 3.195559e-01, -7.997231e-01),
        rotation,
    )
}

/// Karlsruhe, where KITTI drove.
pub const ORIGIN: GeoOrigin = GeoOrigin::new(49.011_213_954_206, 8.422_885_922_889_3, 112.83);

/// What the GPS of a frame really did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GpsTruth {
    /// A normal noisy fix.
    Clean,
    /// No satellites: numsats 0, navstat 2 (initialising), pos_accuracy 99 m, last fix repeated.
    NoSatellites,
    /// A frozen receiver: the whole fix repeats the previous one, status looks fine.
    Frozen,
    /// Latitude and longitude are NaN.
    NanFix,
    /// The fix is shifted (multipath or a bad solution) while its status looks fine.
    Jump,
}

/// A span of time in which the GPS misbehaves.
#[derive(Clone, Copy, Debug)]
pub struct GpsEvent {
    /// Start and end, seconds.
    pub from: f64,
    pub to: f64,
    /// What happens.
    pub kind: GpsTruth,
    /// Offset of the fix during a jump, metres (east, north, up).
    pub offset: Vector3<f64>,
}

/// The sensors' noise.
#[derive(Clone, Copy, Debug)]
pub struct Noise {
    pub gps_sigma: f64,
    pub velocity_sigma: f64,
    pub attitude_sigma: f64,
    pub yaw_sigma: f64,
    pub accel_sigma: f64,
    pub gyro_sigma: f64,
    pub accel_bias: Vector3<f64>,
    pub gyro_bias: Vector3<f64>,
}

impl Default for Noise {
    /// σ 0.5 m GPS, 0.1 m/s velocity, a bias-y MEMS-grade IMU.
    fn default() -> Self {
        Self {
            gps_sigma: 0.5,
            velocity_sigma: 0.1,
            attitude_sigma: 0.3_f64.to_radians(),
            yaw_sigma: 1.0_f64.to_radians(),
            accel_sigma: 0.1,
            gyro_sigma: 0.003,
            accel_bias: Vector3::new(0.12, -0.15, 0.25),
            gyro_bias: Vector3::new(0.002, -0.003, 0.004),
        }
    }
}

/// One frame of a synthetic drive.
#[derive(Clone, Debug)]
pub struct DriveFrame {
    pub timestamp: f64,
    pub oxts: Oxts,
    pub true_imu: Isometry3<f64>,
    pub true_velo: Isometry3<f64>,
    pub gps: GpsTruth,
}

/// A smooth on/off window: 0 outside [a, b], rising and falling over `ramp` seconds.
fn window(t: f64, a: f64, b: f64, ramp: f64) -> f64 {
    let rise = ((t - a) / ramp).clamp(0.0, 1.0);
    let fall = ((b - t) / ramp).clamp(0.0, 1.0);
    let s = |x: f64| 0.5 - 0.5 * (std::f64::consts::PI * x).cos();
    s(rise) * s(fall)
}

/// Longitudinal acceleration (m/s²) of the synthetic drive at time `t`.
fn acceleration(t: f64) -> f64 {
    1.2 * window(t, 3.0, 9.0, 1.0) - 1.8 * window(t, 25.0, 29.0, 1.0)
        + 0.9 * window(t, 38.0, 46.0, 1.5)
        - 1.0 * window(t, 60.0, 64.0, 1.0)
        + 1.5 * window(t, 66.0, 70.0, 1.0)
        - 0.8 * window(t, 95.0, 101.0, 1.0)
}

/// Yaw rate (rad/s) at time `t` and speed `speed`: turns of given radius.
fn yaw_rate(t: f64, speed: f64) -> f64 {
    let turn = |a: f64, b: f64, radius: f64| window(t, a, b, 1.5) * speed / radius;
    turn(12.0, 20.0, 30.0) - turn(30.0, 36.0, 45.0) + turn(48.0, 53.0, 60.0)
        - turn(53.0, 58.0, 60.0)
        + turn(75.0, 88.0, 80.0)
        - turn(104.0, 112.0, 25.0)
}

/// Road height (m) and slope (dz per metre) at horizontal distance `d`.
fn road(d: f64) -> (f64, f64) {
    (2.5 * (d / 90.0).sin(), 2.5 / 90.0 * (d / 90.0).cos())
}

/// A drive of `seconds` at 10 Hz (timestamps jittered by a few ms) with turns, speed changes
/// and hills; `events` spoil the GPS; `seed` draws the noise.
pub fn drive(seconds: f64, noise: &Noise, events: &[GpsEvent], seed: u64) -> Vec<DriveFrame> {
    let h = 0.002; // integration step
    let steps = (seconds / h).round() as usize + 4;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);

    // Truth on a fine grid: speed along the road, heading, horizontal distance, position.
    let mut speed = 8.0;
    let mut heading: f64 = 0.6;
    let mut distance = 0.0;
    let mut position = Vector3::new(0.0, 0.0, road(0.0).0);
    let mut times = Vec::with_capacity(steps);
    let mut positions = Vec::with_capacity(steps);
    let mut velocities = Vec::with_capacity(steps);
    let mut rotations = Vec::with_capacity(steps);
    for i in 0..steps {
        let t = i as f64 * h;
        let (_, slope) = road(distance);
        let gamma = slope.atan();
        let velocity = Vector3::new(
            speed * gamma.cos() * heading.cos(),
            speed * gamma.cos() * heading.sin(),
            speed * gamma.sin(),
        );
        let rate = yaw_rate(t, speed);
        let lateral = rate * speed;
        let roll = 0.006 * lateral;
        let rotation = UnitQuaternion::from_euler_angles(roll, -gamma, heading);
        times.push(t);
        positions.push(position);
        velocities.push(velocity);
        rotations.push(rotation);
        // advance (velocity trapezoid for position)
        speed += acceleration(t) * h;
        heading += rate * h;
        distance += speed * gamma.cos() * h;
        let (_, slope1) = road(distance);
        let g1 = slope1.atan();
        let v1 = Vector3::new(
            speed * g1.cos() * heading.cos(),
            speed * g1.cos() * heading.sin(),
            speed * g1.sin(),
        );
        position += (velocity + v1) * (0.5 * h);
    }

    let imu_to_velo = kitti_imu_to_velo();
    let velo_to_imu = imu_to_velo.inverse();
    let gravity = Vector3::new(0.0, 0.0, -9.81);
    let gauss = |rng: &mut ChaCha8Rng| -> f64 {
        // Box–Muller
        let u1: f64 = rng.random::<f64>().max(1e-300);
        let u2: f64 = rng.random::<f64>();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    };
    let gauss3 =
        |rng: &mut ChaCha8Rng, s: f64| Vector3::new(gauss(rng) * s, gauss(rng) * s, gauss(rng) * s);

    let frame_every = (0.1 / h).round() as usize;
    let mut frames: Vec<DriveFrame> = Vec::new();
    let mut k = 1;
    while k * frame_every + 3 < steps && (k * frame_every) as f64 * h <= seconds {
        let jitter: i64 = rng.random_range(-2..=2);
        let i = (k * frame_every) as i64 + jitter;
        let i = i as usize;
        let t = times[i];
        let r = rotations[i];
        let p = positions[i];
        let v = velocities[i];
        let a_world = (velocities[i + 1] - velocities[i - 1]) / (2.0 * h);
        let omega = (rotations[i - 1].inverse() * rotations[i + 1]).scaled_axis() / (2.0 * h);
        let specific = r.inverse() * (a_world - gravity);

        let accel = specific + noise.accel_bias + gauss3(&mut rng, noise.accel_sigma);
        let gyro = omega + noise.gyro_bias + gauss3(&mut rng, noise.gyro_sigma);
        let (roll, pitch, yaw) = r.euler_angles();

        let gps = events
            .iter()
            .find(|e| t >= e.from && t < e.to)
            .map_or(GpsTruth::Clean, |e| e.kind);
        let offset = events
            .iter()
            .find(|e| t >= e.from && t < e.to && e.kind == GpsTruth::Jump)
            .map_or(Vector3::zeros(), |e| e.offset);
        let measured = p + offset + gauss3(&mut rng, noise.gps_sigma);
        let measured_v = v + gauss3(&mut rng, noise.velocity_sigma);
        let (lat, lon, alt) = ORIGIN.to_geodetic(&measured);
        let heading_frame = UnitQuaternion::from_euler_angles(0.0, 0.0, yaw);
        let v_flu = heading_frame.inverse() * measured_v;
        let mut oxts = Oxts {
            lat,
            lon,
            alt,
            roll: roll + gauss(&mut rng) * noise.attitude_sigma,
            pitch: pitch + gauss(&mut rng) * noise.attitude_sigma,
            yaw: yaw + gauss(&mut rng) * noise.yaw_sigma,
            vn: measured_v.y,
            ve: measured_v.x,
            vf: v_flu.x,
            vl: v_flu.y,
            vu: measured_v.z,
            ax: accel.x,
            ay: accel.y,
            az: accel.z,
            af: accel.x,
            al: accel.y,
            au: accel.z,
            wx: gyro.x,
            wy: gyro.y,
            wz: gyro.z,
            wf: gyro.x,
            wl: gyro.y,
            wu: gyro.z,
            pos_accuracy: noise.gps_sigma,
            vel_accuracy: noise.velocity_sigma,
            navstat: 4,
            numsats: 9,
            posmode: 4,
            velmode: 4,
            orimode: 4,
        };
        let previous = frames.last().map(|f| f.oxts);
        match gps {
            GpsTruth::Clean | GpsTruth::Jump => {}
            GpsTruth::NoSatellites => {
                if let Some(prev) = previous {
                    (oxts.lat, oxts.lon, oxts.alt) = (prev.lat, prev.lon, prev.alt);
                }
                oxts.numsats = 0;
                oxts.navstat = 2;
                oxts.pos_accuracy = 99.0;
                oxts.vel_accuracy = 99.0;
            }
            GpsTruth::Frozen => {
                if let Some(prev) = previous {
                    (oxts.lat, oxts.lon, oxts.alt) = (prev.lat, prev.lon, prev.alt);
                    (oxts.vn, oxts.ve, oxts.vu) = (prev.vn, prev.ve, prev.vu);
                }
            }
            GpsTruth::NanFix => {
                oxts.lat = f64::NAN;
                oxts.lon = f64::NAN;
            }
        }
        let true_imu = Isometry3::from_parts(Translation3::from(p), r);
        frames.push(DriveFrame {
            timestamp: 1_317_000_000.0 + t,
            oxts,
            true_imu,
            true_velo: true_imu * velo_to_imu,
            gps,
        });
        k += 1;
    }
    frames
}

/// The position error (metres) of a Velodyne pose.
pub fn position_error(estimate: &Isometry3<f64>, truth: &Isometry3<f64>) -> f64 {
    (estimate.translation.vector - truth.translation.vector).norm()
}

/// Root mean square of a list of errors.
pub fn rms(errors: &[f64]) -> f64 {
    (errors.iter().map(|e| e * e).sum::<f64>() / errors.len().max(1) as f64).sqrt()
}

/// How far (metres) a static object `range` metres from the Velodyne appears to move in the
/// world between two consecutive frames, worst over 16 bearings: the object seen from frame
/// `k` is placed with the estimated pose of `k`, and the same object seen from frame `k + 1`
/// with the estimated pose of `k + 1`.
pub fn frame_to_frame_error(
    est: (&Isometry3<f64>, &Isometry3<f64>),
    truth: (&Isometry3<f64>, &Isometry3<f64>),
    range: f64,
) -> f64 {
    let mut worst: f64 = 0.0;
    for b in 0..16 {
        let bearing = b as f64 * std::f64::consts::TAU / 16.0;
        let object = truth.0 * Point3::new(range * bearing.cos(), range * bearing.sin(), 0.0);
        let seen_then = est.0 * (truth.0.inverse() * object);
        let seen_now = est.1 * (truth.1.inverse() * object);
        worst = worst.max((seen_now - seen_then).norm());
    }
    worst
}

/// The yaw error (radians, wrapped) between two poses.
pub fn yaw_error(estimate: &Isometry3<f64>, truth: &Isometry3<f64>) -> f64 {
    let d = estimate.rotation.euler_angles().2 - truth.rotation.euler_angles().2;
    (d + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
}
