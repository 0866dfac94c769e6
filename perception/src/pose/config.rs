//! Tuning of the ego-pose filter: noise densities, GPS validity rules and gates.

use serde::{Deserialize, Serialize};

/// Every tunable of the ego-pose filter, with defaults fit for a KITTI-like car: a fibre/MEMS
/// IMU sampled once per scan (10 Hz) and a GPS with about 0.5 m noise.
///
/// Process noise is given as continuous-time densities: over a step of `dt` seconds a density
/// `q` adds a variance of `q² · dt`. A sample noise of σ at sampling period `dt` corresponds to a
/// density of `σ · √dt`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct PoseConfig {
    /// Magnitude of gravity in m/s². Default 9.81.
    pub gravity: f64,
    /// Accelerometer white noise, m/s²/√Hz. It also absorbs what sampling the IMU only once per
    /// scan misses of the car's jerk. Default 0.04 (0.13 m/s² per 10 Hz sample).
    pub accel_noise_density: f64,
    /// Gyroscope white noise, rad/s/√Hz. Default 0.001 (0.003 rad/s per 10 Hz sample).
    pub gyro_noise_density: f64,
    /// Accelerometer bias random walk, m/s²/√s. Default 0.002.
    pub accel_bias_walk: f64,
    /// Gyroscope bias random walk, rad/s/√s. Default 2e-5.
    pub gyro_bias_walk: f64,

    /// Initial standard deviation of the velocity when the first packet carries no usable GPS
    /// velocity, m/s. Default 2.0.
    pub initial_velocity_sigma: f64,
    /// Initial standard deviation of roll and pitch, rad. Default 0.02.
    pub initial_roll_pitch_sigma: f64,
    /// Initial standard deviation of yaw (taken from the first packet), rad. Default 0.01.
    pub initial_yaw_sigma: f64,
    /// Initial standard deviation of each accelerometer bias, m/s². Default 0.3.
    pub initial_accel_bias_sigma: f64,
    /// Initial standard deviation of each gyroscope bias, rad/s. Default 0.003 (0.17°/s).
    pub initial_gyro_bias_sigma: f64,

    /// Smallest standard deviation assumed for a GPS position, per axis, in metres: a packet's
    /// `pos_accuracy` is used when larger. Default 0.5.
    pub gps_position_sigma: f64,
    /// Vertical GPS standard deviation as a multiple of the horizontal one (`pos_accuracy` is
    /// KITTI's north/east accuracy; satellite geometry makes height worse). Default 1.6.
    pub gps_vertical_sigma_ratio: f64,
    /// Smallest standard deviation assumed for a GPS velocity, per axis, in m/s: a packet's
    /// `vel_accuracy` is used when larger. Default 0.05.
    pub gps_velocity_sigma: f64,
    /// A fix whose `pos_accuracy` exceeds this (metres) is a dropout. Default 5.0.
    pub max_pos_accuracy: f64,
    /// A velocity whose `vel_accuracy` exceeds this (m/s) is not used. Default 2.0.
    pub max_vel_accuracy: f64,
    /// A fix from fewer satellites (`numsats`) is a dropout. Default 4.
    pub min_numsats: i32,
    /// `navstat` values of a usable fix; any other is a dropout. Default `[4]` (OXTS "locked").
    pub good_navstat: Vec<i32>,

    /// Standard deviation of the non-holonomic pseudo-measurement (a car moves neither sideways
    /// nor vertically in its own frame), m/s; 0 turns it off. It makes yaw observable at
    /// constant speed. It also absorbs side-slip and the IMU's lever arm to the rear axle in
    /// turns. Default 0.1.
    pub nonholonomic_sigma: f64,
    /// Standard deviation of the packet's roll and pitch used as a measurement, rad; 0 turns it
    /// off. With a 10 Hz IMU the filter cannot tell a small roll or pitch error from an
    /// accelerometer bias until the car turns, and drifting between the two tilts far objects
    /// by tens of centimetres; the OXTS unit's own gravity-referenced tilt (0.03° class on
    /// KITTI's RT3003) anchors it. Default 0.005 (0.3°).
    pub packet_roll_pitch_sigma: f64,
    /// Standard deviation of the packet's yaw used as a measurement, rad; 0 turns it off. The
    /// gyroscope, GPS velocity and the non-holonomic constraint make yaw observable only while
    /// moving, and only to about σ_velocity / speed per fix: slowly, the packet's yaw (the OXTS
    /// unit's own heading, 0.1° class on KITTI) keeps it from wandering at low speed, standing
    /// still and through outages. Default 0.01 (0.6°): a loose anchor, the gyroscope still
    /// carries yaw from frame to frame.
    pub packet_yaw_sigma: f64,
    /// Standard deviation, per axis, of the packet's attitude change between two packets, rad;
    /// 0 turns it off. The gyroscope is sampled once per scan, so a rate that changes abruptly
    /// between two samples leaves its integral uncertain; there the packet's attitude change
    /// (integrated by the unit at its internal rate) is weighted in. Where rates change
    /// smoothly it has no effect. Default 0.003 (0.17°).
    pub packet_attitude_increment_sigma: f64,

    /// Mahalanobis gate (squared) on the 3-D GPS position innovation: a larger value rejects the
    /// fix as a jump. Default 16.27 (χ² with 3 degrees of freedom at 99.9 %).
    pub position_gate: f64,
    /// Mahalanobis gate (squared) on the 3-D GPS velocity innovation. Default 16.27.
    pub velocity_gate: f64,
    /// Mahalanobis gate (squared) on the packet-attitude innovation. Default 16.27.
    pub attitude_gate: f64,
    /// After this many consecutive gated-out fixes of one kind the filter stops trusting itself
    /// and re-anchors that part of its state on the measurement (a real, lasting shift).
    /// Default 30 (3 s at 10 Hz).
    pub max_consecutive_rejections: u32,

    /// Fastest the odometry position may move away from where the IMU carried it, to follow
    /// the GPS-corrected world position, m/s; 0 makes the odometry frame the world frame.
    /// Static objects appear to move at most this fast in the odometry frame the tracker
    /// works in; see [`PoseEstimator::output_offset`]. Default 0.1 (1 cm per 10 Hz frame).
    ///
    /// [`PoseEstimator::output_offset`]: super::PoseEstimator::output_offset
    pub max_output_correction_speed: f64,

    /// A gap between packets longer than this (seconds) re-initialises the filter from the next
    /// usable fix instead of predicting through it. Default 1.0.
    pub max_prediction_gap: f64,
}

impl Default for PoseConfig {
    fn default() -> Self {
        Self {
            gravity: 9.81,
            accel_noise_density: 0.04,
            gyro_noise_density: 0.001,
            accel_bias_walk: 0.002,
            gyro_bias_walk: 2e-5,
            initial_velocity_sigma: 2.0,
            initial_roll_pitch_sigma: 0.02,
            initial_yaw_sigma: 0.01,
            initial_accel_bias_sigma: 0.3,
            initial_gyro_bias_sigma: 0.003,
            gps_position_sigma: 0.5,
            gps_vertical_sigma_ratio: 1.6,
            gps_velocity_sigma: 0.05,
            max_pos_accuracy: 5.0,
            max_vel_accuracy: 2.0,
            min_numsats: 4,
            good_navstat: vec![4],
            nonholonomic_sigma: 0.1,
            packet_roll_pitch_sigma: 0.005,
            packet_yaw_sigma: 0.01,
            packet_attitude_increment_sigma: 0.003,
            position_gate: 16.27,
            velocity_gate: 16.27,
            attitude_gate: 16.27,
            max_consecutive_rejections: 30,
            max_output_correction_speed: 0.1,
            max_prediction_gap: 1.0,
        }
    }
}
