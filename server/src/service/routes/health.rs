//! `GET /healthz` (cheap: no lock taken) and `GET /metrics`.

use std::sync::atomic::Ordering;

use axum::{Json, extract::State, http::header, response::IntoResponse};
use trackd_client::api;

use crate::service::state::AppState;

/// Liveness and a few counters.
#[utoipa::path(get, path = "/healthz", responses((status = 200, body = api::Health)))]
pub async fn healthz(State(state): State<AppState>) -> Json<api::Health> {
    Json(api::Health {
        status: "ok".into(),
        vehicle: state.settings.vehicle.id.clone(),
        frames: state.latest.borrow().frames,
        queue_depth: state.settings.queue.capacity - state.queue.capacity(),
        zenoh: state.zenoh_up.load(Ordering::Relaxed),
    })
}

/// Prometheus text exposition.
#[utoipa::path(get, path = "/metrics",
    responses((status = 200, description = "Prometheus text format", content_type = "text/plain", body = String)))]
pub async fn metrics(State(state): State<AppState>) -> impl IntoResponse {
    (
        [(
            header::CONTENT_TYPE,
            "application/openmetrics-text; version=1.0.0; charset=utf-8",
        )],
        state.metrics.render(),
    )
}
