//! `GET /v1/stream`: Server-Sent Events, one `tracks` event after each frame.

use std::{convert::Infallible, sync::Arc, time::Duration};

use axum::{
    extract::State,
    response::sse::{Event, KeepAlive, Sse},
};
use futures_util::{Stream, stream};
use tokio::sync::broadcast::error::RecvError;
use trackd_client::api;

use crate::service::state::AppState;

/// The live stream of tracks.
#[utoipa::path(
    get,
    path = "/v1/stream",
    responses((status = 200, description = "text/event-stream of `tracks` events (api::Tracks as JSON)",
        content_type = "text/event-stream", body = api::Tracks))
)]
pub async fn sse(
    State(state): State<AppState>,
) -> Sse<impl Stream<Item = Result<Event, Infallible>>> {
    let events = state.events.subscribe();
    let shutdown = state.shutdown.clone();
    let stream = stream::unfold(
        (events, shutdown, state),
        |(mut events, mut shutdown, state)| async move {
            let next = tokio::select! {
                _ = shutdown.changed() => return None,
                next = events.recv() => next,
            };
            let event = match next {
                Ok(tracks) => tracks_event(&tracks),
                Err(RecvError::Lagged(n)) => {
                    for _ in 0..n {
                        state.metrics.count_drop("sse_lagged");
                    }
                    Event::default().event("lagged").data(n.to_string())
                }
                Err(RecvError::Closed) => return None,
            };
            Some((Ok(event), (events, shutdown, state)))
        },
    );
    Sse::new(stream).keep_alive(KeepAlive::new().interval(Duration::from_secs(10)))
}

fn tracks_event(tracks: &Arc<api::Tracks>) -> Event {
    let data = serde_json::to_string(tracks.as_ref()).unwrap_or_else(|_| "{}".into());
    Event::default().event("tracks").data(data)
}
