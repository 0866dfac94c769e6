//! The service's Zenoh session: publishes this vehicle's super frames, declares its
//! liveliness, takes in the fleet's super frames and liveliness, answers occupancy queries.
//!
//! Keys: `trackd/fleet/<vehicle>/superframe`, `trackd/fleet/<vehicle>/alive`,
//! `trackd/fleet/<vehicle>/occupancy`.

use std::{sync::atomic::Ordering, time::SystemTime};

use anyhow::Context;
use prost::Message;
use tokio::{sync::mpsc, task::JoinSet};
use trackd_proto::SuperFrame;
use zenoh::{
    Session,
    sample::{Locality, Sample, SampleKind},
};

use super::{
    occupancy,
    state::{AppState, lock},
};

/// The key a vehicle publishes its super frames on.
pub fn superframe_key(vehicle: &str) -> String {
    format!("trackd/fleet/{vehicle}/superframe")
}

/// The key of a vehicle's liveliness token.
pub fn alive_key(vehicle: &str) -> String {
    format!("trackd/fleet/{vehicle}/alive")
}

/// The key a vehicle answers occupancy queries on.
pub fn occupancy_key(vehicle: &str) -> String {
    format!("trackd/fleet/{vehicle}/occupancy")
}

/// The `<vehicle>` chunk of a `trackd/fleet/<vehicle>/<what>` key.
fn vehicle_of(key: &str) -> Option<&str> {
    let mut parts = key.split('/');
    match (
        parts.next(),
        parts.next(),
        parts.next(),
        parts.next(),
        parts.next(),
    ) {
        (Some("trackd"), Some("fleet"), Some(vehicle), Some(_), None) => Some(vehicle),
        _ => None,
    }
}

/// A running Zenoh link; [`ZenohLink::close`] withdraws the liveliness token.
pub struct ZenohLink {
    session: Session,
    tasks: JoinSet<()>,
}

impl ZenohLink {
    /// Opens the session and starts the publisher, subscribers and queryable.
    pub async fn start(
        state: AppState,
        superframes: mpsc::Receiver<SuperFrame>,
    ) -> anyhow::Result<Self> {
        let settings = &state.settings;
        let vehicle = settings.vehicle.id.clone();
        let config = settings.zenoh.to_zenoh_config()?;
        let session = zenoh::open(config)
            .await
            .map_err(|e| anyhow::anyhow!("opening the Zenoh session: {e}"))?;
        let mut tasks = JoinSet::new();

        let publisher = session
            .declare_publisher(superframe_key(&vehicle))
            .await
            .map_err(|e| anyhow::anyhow!("declaring the super-frame publisher: {e}"))?;
        let token = session
            .liveliness()
            .declare_token(alive_key(&vehicle))
            .await
            .map_err(|e| anyhow::anyhow!("declaring the liveliness token: {e}"))?;
        let subscriber = session
            .declare_subscriber("trackd/fleet/*/superframe")
            .allowed_origin(Locality::Remote)
            .await
            .map_err(|e| anyhow::anyhow!("subscribing to super frames: {e}"))?;
        let liveliness = session
            .liveliness()
            .declare_subscriber("trackd/fleet/*/alive")
            .history(true)
            .await
            .map_err(|e| anyhow::anyhow!("subscribing to liveliness: {e}"))?;
        let queryable = session
            .declare_queryable(occupancy_key(&vehicle))
            .await
            .map_err(|e| anyhow::anyhow!("declaring the occupancy queryable: {e}"))?;

        // Publisher: the worker's super frames, in order.
        let s = state.clone();
        let mut shutdown = state.shutdown.clone();
        let mut superframes = superframes;
        tasks.spawn(async move {
            let _token = token; // withdrawn when this task ends
            loop {
                tokio::select! {
                    _ = shutdown.changed() => break,
                    next = superframes.recv() => {
                        let Some(sf) = next else { break };
                        match publisher.put(sf.encode_to_vec()).await {
                            Ok(()) => s.metrics.zenoh("out"),
                            Err(e) => {
                                s.metrics.count_drop("publish_failed");
                                tracing::warn!("publishing a super frame: {e}");
                            }
                        }
                    }
                }
            }
        });

        // Subscriber: the fleet's super frames into fusion.
        let s = state.clone();
        let mut shutdown = state.shutdown.clone();
        tasks.spawn(async move {
            loop {
                tokio::select! {
                    _ = shutdown.changed() => break,
                    sample = subscriber.recv_async() => match sample {
                        Ok(sample) => ingest(&s, &sample),
                        Err(_) => break,
                    }
                }
            }
        });

        // Liveliness: vehicles joining and leaving.
        let s = state.clone();
        let mut shutdown = state.shutdown.clone();
        tasks.spawn(async move {
            loop {
                tokio::select! {
                    _ = shutdown.changed() => break,
                    sample = liveliness.recv_async() => match sample {
                        Ok(sample) => {
                            let key = sample.key_expr().as_str();
                            let Some(vehicle) = vehicle_of(key) else { continue };
                            let alive = sample.kind() == SampleKind::Put;
                            tracing::info!(vehicle, alive, "fleet liveliness");
                            lock(&s.fusion).set_alive(vehicle, alive);
                        }
                        Err(_) => break,
                    }
                }
            }
        });

        // Queryable: this vehicle's occupancy map as a `.bt` file.
        let s = state.clone();
        let mut shutdown = state.shutdown.clone();
        tasks.spawn(async move {
            loop {
                tokio::select! {
                    _ = shutdown.changed() => break,
                    query = queryable.recv_async() => {
                        let Ok(query) = query else { break };
                        let answer = occupancy::bt(&s).await;
                        let sent = match answer {
                            Ok(bytes) => query.reply(query.key_expr().clone(), bytes).await,
                            Err(e) => query.reply_err(e.to_string()).await,
                        };
                        if let Err(e) = sent {
                            tracing::warn!("answering an occupancy query: {e}");
                        }
                    }
                }
            }
        });

        state.zenoh_up.store(true, Ordering::Relaxed);
        tracing::info!(
            vehicle,
            listen = ?settings.zenoh.listen,
            connect = ?settings.zenoh.connect,
            "Zenoh session open"
        );
        Ok(Self { session, tasks })
    }

