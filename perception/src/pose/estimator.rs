//! [`PoseEstimator`]: OXTS packets (or given poses) in, the Velodyne's pose in the world out.

use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3};

use super::{
    config::PoseConfig,
    ekf::{Correction, ErrorStateEkf, Measurement},
    error::PoseError,
    gps,
    imu::ImuSample,
    measurement,
    report::{FixOutcome, StepReport},
    slew::Slew,
    state::{ACCEL_BIAS, ATTITUDE, Covariance, GYRO_BIAS, NavState, POSITION, VELOCITY},
};
use crate::{geo::GeoOrigin, oxts::Oxts};

/// The ego-pose filter of one vehicle.
///
/// Feed it every scan's OXTS packet in timestamp order with [`update`](Self::update); it
/// returns the pose of the Velodyne frame in the fleet's world frame, and
/// [`odometry`](Self::odometry) the same pose in the vehicle's odometry frame. A refused
/// update (an `Err`) leaves the estimator as it was.
///
/// The two frames (the `map` and `odom` frames of a localisation stack): the world pose is the
/// filter's best estimate, and GPS corrections move it — by a metre or more while the filter
/// converges from its first fix or after an outage. Every static object would move with it.
/// The odometry pose moves as the IMU carried the vehicle and follows the world pose at most
/// [`PoseConfig::max_output_correction_speed`]: objects stay still in it, and
/// [`world_from_odometry`](Self::world_from_odometry) places them in the world.
#[derive(Clone, Debug)]
pub struct PoseEstimator {
    cfg: PoseConfig,
    origin: Option<GeoOrigin>,
    velo_to_imu: Isometry3<f64>,
    filter: Option<Filter>,
    last_timestamp: Option<f64>,
    pose: Option<Isometry3<f64>>,
    odometry: Option<Isometry3<f64>>,
    report: StepReport,
}

/// The running filter and what it remembers of the previous packet.
#[derive(Clone, Debug)]
struct Filter {
    ekf: ErrorStateEkf,
    timestamp: f64,
    packet: Oxts,
    imu: ImuSample,
    position_rejections: u32,
    velocity_rejections: u32,
    slew: Slew,
}

impl PoseEstimator {
    /// A new estimator. `origin` is the fleet's world origin; `None` takes the first usable
    /// GPS fix as the origin. `imu_to_velo` is KITTI's `calib_imu_to_velo` (it maps IMU
    /// coordinates to Velodyne coordinates).
    pub fn new(cfg: PoseConfig, origin: Option<GeoOrigin>, imu_to_velo: Isometry3<f64>) -> Self {
        Self {
            cfg,
            origin,
            velo_to_imu: imu_to_velo.inverse(),
            filter: None,
            last_timestamp: None,
            pose: None,
            odometry: None,
            report: StepReport::default(),
        }
    }

    /// Fuses one OXTS packet taken at `timestamp` (seconds, the scan's) and returns the
    /// Velodyne's pose in the world frame: the IMU pose · inv(`imu_to_velo`). The pose in the
    /// odometry frame is [`odometry`](Self::odometry).
    ///
    /// The first packet with a usable fix and finite attitude initialises the filter; until
    /// then this returns [`PoseError::AwaitingFix`] or [`PoseError::AwaitingAttitude`]. After
    /// a gap longer than [`PoseConfig::max_prediction_gap`] the filter restarts from the
    /// packet if it can, else predicts through the gap.
    pub fn update(&mut self, timestamp: f64, oxts: &Oxts) -> Result<Isometry3<f64>, PoseError> {
        self.check_timestamp(timestamp)?;
        let restart = match &self.filter {
            None => true,
            Some(f) => timestamp - f.timestamp > self.cfg.max_prediction_gap,
        };
        let report = if restart {
            match (self.initialise(timestamp, oxts), self.filter.is_some()) {
                (Ok(report), _) => report,
                (Err(e), false) => return Err(e),
                (Err(_), true) => self.step(timestamp, oxts),
            }
        } else {
            self.step(timestamp, oxts)
        };
        self.report = report;
        self.last_timestamp = Some(timestamp);
        let pose = self
            .filter
            .as_ref()
            .map(|f| f.ekf.state.pose() * self.velo_to_imu);
        self.pose = pose;
        self.odometry = self.filter.as_ref().zip(pose).map(|(f, mut p)| {
            p.translation.vector += f.slew.offset();
            p
        });
        // the filter exists here: either it ran a step or it was just initialised
        pose.ok_or(PoseError::AwaitingAttitude)
    }

