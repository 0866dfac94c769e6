//! What a real GPS/IMU reports instead of the truth: noise, biases and GPS outages.
//!
//! GPS positions carry white noise (σ 0.5 m horizontal by default). During an outage (the
//! first 2–6 s into a drive, then every 8–20 s, lasting 1–4 s) the unit holds its last fix and
//! says so: `navstat` 2 instead of 4, `posmode` and `velmode` 0 (no solution) instead of 4,
//! 0–3 satellites instead of 7–12, and a `pos_accuracy` that grows with the distance driven
//! since the fix. Velocities get noisier then. Accelerometers and gyros carry a per-run bias
//! plus white noise; roll, pitch and yaw small noise (yaw also a bias).

use nalgebra::{UnitQuaternion, Vector3};
use rand::Rng;
use trackd_perception::geo::GeoOrigin;
use trackd_perception::oxts::Oxts;

use crate::oxts_truth::{GOOD_FIX, Motion, Status};
use crate::random::{between, gauss};

/// The noise model of the simulated OXTS unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OxtsNoise {
    /// Horizontal GPS position noise (m, per axis).
    pub gps_sigma: f64,
    /// Vertical GPS position noise (m).
    pub gps_sigma_up: f64,
    /// Velocity noise (m/s, per axis) with a fix; three times this without.
    pub velocity_sigma: f64,
    /// Roll and pitch noise (rad).
    pub roll_pitch_sigma: f64,
    /// Yaw noise (rad); the per-run yaw bias has the same spread.
    pub yaw_sigma: f64,
    /// Accelerometer white noise (m/s²).
    pub accel_sigma: f64,
    /// Spread of the per-run accelerometer bias (m/s²).
    pub accel_bias_sigma: f64,
    /// Gyro white noise (rad/s).
    pub gyro_sigma: f64,
    /// Spread of the per-run gyro bias (rad/s).
    pub gyro_bias_sigma: f64,
    /// When the first GPS outage starts (seconds, uniform range); `None`: no outages.
    pub first_outage: Option<(f64, f64)>,
    /// Time between the end of one outage and the start of the next (seconds).
    pub outage_gap: (f64, f64),
    /// Length of an outage (seconds).
    pub outage_length: (f64, f64),
}

impl Default for OxtsNoise {
    fn default() -> Self {
        Self {
            gps_sigma: 0.5,
            gps_sigma_up: 0.8,
            velocity_sigma: 0.05,
            roll_pitch_sigma: 0.0005,
            yaw_sigma: 0.002,
            accel_sigma: 0.05,
            accel_bias_sigma: 0.05,
            gyro_sigma: 0.002,
            gyro_bias_sigma: 0.0005,
            first_outage: Some((2.0, 6.0)),
            outage_gap: (8.0, 20.0),
            outage_length: (1.0, 4.0),
        }
    }
}

impl OxtsNoise {
    /// No noise and no outages: packets report the truth.
    pub fn none() -> Self {
        Self {
            gps_sigma: 0.0,
            gps_sigma_up: 0.0,
            velocity_sigma: 0.0,
            roll_pitch_sigma: 0.0,
            yaw_sigma: 0.0,
            accel_sigma: 0.0,
            accel_bias_sigma: 0.0,
            gyro_sigma: 0.0,
            gyro_bias_sigma: 0.0,
            first_outage: None,
            outage_gap: (0.0, 0.0),
            outage_length: (0.0, 0.0),
        }
    }

    /// For each time, whether the GPS is out then.
    pub fn outages<R: Rng + ?Sized>(&self, times: &[f64], rng: &mut R) -> Vec<bool> {
        let mut out = vec![false; times.len()];
        let Some(first) = self.first_outage else {
            return out;
        };
        let end = times.last().copied().unwrap_or(0.0);
        let mut start = between(rng, first.0, first.1);
        while start <= end {
            let stop = start + between(rng, self.outage_length.0, self.outage_length.1);
            for (o, &t) in out.iter_mut().zip(times) {
                *o |= t >= start && t < stop;
            }
            start = stop + between(rng, self.outage_gap.0, self.outage_gap.1);
        }
        out
    }

