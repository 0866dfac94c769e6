//! Fleet benchmark on loopback (not a test): `cargo bench -p trackd --bench fleet`.
//!
//! 1. Publish → fused latency: a peer publishes a super frame with a new object; the time
//!    until the object is in a service's `GET /v1/fleet/objects` (polled without pause).
//! 2. Capacity: N services on one machine, each fed scans over REST at 10 Hz and sent
//!    super frames by every other vehicle at 10 Hz; does every service keep 10 Hz, and how
//!    long do uploads and fusion take?
//!
//! Scans are a real KITTI scan when the shared data is there, else a synthetic one of
//! 120 000 points. Set `TRACKD_BENCH_MAX_VEHICLES` to bound the capacity sweep.

use std::{
    sync::Arc,
    time::{Duration, Instant},
};

use prost::Message;
use trackd_client::{Client, ClientError, ScanBody};
use trackd_proto::{Box3, GeoPoint, SuperFrame, TrackedObject};
use trackd_service::{
    local_fleet::{LocalFleet, free_port, loopback_endpoint},
    service::{alive_key, superframe_key},
    settings::{Settings, zenoh_config},
};

const ORIGIN: [f64; 3] = [49.011_213_954_206, 8.422_885_922_889_3, 112.83];
const OBJECTS_PER_FRAME: usize = 20;

fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let i = ((sorted.len() - 1) as f64 * p).round() as usize;
    sorted[i]
}

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
                    y: (vehicle.len() as f64) * 3.0,
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

fn base() -> Settings {
    let mut s = Settings::default();
    s.fleet.origin = Some(ORIGIN);
    s
}

fn scan_bytes() -> Vec<u8> {
    if let Some(dir) = trackd_dataset::shared_data_dir("kitti-format-samples") {
        let found = std::fs::read_dir(dir.join("raw/2011_09_26"))
            .ok()
            .and_then(|mut drives| {
                drives.find_map(|d| {
                    let p = d.ok()?.path().join("velodyne_points/data/0000000000.bin");
                    std::fs::read(p).ok()
                })
            });
        if let Some(bytes) = found {
            return bytes;
        }
    }
    (0..120_000)
        .flat_map(|i| {
            let a = i as f32 * 0.001;
            [20.0 * a.cos(), 20.0 * a.sin(), -1.5, 0.3]
        })
        .flat_map(f32::to_le_bytes)
        .collect()
}

async fn latency() -> anyhow::Result<()> {
    let fleet = LocalFleet::start(&["a".into()], &base()).await?;
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
    for round in 0..300u64 {
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
    samples.sort_by(f64::total_cmp);
    println!(
        "publish -> fused (REST-visible), {} objects/frame, {} samples: p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms",
        OBJECTS_PER_FRAME,
        samples.len(),
        percentile(&samples, 0.5),
        percentile(&samples, 0.99),
        percentile(&samples, 1.0)
    );
    drop(session);
    fleet.stop().await
}

/// Runs N vehicles at 10 Hz for `seconds`; returns (worst achieved Hz, upload p99 ms,
/// fused-view p99 ms).
async fn capacity(n: usize, seconds: u64, scan: Arc<Vec<u8>>) -> anyhow::Result<(f64, f64, f64)> {
    let ids: Vec<String> = (0..n).map(|i| format!("v{i}")).collect();
    let fleet = LocalFleet::start(&ids, &base()).await?;
    let period = Duration::from_millis(100);
    let mut tasks = tokio::task::JoinSet::new();
    for (i, service) in fleet.services.iter().enumerate() {
        let client = Client::new(&service.url(), None);
        let scan = scan.clone();
        let id = ids[i].clone();
        let router_port = fleet.router_port;
        tasks.spawn(async move {
            // The vehicle's super frames, as its pipeline would publish them.
            let (session, _token) = peer(router_port, &format!("{id}-sf")).await?;
            let key = superframe_key(&format!("{id}-sf"));
            let mut upload_ms = Vec::new();
            let mut fused_ms = Vec::new();
            let start = Instant::now();
            let mut next = Instant::now();
            let mut frames = 0u64;
            while start.elapsed() < Duration::from_secs(seconds) {
                tokio::time::sleep_until(next.into()).await;
                next += period;
                frames += 1;
                let t = Instant::now();
                let body = ScanBody::Raw {
                    bytes: scan.as_ref().clone(),
                    content_type: trackd_client::api::KITTI_BIN,
                    timestamp: frames as f64 * 0.1,
                    pose: Some([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]),
                    oxts: None,
                };
                match client.upload(body, false).await {
                    Ok(_) | Err(ClientError::Busy { .. }) => {}
                    Err(e) => return Err(anyhow::anyhow!("{e}")),
                }
                upload_ms.push(t.elapsed().as_secs_f64() * 1000.0);
                session
                    .put(
                        &key,
                        superframe(&format!("{id}-sf"), frames, 0).encode_to_vec(),
                    )
                    .await
                    .map_err(|e| anyhow::anyhow!("{e}"))?;
                let t = Instant::now();
                client.objects().await?;
                fused_ms.push(t.elapsed().as_secs_f64() * 1000.0);
            }
            let hz = frames as f64 / start.elapsed().as_secs_f64();
            Ok::<_, anyhow::Error>((hz, upload_ms, fused_ms))
        });
    }
    let mut worst_hz = f64::INFINITY;
    let mut uploads = Vec::new();
    let mut fused = Vec::new();
    while let Some(r) = tasks.join_next().await {
        let (hz, u, f) = r??;
        worst_hz = worst_hz.min(hz);
        uploads.extend(u);
        fused.extend(f);
    }
    uploads.sort_by(f64::total_cmp);
    fused.sort_by(f64::total_cmp);
    fleet.stop().await?;
    Ok((
        worst_hz,
        percentile(&uploads, 0.99),
        percentile(&fused, 0.99),
    ))
}

fn main() -> anyhow::Result<()> {
    let runtime = tokio::runtime::Runtime::new()?;
    runtime.block_on(async {
        latency().await?;
        let scan = Arc::new(scan_bytes());
        println!(
            "capacity: scans of {} points over REST at 10 Hz per vehicle, {} super-frame objects per vehicle at 10 Hz",
            scan.len() / 16,
            OBJECTS_PER_FRAME
        );
        let max: usize = std::env::var("TRACKD_BENCH_MAX_VEHICLES")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(32);
        let mut n = 2;
        while n <= max {
            let (hz, upload_p99, fused_p99) = capacity(n, 5, scan.clone()).await?;
            println!(
                "  {n:>3} vehicles: worst {hz:.2} Hz, upload p99 {upload_p99:.1} ms, fleet view p99 {fused_p99:.1} ms"
            );
            if hz < 9.5 {
                println!("  -> one machine holds fewer than {n} vehicles at 10 Hz");
                break;
            }
            n *= 2;
        }
        Ok(())
    })
}