    /// Passes a given Velodyne pose (e.g. from KITTI odometry `poses`) through unchanged:
    /// there is nothing to filter. Only the timestamp order is checked; the OXTS filter, if
    /// any, is untouched.
    pub fn update_given(
        &mut self,
        timestamp: f64,
        velo_pose: Isometry3<f64>,
    ) -> Result<Isometry3<f64>, PoseError> {
        self.check_timestamp(timestamp)?;
        let finite = velo_pose.translation.vector.iter().all(|v| v.is_finite())
            && velo_pose.rotation.coords.iter().all(|v| v.is_finite());
        if !finite {
            return Err(PoseError::InvalidPose);
        }
        self.last_timestamp = Some(timestamp);
        self.pose = Some(velo_pose);
        self.odometry = Some(velo_pose);
        self.report = StepReport::default();
        Ok(velo_pose)
    }

    /// The Velodyne pose in the world frame returned by the last successful update.
    pub fn pose(&self) -> Option<Isometry3<f64>> {
        self.pose
    }

    /// The Velodyne pose of the last successful update in the odometry frame: continuous,
    /// moved by GPS corrections at most [`PoseConfig::max_output_correction_speed`].
    pub fn odometry(&self) -> Option<Isometry3<f64>> {
        self.odometry
    }

    /// How far the odometry position is from the world one (metres): GPS corrections not yet
    /// followed. `None` before initialisation.
    pub fn output_offset(&self) -> Option<Vector3<f64>> {
        self.filter.as_ref().map(|f| f.slew.offset())
    }

    /// The transform from the odometry frame to the world frame (a translation by minus the
    /// [`output_offset`](Self::output_offset)); the identity before initialisation.
    pub fn world_from_odometry(&self) -> Translation3<f64> {
        Translation3::from(-self.output_offset().unwrap_or_default())
    }

    /// The filtered IMU pose in the world frame (`None` before initialisation).
    pub fn imu_pose(&self) -> Option<Isometry3<f64>> {
        self.filter.as_ref().map(|f| f.ekf.state.pose())
    }

    /// The filtered IMU velocity in the world frame, m/s.
    pub fn velocity(&self) -> Option<Vector3<f64>> {
        self.filter.as_ref().map(|f| f.ekf.state.velocity)
    }

    /// The estimated accelerometer bias (IMU frame, m/s²).
    pub fn accel_bias(&self) -> Option<Vector3<f64>> {
        self.filter.as_ref().map(|f| f.ekf.state.accel_bias)
    }

    /// The estimated gyroscope bias (IMU frame, rad/s).
    pub fn gyro_bias(&self) -> Option<Vector3<f64>> {
        self.filter.as_ref().map(|f| f.ekf.state.gyro_bias)
    }

    /// The full error-state covariance; its layout is given by
    /// [`POSITION`](super::POSITION), [`VELOCITY`](super::VELOCITY), … in [`super`].
    pub fn covariance(&self) -> Option<&Covariance> {
        self.filter.as_ref().map(|f| &f.ekf.covariance)
    }

    /// Covariance of the IMU position (world frame, m²).
    pub fn position_covariance(&self) -> Option<Matrix3<f64>> {
        self.block(POSITION)
    }

    /// Covariance of the attitude error (IMU frame, rad²); entry (2, 2) is about the yaw
    /// variance.
    pub fn attitude_covariance(&self) -> Option<Matrix3<f64>> {
        self.block(ATTITUDE)
    }

    /// What the last successful update did with the GPS.
    pub fn last_step(&self) -> &StepReport {
        &self.report
    }

    /// Whether the last update used the GPS position.
    pub fn gps_used(&self) -> bool {
        self.report.position.used()
    }

    /// Whether the last update rejected the GPS position as a jump.
    pub fn gps_rejected(&self) -> bool {
        matches!(self.report.position, FixOutcome::Rejected { .. })
    }

    /// The world origin: the one given, or the first fix's once initialised.
    pub fn origin(&self) -> Option<GeoOrigin> {
        self.origin
    }

    /// The configuration in use.
    pub fn config(&self) -> &PoseConfig {
        &self.cfg
    }

    fn block(&self, first: usize) -> Option<Matrix3<f64>> {
        self.covariance()
            .map(|p| p.fixed_view::<3, 3>(first, first).into_owned())
    }

