//! Which GPS fixes of an OXTS packet are usable: the dropout rules.
//!
//! A packet's position is a dropout (not used, the filter predicts through it) when any of:
//! - latitude, longitude or altitude is NaN or infinite ([`Dropout::NonFinite`]);
//! - `pos_accuracy` is NaN or above [`PoseConfig::max_pos_accuracy`] ([`Dropout::PoorAccuracy`]);
//! - `numsats` is below [`PoseConfig::min_numsats`] ([`Dropout::FewSatellites`]);
//! - `navstat` is not one of [`PoseConfig::good_navstat`] ([`Dropout::NavStatus`]);
//! - latitude, longitude and altitude are bit-for-bit those of the previous packet: a receiver
//!   repeating its last fix ([`Dropout::Stale`]). Real, noisy fixes never repeat exactly; a
//!   parked car loses nothing by skipping such a fix.
//!
//! The velocity (`ve`, `vn`, `vu`) follows the same satellite and status rules with
//! `vel_accuracy` against [`PoseConfig::max_vel_accuracy`]; it is stale only when the whole fix
//! (position and velocity) repeats the previous packet's.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::config::PoseConfig;
use crate::{geo::GeoOrigin, oxts::Oxts};

/// Why a packet's GPS position or velocity was not used.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Dropout {
    /// A NaN or infinite field.
    NonFinite,
    /// The packet's own accuracy estimate is too poor (or NaN).
    PoorAccuracy,
    /// Too few satellites.
    FewSatellites,
    /// The navigation status says the solution is not locked.
    NavStatus,
    /// The same fix as the previous packet.
    Stale,
}

/// A usable GPS position in the world frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PositionFix {
    /// East, north, up metres from the origin.
    pub position: Vector3<f64>,
    /// Standard deviation east and north, metres.
    pub sigma: f64,
    /// Standard deviation up, metres.
    pub sigma_up: f64,
}

/// A usable GPS velocity in the world frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct VelocityFix {
    /// East, north, up m/s.
    pub velocity: Vector3<f64>,
    /// Standard deviation per axis, m/s.
    pub sigma: f64,
}

/// The status rules shared by position and velocity.
fn receiver_status(oxts: &Oxts, cfg: &PoseConfig) -> Result<(), Dropout> {
    if oxts.numsats < cfg.min_numsats {
        return Err(Dropout::FewSatellites);
    }
    if !cfg.good_navstat.contains(&oxts.navstat) {
        return Err(Dropout::NavStatus);
    }
    Ok(())
}

fn same_position(a: &Oxts, b: &Oxts) -> bool {
    a.lat.to_bits() == b.lat.to_bits()
        && a.lon.to_bits() == b.lon.to_bits()
        && a.alt.to_bits() == b.alt.to_bits()
}

fn same_velocity(a: &Oxts, b: &Oxts) -> bool {
    a.vn.to_bits() == b.vn.to_bits()
        && a.ve.to_bits() == b.ve.to_bits()
        && a.vu.to_bits() == b.vu.to_bits()
}

/// The packet's position, or why it is a dropout. `previous` is the packet before it.
pub(crate) fn position_fix(
    oxts: &Oxts,
    previous: Option<&Oxts>,
    origin: &GeoOrigin,
    cfg: &PoseConfig,
) -> Result<PositionFix, Dropout> {
    if !(oxts.lat.is_finite() && oxts.lon.is_finite() && oxts.alt.is_finite()) {
        return Err(Dropout::NonFinite);
    }
    if oxts.pos_accuracy.is_nan() || oxts.pos_accuracy > cfg.max_pos_accuracy {
        return Err(Dropout::PoorAccuracy);
    }
    receiver_status(oxts, cfg)?;
    if previous.is_some_and(|p| same_position(oxts, p)) {
        return Err(Dropout::Stale);
    }
    let position = origin.to_local(oxts.lat, oxts.lon, oxts.alt);
    if !position.iter().all(|v| v.is_finite()) {
        return Err(Dropout::NonFinite);
    }
    let sigma = cfg.gps_position_sigma.max(oxts.pos_accuracy);
    Ok(PositionFix {
        position,
        sigma,
        sigma_up: sigma * cfg.gps_vertical_sigma_ratio,
    })
}

