//! `POST /v1/scans`: queue a scan for the worker; answer with its result, or 202.

use std::{sync::atomic::Ordering, time::Duration};

use axum::{
    Json,
    body::Bytes,
    extract::{
        Query, State,
        rejection::{BytesRejection, QueryRejection},
    },
    http::{HeaderMap, StatusCode},
    response::{IntoResponse, Response},
};
use tokio::sync::{mpsc::error::TrySendError, oneshot};
use trackd_client::api;

use crate::service::{
    error::HttpError,
    ingest::{ScanQuery, media_type, read_scan},
    state::AppState,
    worker::Job,
};

/// Upload one scan.
///
/// Body: a protobuf `trackd.v1.Scan` (`application/x-protobuf`), or a KITTI `.bin`
/// (`application/x-kitti-bin`) or PCD (`application/x-pcd`) file with its timestamp and
/// pose or OXTS packet in the query or in `X-Trackd-Timestamp` / `X-Trackd-Pose` /
/// `X-Trackd-Oxts` headers.
#[utoipa::path(
    post,
    path = "/v1/scans",
    params(ScanQuery),
    request_body(content = Vec<u8>, content_type = "application/x-protobuf",
        description = "trackd.v1.Scan, or a .bin / PCD file with another content type"),
    responses(
        (status = 200, description = "Processed", body = api::ScanProcessed),
        (status = 202, description = "Queued (async=true)", body = api::ScanQueued),
        (status = 400, description = "Malformed body or parameters", body = api::ApiError),
        (status = 401, description = "Token missing or wrong", body = api::ApiError),
        (status = 413, description = "Body over the limit", body = api::ApiError),
        (status = 415, description = "Content type not accepted", body = api::ApiError),
        (status = 422, description = "The pipeline refused the scan", body = api::ApiError),
        (status = 429, description = "Queue full; see Retry-After", body = api::ApiError),
        (status = 504, description = "Still queued after the wait; it will be processed", body = api::ApiError),
    ),
    security(("bearer" = []))
)]
pub async fn upload(
    State(state): State<AppState>,
    headers: HeaderMap,
    query: Result<Query<ScanQuery>, QueryRejection>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Response, HttpError> {
    let m = &state.metrics;
    let refuse = |status: StatusCode, reason: &'static str, message: String| {
        m.reject_scan(reason);
        HttpError::new(status, message)
    };
    let Query(query) =
        query.map_err(|e| refuse(StatusCode::BAD_REQUEST, "bad_request", e.body_text()))?;
    let content_type = media_type(&headers);
    let body = body.map_err(|e| {
        let status = e.status();
        let reason = if status == StatusCode::PAYLOAD_TOO_LARGE {
            "too_large"
        } else {
            "bad_request"
        };
        refuse(status, reason, e.body_text())
    })?;
    let frame = read_scan(content_type.as_deref(), &headers, &query, &body)
        .map_err(|r| refuse(r.status, r.reason, r.message))?;

    let scan_id = state.next_scan_id.fetch_add(1, Ordering::Relaxed);
    let (reply, result) = if query.queue_only {
        (None, None)
    } else {
        let (tx, rx) = oneshot::channel();
        (Some(tx), Some(rx))
    };
    match state.queue.try_send(Job {
        scan_id,
        frame,
        reply,
    }) {
        Ok(()) => {}
        Err(TrySendError::Full(_)) => {
            let mut e = refuse(
                StatusCode::TOO_MANY_REQUESTS,
                "queue_full",
                format!(
                    "the scan queue is full ({} scans); retry later",
                    state.settings.queue.capacity
                ),
            );
            e.retry_after_s = Some(1);
            return Err(e);
        }
        Err(TrySendError::Closed(_)) => {
            return Err(refuse(
                StatusCode::SERVICE_UNAVAILABLE,
                "stopping",
                "the service is stopping".into(),
            ));
        }
    }
    m.scans_accepted.inc();
    let queue_depth = state.settings.queue.capacity - state.queue.capacity();
    m.queue_depth.set(queue_depth as i64);

    let Some(result) = result else {
        return Ok((
            StatusCode::ACCEPTED,
            Json(api::ScanQueued {
                scan_id,
                queue_depth,
            }),
        )
            .into_response());
    };
    let wait = Duration::from_millis(state.settings.http.result_timeout_ms);
    match tokio::time::timeout(wait, result).await {
        Ok(Ok(Ok(processed))) => Ok(Json(processed).into_response()),
        Ok(Ok(Err(message))) => Err(HttpError::new(StatusCode::UNPROCESSABLE_ENTITY, message)),
        Ok(Err(_)) => Err(HttpError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            "the perception worker stopped",
        )),
        Err(_) => Err(HttpError::new(
            StatusCode::GATEWAY_TIMEOUT,
            format!("scan {scan_id} is still queued after {wait:?}; it will be processed"),
        )),
    }
}