    fn check_timestamp(&self, timestamp: f64) -> Result<(), PoseError> {
        if !timestamp.is_finite() {
            return Err(PoseError::InvalidTimestamp(timestamp));
        }
        match self.last_timestamp {
            Some(previous) if timestamp == previous => {
                Err(PoseError::DuplicateTimestamp(timestamp))
            }
            Some(previous) if timestamp < previous => Err(PoseError::OutOfOrder {
                previous,
                current: timestamp,
            }),
            _ => Ok(()),
        }
    }

    /// Starts the filter from one packet: position from its fix, velocity from its GPS
    /// velocity (or zero, uncertain), attitude from its roll/pitch/yaw, zero biases.
    fn initialise(&mut self, timestamp: f64, oxts: &Oxts) -> Result<StepReport, PoseError> {
        let cfg = &self.cfg;
        let attitude = [oxts.roll, oxts.pitch, oxts.yaw];
        if !attitude.iter().all(|a| a.is_finite()) {
            return Err(PoseError::AwaitingAttitude);
        }
        let origin = self
            .origin
            .unwrap_or(GeoOrigin::new(oxts.lat, oxts.lon, oxts.alt));
        let fix = gps::position_fix(oxts, None, &origin, cfg).map_err(PoseError::AwaitingFix)?;
        let (velocity, velocity_sigma, velocity_outcome) = match gps::velocity_fix(oxts, None, cfg)
        {
            Ok(v) => (v.velocity, v.sigma, FixOutcome::Initialised),
            Err(d) => (
                Vector3::zeros(),
                cfg.initial_velocity_sigma,
                FixOutcome::Dropout(d),
            ),
        };
        let orientation = oxts.orientation();
        let imu = ImuSample::from_oxts(oxts).unwrap_or(ImuSample {
            accel: orientation.inverse() * Vector3::new(0.0, 0.0, cfg.gravity),
            gyro: Vector3::zeros(),
        });

        let mut covariance = Covariance::zeros();
        let mut set = |first: usize, sigmas: [f64; 3]| {
            for (i, s) in sigmas.iter().enumerate() {
                covariance[(first + i, first + i)] = s * s;
            }
        };
        set(POSITION, [fix.sigma, fix.sigma, fix.sigma_up]);
        set(VELOCITY, [velocity_sigma; 3]);
        let (rp, y) = (cfg.initial_roll_pitch_sigma, cfg.initial_yaw_sigma);
        set(ATTITUDE, [rp, rp, y]);
        set(ACCEL_BIAS, [cfg.initial_accel_bias_sigma; 3]);
        set(GYRO_BIAS, [cfg.initial_gyro_bias_sigma; 3]);

        let ekf = ErrorStateEkf {
            state: NavState {
                position: fix.position,
                velocity,
                orientation,
                accel_bias: Vector3::zeros(),
                gyro_bias: Vector3::zeros(),
            },
            covariance,
        };
        self.origin = Some(origin);
        self.filter = Some(Filter {
            ekf,
            timestamp,
            packet: *oxts,
            imu,
            position_rejections: 0,
            velocity_rejections: 0,
            slew: Slew::default(),
        });
        Ok(StepReport {
            position: FixOutcome::Initialised,
            velocity: velocity_outcome,
            initialised: true,
            imu_held: ImuSample::from_oxts(oxts).is_none(),
        })
    }

