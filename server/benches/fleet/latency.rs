//! Publish → fused latency: a Zenoh peer publishes a super frame holding new objects; the time
//! until they are in a service's `GET /v1/fleet/objects` (polled without pause).

use std::time::{Duration, Instant};

use prost::Message;
use trackd_client::Client;
use trackd_proto::{Box3, GeoPoint, SuperFrame, TrackedObject};
use trackd_service::{
    local_fleet::{LocalFleet, free_port, loopback_endpoint},
    service::{alive_key, superframe_key},
    settings::zenoh_config,
};

use crate::stats::{percentile, sorted};
use crate::{ORIGIN, base_settings};

/// Objects in each published super frame.
const OBJECTS_PER_FRAME: usize = 20;
/// Super frames timed.
const ROUNDS: u64 = 300;

/// A super frame of `vehicle` holding [`OBJECTS_PER_FRAME`] cars with ids from `first_id`.
fn superframe(vehicle: &str, sequence: u64, first_id: u64) -> SuperFrame {
    SuperFrame {
        version: trackd_proto::SCHEMA_VERSION,
        vehicle_id: vehicle.into(),
        sequence,
        timestamp: sequence as f64 * 0.1,
        ego_pose: None,
        origin: Some(GeoPoint {
            lat: ORIGIN[0],
            lon: ORIGIN[1],
            alt: ORIGIN[2],
        }),
        objects: (0..OBJECTS_PER_FRAME as u64)
            .map(|k| TrackedObject {
                id: first_id + k,
                class: trackd_proto::ObjectClass::Car as i32,
                r#box: Some(Box3 {
                    x: 10.0 + 5.0 * k as f64,
                    y: 3.0,
                    z: 0.8,
                    l: 4.0,
                    w: 1.8,
                    h: 1.5,
                    yaw: 0.0,
                }),
                confidence: 0.8,
                ..Default::default()
            })
            .collect(),
    }
}

/// A Zenoh peer connected to the router at `router_port` (explicit loopback endpoints, no
/// multicast scouting), alive as `vehicle`.
async fn peer(
    router_port: u16,
    vehicle: &str,
) -> anyhow::Result<(zenoh::Session, zenoh::liveliness::LivelinessToken)> {
    let config = zenoh_config(
        "peer",
        &[loopback_endpoint(free_port()?)],
        &[loopback_endpoint(router_port)],
        false,
    )?;
    let session = zenoh::open(config)
        .await
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let token = session
        .liveliness()
        .declare_token(alive_key(vehicle))
        .await
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok((session, token))
}

/// Measures and prints publish → fused latency through a router to one service.
pub async fn run() -> anyhow::Result<()> {
    let fleet = LocalFleet::start(&["a".into()], &base_settings()).await?;
    let a = Client::new(&fleet.services[0].url(), None);
    let (session, _token) = peer(fleet.router_port, "b").await?;
    let key = superframe_key("b");
    // Warm up until frames get through.
    let mut sequence = 0;
    loop {
        sequence += 1;
        session
            .put(&key, superframe("b", sequence, 0).encode_to_vec())
            .await
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        tokio::time::sleep(Duration::from_millis(50)).await;
        if !a.objects().await?.objects.is_empty() {
            break;
        }
    }
    let mut samples = Vec::new();
    for round in 0..ROUNDS {
        sequence += 1;
        let first_id = 1_000 * (round + 1);
        let wanted = format!("b/{first_id}");
        let sent = Instant::now();
        session
            .put(&key, superframe("b", sequence, first_id).encode_to_vec())
            .await
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        loop {
            if a.objects().await?.objects.iter().any(|o| o.id == wanted) {
                break;
            }
            anyhow::ensure!(
                sent.elapsed() < Duration::from_secs(5),
                "frame {round} never arrived"
            );
        }
        samples.push(sent.elapsed().as_secs_f64() * 1000.0);
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    let samples = sorted(samples);
    println!(
        "publish -> fused (REST-visible), {OBJECTS_PER_FRAME} objects/frame, {} samples: \
         p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms",
        samples.len(),
        percentile(&samples, 0.5),
        percentile(&samples, 0.99),
        percentile(&samples, 1.0)
    );
    drop(session);
    fleet.stop().await
}
