//! What the HTTP handlers and the Zenoh link share.

use std::sync::{
    Arc, Mutex, MutexGuard,
    atomic::{AtomicBool, AtomicU64},
};

use tokio::sync::{broadcast, mpsc, watch};
use trackd_client::api;
use trackd_perception::{Pipeline, TrackState, fleet::Fusion};
use trackd_proto::SuperFrame;

use super::{clock::Clock, history::History, metrics::Metrics, worker::Job};
use crate::settings::Settings;

/// The state after the latest processed frame.
#[derive(Clone, Debug, Default)]
pub struct Latest {
    /// The tracks as JSON.
    pub tracks: api::Tracks,
    /// The tracks as the pipeline gave them (for fusion).
    pub states: Vec<TrackState>,
    /// Ground position of the sensor in the world frame (x, y).
    pub ego_xy: [f64; 2],
    /// When the frame finished (service clock, ms).
    pub at_ms: Option<u64>,
    /// The latest super frame this vehicle made, if any.
    pub superframe: Option<Arc<SuperFrame>>,
    /// Frames processed.
    pub frames: u64,
}

/// Locks a mutex, recovering the data if a panicking thread poisoned it (the worker catches
/// pipeline panics; the data stays usable).
pub fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// Shared by every handler and task of one service.
pub struct Shared {
    /// The settings in force.
    pub settings: Settings,
    /// The service clock.
    pub clock: Clock,
    /// Scans to the worker.
    pub queue: mpsc::Sender<Job>,
    /// Id of the next accepted upload.
    pub next_scan_id: AtomicU64,
    /// The latest frame's state.
    pub latest: watch::Receiver<Arc<Latest>>,
    /// Each frame's tracks, for SSE.
    pub events: broadcast::Sender<Arc<api::Tracks>>,
    /// Track positions.
    pub history: Arc<Mutex<History>>,
    /// The fleet view.
    pub fusion: Arc<Mutex<Fusion>>,
    /// The metrics.
    pub metrics: Arc<Metrics>,
    /// The pipeline (the worker locks it per frame; readers of the occupancy map too).
    pub pipeline: Arc<Mutex<Pipeline>>,
    /// Whether the Zenoh session is up.
    pub zenoh_up: AtomicBool,
    /// Turns true when the service stops.
    pub shutdown: watch::Receiver<bool>,
}

/// The axum state: a cheap handle on [`Shared`].
pub type AppState = Arc<Shared>;
