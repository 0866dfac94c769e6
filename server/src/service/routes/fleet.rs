//! `GET /v1/fleet`, `GET /v1/fleet/objects`.

use axum::{Json, extract::State};
use trackd_client::api;

use crate::service::{
    state::{AppState, lock},
    views,
};

/// The vehicles this service has heard of.
#[utoipa::path(get, path = "/v1/fleet", responses((status = 200, body = api::Fleet)))]
pub async fn vehicles(State(state): State<AppState>) -> Json<api::Fleet> {
    let now = state.clock.now_ms();
    let mut fusion = lock(&state.fusion);
    fusion.expire(now);
    let vehicles = fusion
        .vehicles()
        .iter()
        .map(|(id, v)| api::VehicleStatus {
            id: id.clone(),
            alive: v.alive,
            last_seen_ms: v.last_seen_ms.map(|t| now.saturating_sub(t)),
            sequence: v.sequence,
            timestamp: v.timestamp,
            lag_ms: v.lag_ms,
            objects: v.objects.len(),
            superframes: v.superframes,
        })
        .collect();
    Json(api::Fleet {
        vehicle: state.settings.vehicle.id.clone(),
        origin: state.settings.fleet.origin,
        vehicles,
    })
}

/// The fused world view: this vehicle's tracks (when tracked in the world frame) and every
/// live vehicle's latest objects, one entry per object.
#[utoipa::path(get, path = "/v1/fleet/objects", responses((status = 200, body = api::FusedObjects)))]
pub async fn objects(State(state): State<AppState>) -> Json<api::FusedObjects> {
    let now = state.clock.now_ms();
    let latest = state.latest.borrow().clone();
    let in_world = latest.tracks.tracking_frame.as_deref() == Some("world");
    let own: &[_] = if in_world { &latest.states } else { &[] };
    let own_age = latest.at_ms.map_or(0, |t| now.saturating_sub(t));
    let mut fusion = lock(&state.fusion);
    fusion.expire(now);
    let view = fusion.view(own, own_age, now);
    Json(api::FusedObjects {
        objects: view.iter().map(views::fused).collect(),
    })
}