    /// One predict–correct cycle of a running filter.
    fn step(&mut self, timestamp: f64, oxts: &Oxts) -> StepReport {
        let cfg = &self.cfg;
        let (Some(f), Some(origin)) = (self.filter.as_mut(), self.origin.as_ref()) else {
            return StepReport::default();
        };
        let sample = ImuSample::from_oxts(oxts);
        let imu = sample.unwrap_or(f.imu);
        let attitudes = [&f.packet, oxts].map(|p| {
            [p.roll, p.pitch, p.yaw]
                .iter()
                .all(|a| a.is_finite())
                .then(|| p.orientation())
        });
        let increment = match attitudes {
            [Some(before), Some(after)] => Some(before.inverse() * after),
            _ => None,
        };
        let dt = timestamp - f.timestamp;
        f.ekf.predict(dt, &f.imu, &imu, increment.as_ref(), cfg);
        let predicted = f.ekf.state.position;

        let velocity = match gps::velocity_fix(oxts, Some(&f.packet), cfg) {
            Err(d) => FixOutcome::Dropout(d),
            Ok(fix) => {
                let m = measurement::velocity(&f.ekf.state, &fix);
                gated(&mut f.ekf, &m, cfg, VELOCITY, &mut f.velocity_rejections)
            }
        };
        let position = match gps::position_fix(oxts, Some(&f.packet), origin, cfg) {
            Err(d) => FixOutcome::Dropout(d),
            Ok(fix) => {
                let m = measurement::position(&f.ekf.state, &fix);
                gated(&mut f.ekf, &m, cfg, POSITION, &mut f.position_rejections)
            }
        };
        if cfg.nonholonomic_sigma > 0.0 {
            let m = measurement::nonholonomic(&f.ekf.state, cfg.nonholonomic_sigma);
            f.ekf.correct(&m, f64::INFINITY);
        }
        if [oxts.roll, oxts.pitch, oxts.yaw]
            .iter()
            .all(|a| a.is_finite())
        {
            let measured: UnitQuaternion<f64> = oxts.orientation();
            if cfg.packet_roll_pitch_sigma > 0.0 {
                let m =
                    measurement::roll_pitch(&f.ekf.state, &measured, cfg.packet_roll_pitch_sigma);
                f.ekf.correct(&m, cfg.attitude_gate);
            }
            if cfg.packet_yaw_sigma > 0.0 {
                let m = measurement::yaw(&f.ekf.state, &measured, cfg.packet_yaw_sigma);
                f.ekf.correct(&m, cfg.attitude_gate);
            }
        }

        let correction = f.ekf.state.position - predicted;
        f.slew
            .absorb(&correction, dt, cfg.max_output_correction_speed);
        f.timestamp = timestamp;
        f.packet = *oxts;
        f.imu = imu;
        StepReport {
            position,
            velocity,
            initialised: false,
            imu_held: sample.is_none(),
        }
    }
}