    /// The packets a noisy unit reports for the true `motions` at `times`.
    pub fn packets<R: Rng + ?Sized>(
        &self,
        motions: &[Motion],
        times: &[f64],
        origin: &GeoOrigin,
        rng: &mut R,
    ) -> Vec<Oxts> {
        let outages = self.outages(times, rng);
        let vec3 = |rng: &mut R, s: f64| Vector3::new(gauss(rng), gauss(rng), gauss(rng)) * s;
        let accel_bias = vec3(rng, self.accel_bias_sigma);
        let gyro_bias = vec3(rng, self.gyro_bias_sigma);
        let yaw_bias = self.yaw_sigma * gauss(rng);
        let mut numsats = 10i32;
        // The last GPS fix: (time, reported position).
        let mut fix: Option<(f64, Vector3<f64>)> = None;
        let mut packets = Vec::with_capacity(motions.len());
        for ((m, &t), &out) in motions.iter().zip(times).zip(&outages) {
            let (roll, pitch, yaw) = m.orientation.euler_angles();
            let noisy = Motion {
                position: m.position,
                orientation: UnitQuaternion::from_euler_angles(
                    roll + self.roll_pitch_sigma * gauss(rng),
                    pitch + self.roll_pitch_sigma * gauss(rng),
                    yaw + yaw_bias + self.yaw_sigma * gauss(rng),
                ),
                velocity: m.velocity + vec3(rng, self.velocity_sigma * if out { 3.0 } else { 1.0 }),
                specific_force: m.specific_force + accel_bias + vec3(rng, self.accel_sigma),
                angular_rate: m.angular_rate + gyro_bias + vec3(rng, self.gyro_sigma),
            };
            let mut status = GOOD_FIX;
            status.pos_accuracy = self.gps_sigma.max(0.01);
            status.vel_accuracy = self.velocity_sigma.max(0.01);
            let reported = match (out, fix) {
                (true, Some((t_fix, held))) => {
                    let drift = m.velocity.norm() * (t - t_fix);
                    status = Status {
                        navstat: 2,
                        numsats: rng.next_u32() as i32 & 3,
                        posmode: 0,
                        velmode: 0,
                        pos_accuracy: status.pos_accuracy.hypot(drift),
                        vel_accuracy: 3.0 * status.vel_accuracy,
                        ..status
                    };
                    held
                }
                _ => {
                    numsats = (numsats + (rng.next_u32() % 3) as i32 - 1).clamp(7, 12);
                    status.numsats = numsats;
                    let n = Vector3::new(
                        self.gps_sigma * gauss(rng),
                        self.gps_sigma * gauss(rng),
                        self.gps_sigma_up * gauss(rng),
                    );
                    let p = m.position + n;
                    fix = Some((t, p));
                    p
                }
            };
            packets.push(
                Motion {
                    position: reported,
                    ..noisy
                }
                .packet(origin, &status),
            );
        }
        packets
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    const ORIGIN: GeoOrigin = GeoOrigin::new(49.0, 8.4, 115.0);

    fn driving_east(n: usize) -> (Vec<Motion>, Vec<f64>) {
        let times: Vec<f64> = (0..n).map(|i| i as f64 * 0.1).collect();
        let motions = times
            .iter()
            .map(|&t| Motion {
                position: Vector3::new(10.0 * t, 0.0, 1.0),
                orientation: UnitQuaternion::identity(),
                velocity: Vector3::new(10.0, 0.0, 0.0),
                specific_force: Vector3::new(0.0, 0.0, 9.81),
                angular_rate: Vector3::zeros(),
            })
            .collect();
        (motions, times)
    }

    #[test]
    fn gps_noise_has_the_configured_spread() {
        let (motions, times) = driving_east(3000);
        let noise = OxtsNoise {
            first_outage: None,
            ..OxtsNoise::default()
        };
        let packets = noise.packets(&motions, &times, &ORIGIN, &mut ChaCha8Rng::seed_from_u64(1));
        let errs: Vec<f64> = packets
            .iter()
            .zip(&motions)
            .map(|(p, m)| ORIGIN.to_local(p.lat, p.lon, p.alt).y - m.position.y)
            .collect();
        let sd = (errs.iter().map(|e| e * e).sum::<f64>() / errs.len() as f64).sqrt();
        assert!((sd - 0.5).abs() < 0.05, "{sd}");
        assert!(packets.iter().all(|p| p.navstat == 4 && p.numsats >= 7));
    }

    #[test]
    fn outages_hold_the_last_fix_and_say_so() {
        let (motions, times) = driving_east(400);
        let packets = OxtsNoise::default().packets(
            &motions,
            &times,
            &ORIGIN,
            &mut ChaCha8Rng::seed_from_u64(2),
        );
        let bad: Vec<usize> = (0..packets.len())
            .filter(|&i| packets[i].posmode == 0)
            .collect();
        assert!(!bad.is_empty());
        for &i in &bad {
            let p = &packets[i];
            assert!(p.navstat == 2 && p.numsats < 4);
            let prev = &packets[i - 1];
            assert_eq!((p.lat, p.lon), (prev.lat, prev.lon), "held fix at {i}");
            assert!(p.pos_accuracy >= prev.pos_accuracy);
        }
        // The first outage starts 2–6 s in and lasts 1–4 s.
        assert!((20..=60).contains(&bad[0]), "{bad:?}");
        let first_len = bad
            .iter()
            .zip(bad[0]..)
            .take_while(|(a, b)| **a == *b)
            .count();
        assert!((9..=41).contains(&first_len), "{first_len}");
    }

    #[test]
    fn no_noise_reports_the_truth() {
        let (motions, times) = driving_east(50);
        let packets =
            OxtsNoise::none().packets(&motions, &times, &ORIGIN, &mut ChaCha8Rng::seed_from_u64(3));
        for (p, m) in packets.iter().zip(&motions) {
            assert!((p.raw_imu_pose(&ORIGIN).translation.vector - m.position).norm() < 1e-6);
            assert!((p.ve - 10.0).abs() < 1e-12 && (p.az - 9.81).abs() < 1e-12);
        }
    }
}
