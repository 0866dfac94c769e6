//! `GET /v1/occupancy`: the occupancy map as an OctoMap `.bt` file, or a bird's-eye-view grid
//! around the vehicle as JSON (`?format=grid`, or `Accept: application/json`).

use axum::{
    Json,
    extract::{Query, State},
    http::{HeaderMap, StatusCode, header},
    response::{IntoResponse, Response},
};
use trackd_client::api;

use crate::service::{
    error::HttpError,
    occupancy::{self, Unavailable},
    state::AppState,
};

/// Query of `GET /v1/occupancy`.
#[derive(Debug, Default, serde::Deserialize, utoipa::IntoParams)]
#[into_params(parameter_in = Query)]
pub struct OccupancyQuery {
    /// `bt` (default) or `grid`.
    pub format: Option<String>,
    /// Grid: half side of the square around the vehicle (m, default 50, at most 500).
    pub half_extent: Option<f64>,
}

fn unavailable(e: Unavailable) -> HttpError {
    HttpError::new(StatusCode::INTERNAL_SERVER_ERROR, e.to_string())
}

/// The occupancy map.
#[utoipa::path(
    get,
    path = "/v1/occupancy",
    params(OccupancyQuery),
    responses(
        (status = 200, description = "OctoMap .bt (application/x-octomap-bt), or a grid as JSON",
            body = api::BevGrid),
        (status = 400, description = "Bad parameters", body = api::ApiError),
        (status = 500, description = "The map could not be read", body = api::ApiError),
    )
)]
pub async fn get(
    State(state): State<AppState>,
    headers: HeaderMap,
    Query(query): Query<OccupancyQuery>,
) -> Result<Response, HttpError> {
    let accepts_json = headers
        .get(header::ACCEPT)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.contains("application/json"));
    let grid = match query.format.as_deref() {
        Some("grid") => true,
        Some("bt") => false,
        None => accepts_json,
        Some(other) => {
            return Err(HttpError::new(
                StatusCode::BAD_REQUEST,
                format!("format {other:?}: use bt or grid"),
            ));
        }
    };
    if grid {
        let half = query.half_extent.unwrap_or(50.0);
        if !(half > 0.0 && half <= 500.0) {
            return Err(HttpError::new(
                StatusCode::BAD_REQUEST,
                "half_extent must be in (0, 500] metres",
            ));
        }
        let center = state.latest.borrow().ego_xy;
        let g = occupancy::grid(&state, center, half)
            .await
            .map_err(unavailable)?;
        Ok(Json(g).into_response())
    } else {
        let bytes = occupancy::bt(&state).await.map_err(unavailable)?;
        Ok((
            [
                (header::CONTENT_TYPE, api::OCTOMAP_BT),
                (
                    header::CONTENT_DISPOSITION,
                    "attachment; filename=\"map.bt\"",
                ),
            ],
            bytes,
        )
            .into_response())
    }
}