    /// Stops the tasks (withdrawing the liveliness token) and closes the session.
    pub async fn close(mut self) -> anyhow::Result<()> {
        while self.tasks.join_next().await.is_some() {}
        self.session
            .close()
            .await
            .map_err(|e| anyhow::anyhow!("{e}"))
            .context("closing the Zenoh session")
    }
}

/// Takes in one super frame sample: size, key, decoding and fusion checks, each refusal
/// counted by reason.
fn ingest(state: &AppState, sample: &Sample) {
    let m = &state.metrics;
    let payload = sample.payload();
    if payload.len() > state.settings.zenoh.max_message_bytes {
        m.zenoh_reject("oversized");
        return;
    }
    let Some(key_vehicle) = vehicle_of(sample.key_expr().as_str()) else {
        m.zenoh_reject("bad_key");
        return;
    };
    let bytes = payload.to_bytes();
    let frame = match SuperFrame::decode(bytes.as_ref()) {
        Ok(frame) => frame,
        Err(_) => {
            m.zenoh_reject("decode");
            return;
        }
    };
    if frame.vehicle_id != key_vehicle {
        m.zenoh_reject("key_mismatch");
        return;
    }
    let lag_ms = sample.timestamp().and_then(|t| {
        SystemTime::now()
            .duration_since(t.get_time().to_system_time())
            .ok()
            .map(|d| d.as_secs_f64() * 1000.0)
    });
    let now = state.clock.now_ms();
    match lock(&state.fusion).ingest(&frame, now, lag_ms) {
        Ok(_) => {
            m.zenoh("in");
            if let Some(lag) = lag_ms {
                m.fusion_lag_ms.observe(lag);
            }
        }
        Err(rejection) => {
            m.zenoh_reject(rejection.reason());
            tracing::debug!(vehicle = key_vehicle, "super frame refused: {rejection}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vehicle_ids_come_from_keys() {
        assert_eq!(vehicle_of("trackd/fleet/car-2/superframe"), Some("car-2"));
        assert_eq!(vehicle_of("trackd/fleet/car-2/alive"), Some("car-2"));
        assert_eq!(vehicle_of("trackd/fleet/superframe"), None);
        assert_eq!(vehicle_of("other/fleet/a/superframe"), None);
        assert_eq!(vehicle_of("trackd/fleet/a/b/superframe"), None);
    }
}
