//! `GET /v1/superframes/latest`: protobuf or JSON by `Accept`.

use axum::{
    Json,
    extract::State,
    http::{HeaderMap, header},
    response::{IntoResponse, Response},
};
use prost::Message;
use trackd_client::api;

use crate::service::{error::HttpError, state::AppState, views};

/// The latest super frame this vehicle made.
#[utoipa::path(
    get,
    path = "/v1/superframes/latest",
    responses(
        (status = 200, description = "JSON, or protobuf trackd.v1.SuperFrame with Accept: application/x-protobuf",
            body = api::SuperFrameView),
        (status = 404, description = "None made yet", body = api::ApiError),
    )
)]
pub async fn latest(
    State(state): State<AppState>,
    headers: HeaderMap,
) -> Result<Response, HttpError> {
    let Some(sf) = state.latest.borrow().superframe.clone() else {
        return Err(HttpError::not_found("no super frame made yet"));
    };
    let wants_protobuf = headers
        .get(header::ACCEPT)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.contains("protobuf"));
    if wants_protobuf {
        Ok(([(header::CONTENT_TYPE, api::PROTOBUF)], sf.encode_to_vec()).into_response())
    } else {
        Ok(Json(views::superframe(&sf)).into_response())
    }
}