/// The packet's velocity, or why it is not usable. `previous` is the packet before it.
pub(crate) fn velocity_fix(
    oxts: &Oxts,
    previous: Option<&Oxts>,
    cfg: &PoseConfig,
) -> Result<VelocityFix, Dropout> {
    let velocity = Vector3::new(oxts.ve, oxts.vn, oxts.vu);
    if !velocity.iter().all(|v| v.is_finite()) {
        return Err(Dropout::NonFinite);
    }
    if oxts.vel_accuracy.is_nan() || oxts.vel_accuracy > cfg.max_vel_accuracy {
        return Err(Dropout::PoorAccuracy);
    }
    receiver_status(oxts, cfg)?;
    if previous.is_some_and(|p| same_position(oxts, p) && same_velocity(oxts, p)) {
        return Err(Dropout::Stale);
    }
    Ok(VelocityFix {
        velocity,
        sigma: cfg.gps_velocity_sigma.max(oxts.vel_accuracy),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const ORIGIN: GeoOrigin = GeoOrigin::new(49.0, 8.4, 110.0);

    fn good() -> Oxts {
        Oxts {
            lat: 49.0001,
            lon: 8.4002,
            alt: 111.0,
            ve: 3.0,
            vn: 4.0,
            pos_accuracy: 0.3,
            vel_accuracy: 0.05,
            navstat: 4,
            numsats: 9,
            ..Default::default()
        }
    }

    #[test]
    fn a_locked_fix_is_used_with_the_floor_sigma() {
        let cfg = PoseConfig::default();
        let fix = position_fix(&good(), None, &ORIGIN, &cfg).unwrap();
        assert_eq!(fix.sigma, cfg.gps_position_sigma);
        assert!((fix.position.z - 1.0).abs() < 1e-9);
        let vel = velocity_fix(&good(), None, &cfg).unwrap();
        assert_eq!(vel.velocity, Vector3::new(3.0, 4.0, 0.0));
    }

    #[test]
    fn a_poor_accuracy_widens_the_sigma() {
        let oxts = Oxts {
            pos_accuracy: 2.0,
            ..good()
        };
        let fix = position_fix(&oxts, None, &ORIGIN, &PoseConfig::default()).unwrap();
        assert_eq!(fix.sigma, 2.0);
        assert_eq!(
            fix.sigma_up,
            2.0 * PoseConfig::default().gps_vertical_sigma_ratio
        );
    }

    #[test]
    fn dropouts_are_named() {
        let cfg = PoseConfig::default();
        let cases = [
            (
                Oxts {
                    lat: f64::NAN,
                    ..good()
                },
                Dropout::NonFinite,
            ),
            (
                Oxts {
                    pos_accuracy: 50.0,
                    ..good()
                },
                Dropout::PoorAccuracy,
            ),
            (
                Oxts {
                    pos_accuracy: f64::NAN,
                    ..good()
                },
                Dropout::PoorAccuracy,
            ),
            (
                Oxts {
                    numsats: 0,
                    ..good()
                },
                Dropout::FewSatellites,
            ),
            (
                Oxts {
                    navstat: 2,
                    ..good()
                },
                Dropout::NavStatus,
            ),
        ];
        for (oxts, want) in cases {
            assert_eq!(position_fix(&oxts, None, &ORIGIN, &cfg).unwrap_err(), want);
        }
        assert_eq!(
            velocity_fix(
                &Oxts {
                    vu: f64::INFINITY,
                    ..good()
                },
                None,
                &cfg
            )
            .unwrap_err(),
            Dropout::NonFinite
        );
    }

    #[test]
    fn a_repeated_fix_is_stale_but_a_new_velocity_is_not() {
        let cfg = PoseConfig::default();
        let first = good();
        assert_eq!(
            position_fix(&first, Some(&first), &ORIGIN, &cfg).unwrap_err(),
            Dropout::Stale
        );
        assert_eq!(
            velocity_fix(&first, Some(&first), &cfg).unwrap_err(),
            Dropout::Stale
        );
        let faster = Oxts { ve: 3.5, ..first };
        assert!(velocity_fix(&faster, Some(&first), &cfg).is_ok());
    }
}
