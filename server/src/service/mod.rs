//! One vehicle's service: a perception worker thread, the REST API and the Zenoh fleet link,
//! started together by [`start`] and stopped by [`RunningService::stop`].

pub mod clock;
mod error;
mod history;
mod ingest;
mod metrics;
mod occupancy;
mod routes;
mod state;
mod views;
mod worker;
mod zenoh_link;

use std::{
    net::SocketAddr,
    sync::{Arc, Mutex, atomic::AtomicU64},
    thread::JoinHandle,
    time::Duration,
};

use anyhow::Context;
use tokio::sync::{broadcast, mpsc, watch};
use trackd_perception::{Pipeline, Vehicle, fleet::Fusion};

pub use routes::ApiDoc;
pub use zenoh_link::{alive_key, occupancy_key, superframe_key};

use crate::settings::Settings;
use state::{Latest, Shared};

/// Super frames waiting to be published before new ones are dropped (and counted).
const SUPERFRAME_BACKLOG: usize = 64;
/// Frames buffered per SSE client before it lags.
const SSE_BUFFER: usize = 64;

/// A started service.
pub struct RunningService {
    http_addr: SocketAddr,
    vehicle: String,
    shutdown: watch::Sender<bool>,
    server: tokio::task::JoinHandle<std::io::Result<()>>,
    zenoh: zenoh_link::ZenohLink,
    worker: JoinHandle<()>,
}

impl RunningService {
    /// The address the REST API listens on (the real port when 0 was configured).
    pub fn http_addr(&self) -> SocketAddr {
        self.http_addr
    }

    /// The REST API's base URL.
    pub fn url(&self) -> String {
        format!("http://{}", self.http_addr)
    }

    /// The vehicle id.
    pub fn vehicle(&self) -> &str {
        &self.vehicle
    }

    /// Runs until `stop` resolves, then stops.
    pub async fn run_until(
        self,
        stop: impl std::future::Future<Output = ()>,
    ) -> anyhow::Result<()> {
        stop.await;
        self.stop().await
    }

    /// Stops: HTTP connections and streams end, the liveliness token is withdrawn, the Zenoh
    /// session closes, and the worker finishes the scans already queued.
    pub async fn stop(self) -> anyhow::Result<()> {
        let _ = self.shutdown.send(true);
        let mut server = self.server;
        match tokio::time::timeout(Duration::from_secs(5), &mut server).await {
            Ok(joined) => joined.context("HTTP server task")??,
            Err(_) => {
                server.abort();
                tracing::warn!("HTTP server did not stop within 5 s; aborted");
            }
        }
        self.zenoh.close().await?;
        let worker = self.worker;
        tokio::task::spawn_blocking(move || worker.join())
            .await
            .context("joining the worker")?
            .map_err(|_| anyhow::anyhow!("the perception worker panicked"))?;
        tracing::info!(vehicle = self.vehicle, "service stopped");
        Ok(())
    }
}

/// Starts a service with `settings`: binds the HTTP address, opens the Zenoh session, starts
/// the worker.
pub async fn start(settings: Settings) -> anyhow::Result<RunningService> {
    settings.check()?;
    let vehicle = settings.vehicle.id.clone();
    let clock = clock::Clock::start();
    let metrics = Arc::new(metrics::Metrics::default());
    let pipeline = Arc::new(Mutex::new(Pipeline::new(
        settings.perception.clone(),
        Vehicle {
            id: vehicle.clone(),
            origin: settings.fleet.origin(),
            imu_to_velo: settings.vehicle.imu_to_velo(),
        },
    )));
    let history = Arc::new(Mutex::new(history::History::new(settings.queue.history)));
    let (queue_tx, queue_rx) = mpsc::channel(settings.queue.capacity);
    let (latest_tx, latest_rx) = watch::channel(Arc::new(Latest {
        tracks: trackd_client::api::Tracks {
            vehicle: vehicle.clone(),
            ..Default::default()
        },
        ..Default::default()
    }));
    let (events_tx, _) = broadcast::channel(SSE_BUFFER);
    let (superframes_tx, superframes_rx) = mpsc::channel(SUPERFRAME_BACKLOG);
    let (shutdown_tx, shutdown_rx) = watch::channel(false);

    let worker = worker::spawn(
        pipeline.clone(),
        queue_rx,
        worker::Outputs {
            vehicle: vehicle.clone(),
            clock,
            latest: latest_tx,
            events: events_tx.clone(),
            history: history.clone(),
            superframes: superframes_tx,
            metrics: metrics.clone(),
        },
    )
    .context("starting the perception worker")?;

    let listener = tokio::net::TcpListener::bind(settings.http.listen)
        .await
        .with_context(|| format!("binding the REST API to {}", settings.http.listen))?;
    let http_addr = listener.local_addr()?;

    let fusion = Fusion::new(
        vehicle.clone(),
        settings.fleet.origin(),
        settings.fleet.fusion(),
    );
    let state = Arc::new(Shared {
        settings,
        clock,
        queue: queue_tx,
        next_scan_id: AtomicU64::new(0),
        latest: latest_rx,
        events: events_tx,
        history,
        fusion: Arc::new(Mutex::new(fusion)),
        metrics,
        pipeline,
        zenoh_up: Default::default(),
        shutdown: shutdown_rx.clone(),
    });
    let zenoh = zenoh_link::ZenohLink::start(state.clone(), superframes_rx).await?;

    let app = routes::router(state);
    let mut stop = shutdown_rx;
    let server = tokio::spawn(async move {
        axum::serve(listener, app)
            .with_graceful_shutdown(async move {
                let _ = stop.wait_for(|&s| s).await;
            })
            .await
    });
    tracing::info!(vehicle, %http_addr, "service started");
    Ok(RunningService {
        http_addr,
        vehicle,
        shutdown: shutdown_tx,
        server,
        zenoh,
        worker,
    })
}
