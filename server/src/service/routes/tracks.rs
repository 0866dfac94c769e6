//! `GET /v1/tracks`, `GET /v1/tracks/{id}`.

use axum::{
    Json,
    extract::{Path, State, rejection::PathRejection},
    http::StatusCode,
};
use trackd_client::api;

use crate::service::{
    error::HttpError,
    state::{AppState, lock},
    views,
};

/// The tracks after the latest frame.
#[utoipa::path(get, path = "/v1/tracks", responses((status = 200, body = api::Tracks)))]
pub async fn list(State(state): State<AppState>) -> Json<api::Tracks> {
    let latest = state.latest.borrow().clone();
    let mut tracks = latest.tracks.clone();
    tracks.vehicle.clone_from(&state.settings.vehicle.id);
    Json(tracks)
}

/// One track now and where it has been.
#[utoipa::path(
    get,
    path = "/v1/tracks/{id}",
    params(("id" = u64, Path, description = "Track id")),
    responses(
        (status = 200, body = api::TrackHistory),
        (status = 404, description = "No such track", body = api::ApiError),
    )
)]
pub async fn one(
    State(state): State<AppState>,
    id: Result<Path<u64>, PathRejection>,
) -> Result<Json<api::TrackHistory>, HttpError> {
    let Path(id) = id.map_err(|e| HttpError::new(StatusCode::BAD_REQUEST, e.body_text()))?;
    let current = state
        .latest
        .borrow()
        .states
        .iter()
        .find(|t| t.id == id)
        .map(views::track);
    let history = lock(&state.history).of(id);
    if current.is_none() && history.is_none() {
        return Err(HttpError::not_found(format!("no track {id}")));
    }
    Ok(Json(api::TrackHistory {
        id,
        current,
        history: history.unwrap_or_default(),
    }))
}
