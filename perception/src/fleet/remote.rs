//! Checking a remote super frame and expressing its objects in this fleet's world frame.

use thiserror::Error;
use trackd_proto::SuperFrame;

use super::{
    FusionConfig,
    origin::{OriginShift, distance_m, is_plausible},
};
use crate::{TrackState, geo::GeoOrigin, wire};

/// Longest accepted vehicle id.
pub const MAX_VEHICLE_ID_LEN: usize = 64;

/// Why a super frame was refused. Each variant is a metrics label ([`Rejection::reason`]).
#[derive(Clone, Debug, Error, PartialEq)]
pub enum Rejection {
    /// The message has no schema version (0): not one of ours.
    #[error("no schema version")]
    NoVersion,
    /// The vehicle id is empty, too long or has characters outside `[A-Za-z0-9_.-]`.
    #[error("invalid vehicle id {0:?}")]
    BadVehicleId(String),
    /// This vehicle's own super frame came back.
    #[error("own super frame")]
    Own,
    /// The origin is missing while the fleet has one, or is no place on Earth.
    #[error("origin missing or implausible")]
    BadOrigin,
    /// The origin is too far from the fleet's to be the same fleet.
    #[error("origin {distance_m:.0} m from the fleet origin (limit {limit_m:.0} m)")]
    OriginTooFar {
        /// Distance between the origins (m).
        distance_m: f64,
        /// The configured limit (m).
        limit_m: f64,
    },
    /// More objects than configured.
    #[error("{count} objects (limit {limit})")]
    TooManyObjects {
        /// Objects in the message.
        count: usize,
        /// The configured limit.
        limit: usize,
    },
    /// An object has no box, a non-finite value, a negative or huge extent, a confidence
    /// outside [0, 1], or lies out of range.
    #[error("object {id}: {why}")]
    BadObject {
        /// The object's id in the message.
        id: u64,
        /// What is wrong with it.
        why: String,
    },
}

impl Rejection {
    /// A short, stable label for metrics.
    pub fn reason(&self) -> &'static str {
        match self {
            Self::NoVersion => "no_version",
            Self::BadVehicleId(_) => "bad_vehicle_id",
            Self::Own => "own",
            Self::BadOrigin => "bad_origin",
            Self::OriginTooFar { .. } => "origin_too_far",
            Self::TooManyObjects { .. } => "too_many_objects",
            Self::BadObject { .. } => "bad_object",
        }
    }
}

/// Whether `id` is an acceptable vehicle id (also a single Zenoh key chunk).
pub fn is_valid_vehicle_id(id: &str) -> bool {
    !id.is_empty()
        && id.len() <= MAX_VEHICLE_ID_LEN
        && id
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'-' | b'.'))
}

/// Checks `frame` (from a vehicle other than `own_id`) and returns its objects as track
/// states in the world frame of `fleet_origin`.
///
/// With no fleet origin configured, frames without an origin are taken to share this
/// vehicle's frame and frames with one are refused (they could not be placed).
pub fn objects_in_fleet_frame(
    frame: &SuperFrame,
    own_id: &str,
    fleet_origin: Option<&GeoOrigin>,
    config: &FusionConfig,
) -> Result<Vec<TrackState>, Rejection> {
    if frame.version == 0 {
        return Err(Rejection::NoVersion);
    }
    if !is_valid_vehicle_id(&frame.vehicle_id) {
        return Err(Rejection::BadVehicleId(
            frame.vehicle_id.chars().take(MAX_VEHICLE_ID_LEN).collect(),
        ));
    }
    if frame.vehicle_id == own_id {
        return Err(Rejection::Own);
    }
    let origin = match &frame.origin {
        None => None,
        Some(g) => match wire::origin_from_proto(g) {
            Ok(o) if is_plausible(&o) => Some(o),
            _ => return Err(Rejection::BadOrigin),
        },
    };
    let shift = match (origin, fleet_origin) {
        (None, None) => None,
        (Some(theirs), Some(ours)) => {
            let distance_m = distance_m(&theirs, ours);
            if distance_m > config.max_origin_offset_m {
                return Err(Rejection::OriginTooFar {
                    distance_m,
                    limit_m: config.max_origin_offset_m,
                });
            }
            Some(OriginShift::new(theirs, *ours))
        }
        _ => return Err(Rejection::BadOrigin),
    };
    if frame.objects.len() > config.max_objects {
        return Err(Rejection::TooManyObjects {
            count: frame.objects.len(),
            limit: config.max_objects,
        });
    }
    frame
        .objects
        .iter()
        .map(|o| {
            let bad = |why: String| Rejection::BadObject { id: o.id, why };
            let mut track = wire::track_from_proto(o).map_err(|e| bad(e.to_string()))?;
            if track.center.norm() > config.max_range_m {
                return Err(bad(format!("{:.0} m from its origin", track.center.norm())));
            }
            if let Some(shift) = &shift {
                track.center = shift.apply(&track.center);
            }
            Ok(track)
        })
        .collect()
}
