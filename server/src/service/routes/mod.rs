//! The REST API: one module per resource, assembled here with the OpenAPI document.

mod auth;
mod fleet;
mod health;
mod occupancy;
mod scans;
mod stream;
mod superframes;
mod tracks;

use axum::{
    Json, Router,
    extract::DefaultBodyLimit,
    middleware,
    routing::{get, post},
};
use trackd_client::api;
use utoipa::{
    Modify, OpenApi,
    openapi::security::{HttpAuthScheme, HttpBuilder, SecurityScheme},
};

use super::state::AppState;

/// The OpenAPI 3 document of the API (`GET /openapi.json`).
#[derive(OpenApi)]
#[openapi(
    info(title = "trackd", description = "Training-free LiDAR object tracking, one service per vehicle."),
    paths(
        scans::upload,
        tracks::list,
        tracks::one,
        superframes::latest,
        fleet::vehicles,
        fleet::objects,
        occupancy::get,
        stream::sse,
        health::healthz,
        health::metrics,
    ),
    components(schemas(
        api::Track, api::Tracks, api::StageTime, api::ScanProcessed, api::ScanQueued,
        api::TrackPoint, api::TrackHistory, api::VehicleStatus, api::Fleet, api::FusedObject,
        api::FusedObjects, api::Health, api::SuperFrameView, api::BevGrid, api::ApiError,
    )),
    modifiers(&BearerAuth)
)]
pub struct ApiDoc;

/// Declares the `bearer` security scheme used by writes.
struct BearerAuth;

impl Modify for BearerAuth {
    fn modify(&self, openapi: &mut utoipa::openapi::OpenApi) {
        let components = openapi.components.get_or_insert_with(Default::default);
        components.add_security_scheme(
            "bearer",
            SecurityScheme::Http(HttpBuilder::new().scheme(HttpAuthScheme::Bearer).build()),
        );
    }
}

async fn openapi() -> Json<utoipa::openapi::OpenApi> {
    Json(ApiDoc::openapi())
}

/// The API's router.
pub fn router(state: AppState) -> Router {
    let writes = Router::new()
        .route("/v1/scans", post(scans::upload))
        .route_layer(middleware::from_fn_with_state(
            state.clone(),
            auth::require_token,
        ));
    Router::new()
        .merge(writes)
        .route("/v1/tracks", get(tracks::list))
        .route("/v1/tracks/{id}", get(tracks::one))
        .route("/v1/superframes/latest", get(superframes::latest))
        .route("/v1/fleet", get(fleet::vehicles))
        .route("/v1/fleet/objects", get(fleet::objects))
        .route("/v1/occupancy", get(occupancy::get))
        .route("/v1/stream", get(stream::sse))
        .route("/healthz", get(health::healthz))
        .route("/metrics", get(health::metrics))
        .route("/openapi.json", get(openapi))
        .layer(DefaultBodyLimit::max(state.settings.http.max_body_bytes))
        .with_state(state)
}