/// Applies a GPS measurement of the 3-block starting at `block` through its gate, counting
/// consecutive rejections; past [`PoseConfig::max_consecutive_rejections`] the block is
/// re-anchored on the measurement.
fn gated(
    ekf: &mut ErrorStateEkf,
    m: &Measurement<3>,
    cfg: &PoseConfig,
    block: usize,
    rejections: &mut u32,
) -> FixOutcome {
    let gate = if block == POSITION {
        cfg.position_gate
    } else {
        cfg.velocity_gate
    };
    match ekf.correct(m, gate) {
        Correction::Applied(nis) => {
            *rejections = 0;
            FixOutcome::Used { nis }
        }
        Correction::Rejected(nis) => {
            *rejections += 1;
            if *rejections <= cfg.max_consecutive_rejections {
                return FixOutcome::Rejected { nis };
            }
            *rejections = 0;
            let sigma = m.noise.diagonal().max().sqrt();
            ekf.forget_block(block, m.residual.norm() + 10.0 * sigma);
            match ekf.correct(m, f64::INFINITY) {
                Correction::Applied(_) => FixOutcome::Reanchored { nis },
                _ => FixOutcome::None,
            }
        }
        Correction::Degenerate => FixOutcome::None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Translation3;

    const ORIGIN: GeoOrigin = GeoOrigin::new(49.0, 8.4, 110.0);

    /// A level car parked at `offset` metres from the origin, facing north.
    fn parked(offset: Vector3<f64>) -> Oxts {
        let (lat, lon, alt) = ORIGIN.to_geodetic(&offset);
        Oxts {
            lat,
            lon,
            alt,
            yaw: std::f64::consts::FRAC_PI_2,
            az: 9.81,
            pos_accuracy: 0.5,
            vel_accuracy: 0.1,
            navstat: 4,
            numsats: 8,
            ..Default::default()
        }
    }

    fn calibration() -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::new(-0.81, 0.32, -0.80),
            UnitQuaternion::from_euler_angles(0.0, 0.0, 0.01),
        )
    }

    #[test]
    fn the_velodyne_pose_is_the_imu_pose_times_the_inverse_calibration() {
        let mut est = PoseEstimator::new(PoseConfig::default(), Some(ORIGIN), calibration());
        let packet = parked(Vector3::new(5.0, 7.0, 1.0));
        let pose = est.update(10.0, &packet).unwrap();
        let imu = packet.raw_imu_pose(&ORIGIN);
        let want = imu * calibration().inverse();
        assert!((pose.translation.vector - want.translation.vector).norm() < 1e-6);
        assert!(pose.rotation.angle_to(&want.rotation) < 1e-9);
        assert_eq!(est.pose(), Some(pose));
        assert!(est.last_step().initialised && est.gps_used());
    }

    #[test]
    fn without_an_origin_the_first_fix_is_the_origin() {
        let mut est = PoseEstimator::new(PoseConfig::default(), None, Isometry3::identity());
        let packet = parked(Vector3::new(300.0, -200.0, 4.0));
        let pose = est.update(0.0, &packet).unwrap();
        assert!(pose.translation.vector.norm() < 1e-9);
        assert_eq!(
            est.origin(),
            Some(GeoOrigin::new(packet.lat, packet.lon, packet.alt))
        );
    }

    #[test]
    fn timestamps_must_increase_and_a_refusal_changes_nothing() {
        let mut est = PoseEstimator::new(PoseConfig::default(), Some(ORIGIN), calibration());
        est.update(1.0, &parked(Vector3::zeros())).unwrap();
        est.update(1.1, &parked(Vector3::new(0.01, 0.0, 0.0)))
            .unwrap();
        let before = (est.pose(), est.covariance().copied(), *est.last_step());
        let next = parked(Vector3::new(0.02, 0.0, 0.0));
        assert_eq!(
            est.update(1.1, &next),
            Err(PoseError::DuplicateTimestamp(1.1))
        );
        assert_eq!(
            est.update(1.05, &next),
            Err(PoseError::OutOfOrder {
                previous: 1.1,
                current: 1.05
            })
        );
        assert_eq!(
            est.update_given(1.0, Isometry3::identity()),
            Err(PoseError::OutOfOrder {
                previous: 1.1,
                current: 1.0
            })
        );
        assert!(
            matches!(est.update(f64::NAN, &next), Err(PoseError::InvalidTimestamp(t)) if t.is_nan())
        );
        assert_eq!(
            before,
            (est.pose(), est.covariance().copied(), *est.last_step())
        );
        assert!(est.update(1.2, &next).is_ok());
    }

    #[test]
    fn it_waits_for_a_usable_first_fix() {
        let mut est = PoseEstimator::new(PoseConfig::default(), None, calibration());
        let no_sats = Oxts {
            numsats: 0,
            ..parked(Vector3::zeros())
        };
        assert_eq!(
            est.update(0.0, &no_sats),
            Err(PoseError::AwaitingFix(gps::Dropout::FewSatellites))
        );
        let nan_yaw = Oxts {
            yaw: f64::NAN,
            ..parked(Vector3::zeros())
        };
        assert_eq!(est.update(0.1, &nan_yaw), Err(PoseError::AwaitingAttitude));
        let all_nan = Oxts::from_values(&[f64::NAN; Oxts::FIELDS]);
        assert!(est.update(0.2, &all_nan).is_err());
        assert!(est.imu_pose().is_none() && est.origin().is_none());
        assert!(est.update(0.3, &parked(Vector3::zeros())).is_ok());
    }

    #[test]
    fn a_nan_packet_mid_drive_is_predicted_through() {
        let mut est = PoseEstimator::new(PoseConfig::default(), Some(ORIGIN), calibration());
        est.update(0.0, &parked(Vector3::zeros())).unwrap();
        let all_nan = Oxts::from_values(&[f64::NAN; Oxts::FIELDS]);
        let pose = est.update(0.1, &all_nan).unwrap();
        assert!(pose.translation.vector.iter().all(|v| v.is_finite()));
        let step = est.last_step();
        assert!(step.imu_held);
        assert_eq!(step.position, FixOutcome::Dropout(gps::Dropout::NonFinite));
        assert!(!est.gps_used() && !est.gps_rejected());
    }

    #[test]
    fn a_long_gap_restarts_from_the_next_fix() {
        let mut est =
            PoseEstimator::new(PoseConfig::default(), Some(ORIGIN), Isometry3::identity());
        est.update(0.0, &parked(Vector3::zeros())).unwrap();
        let far = Vector3::new(100.0, 50.0, 0.0);
        let pose = est.update(30.0, &parked(far)).unwrap();
        assert!(est.last_step().initialised);
        assert!((pose.translation.vector - far).norm() < 1e-6);
    }

    #[test]
    fn given_poses_pass_through() {
        let mut est = PoseEstimator::new(PoseConfig::default(), None, calibration());
        let given = Isometry3::from_parts(
            Translation3::new(1.0, 2.0, 3.0),
            UnitQuaternion::from_euler_angles(0.0, 0.1, 0.2),
        );
        assert_eq!(est.update_given(0.0, given), Ok(given));
        assert_eq!(est.pose(), Some(given));
        assert_eq!(est.last_step().position, FixOutcome::None);
        let mut bad = given;
        bad.translation.vector.x = f64::NAN;
        assert_eq!(est.update_given(0.1, bad), Err(PoseError::InvalidPose));
        assert!(est.imu_pose().is_none());
    }
}
