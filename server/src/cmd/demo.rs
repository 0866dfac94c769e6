//! `trackd demo`: a simulated multi-vehicle drive through the whole service, on loopback.
//!
//! Simulates the drive in memory (trackd-sim), starts a Zenoh router and one service per
//! vehicle on free loopback ports, streams each vehicle's scans (with its OXTS packets) into
//! its service over REST at the scan rate, and prints a live summary with the URLs to query.

use std::{
    sync::{
        Arc,
        atomic::{AtomicU64, AtomicUsize, Ordering},
    },
    time::{Duration, Instant},
};

use anyhow::Context;
use trackd_client::{Client, ClientError, ScanBody, Uploaded};
use trackd_perception::wire;
use trackd_service::{local_fleet::LocalFleet, settings::Settings};
use trackd_sim::{Scenario, SimConfig, Simulation, ego::Mount};

/// Flags of `trackd demo`.
#[derive(clap::Args)]
pub struct Args {
    /// Vehicles in the fleet.
    #[arg(long, default_value_t = 2)]
    vehicles: usize,
    /// Scans per vehicle (10 per second of drive).
    #[arg(long, default_value_t = 100)]
    frames: usize,
    /// Scenario: paper, intersection, highway, crowd.
    #[arg(long, default_value = "paper")]
    scenario: Scenario,
    /// Random seed of the world.
    #[arg(long, default_value_t = 7)]
    seed: u64,
    /// Scans per second per vehicle.
    #[arg(long, default_value_t = 10.0)]
    rate: f64,
    /// Replay the drive again and again (time shifted) until Ctrl-C.
    #[arg(long = "loop")]
    repeat: bool,
}

/// What each vehicle's uploader reports to the summary.
#[derive(Default)]
struct Progress {
    frame: AtomicU64,
    uploaded: AtomicU64,
    tracks: AtomicUsize,
}

/// Runs `trackd demo`.
pub fn run(args: Args) -> anyhow::Result<()> {
    anyhow::ensure!(args.vehicles >= 1, "--vehicles must be at least 1");
    anyhow::ensure!(args.frames >= 1, "--frames must be at least 1");
    anyhow::ensure!(args.rate > 0.0, "--rate must be positive");
    eprintln!(
        "trackd demo: simulating the {} scenario with {} vehicles, {} scans each…",
        args.scenario.name(),
        args.vehicles,
        args.frames
    );
    let sim = Arc::new(
        Simulation::new(
            &SimConfig::new(args.scenario, args.frames, args.seed).with_vehicles(args.vehicles),
        )
        .context("building the simulated world")?,
    );
    let runtime = tokio::runtime::Runtime::new()?;
    runtime.block_on(drive(args, sim))
}

fn base_settings(sim: &Simulation) -> Settings {
    let mut s = Settings::default();
    let o = sim.world().origin;
    s.fleet.origin = Some([o.lat, o.lon, o.alt]);
    s.vehicle.set_imu_to_velo(&Mount::kitti().imu_to_velo);
    s
}

async fn drive(args: Args, sim: Arc<Simulation>) -> anyhow::Result<()> {
    let ids: Vec<String> = (1..=args.vehicles).map(|i| format!("car-{i}")).collect();
    let fleet = LocalFleet::start(&ids, &base_settings(&sim)).await?;
    println!("router: tcp/127.0.0.1:{}", fleet.router_port);
    for (id, s) in ids.iter().zip(&fleet.services) {
        println!(
            "{id}: {url}/v1/tracks  {url}/v1/fleet/objects  {url}/v1/stream  {url}/metrics",
            url = s.url()
        );
    }
    let clients: Vec<Client> = fleet
        .services
        .iter()
        .map(|s| Client::new(&s.url(), None))
        .collect();
    let progress: Vec<Arc<Progress>> = ids.iter().map(|_| Arc::default()).collect();
    let started = Instant::now();

    let mut uploaders = tokio::task::JoinSet::new();
    for (v, client) in clients.iter().enumerate() {
        let (sim, client, progress) = (sim.clone(), client.clone(), progress[v].clone());
        let (frames, rate, repeat) = (args.frames, args.rate, args.repeat);
        uploaders.spawn(async move {
            upload_drive(sim, v, frames, rate, repeat, client, progress).await
        });
    }

    let mut ticker = tokio::time::interval(Duration::from_secs(1));
    let stop = super::serve::shutdown_signal();
    tokio::pin!(stop);
    let mut last = vec![0u64; ids.len()];
    loop {
        tokio::select! {
            _ = &mut stop => break,
            done = uploaders.join_next() => match done {
                None => break,
                Some(result) => result.context("uploader task")??,
            },
            _ = ticker.tick() => {
                print_summary(&ids, &clients, &progress, &mut last, started).await;
            }
        }
    }
    print_summary(&ids, &clients, &progress, &mut last, started).await;
    uploaders.abort_all();
    fleet.stop().await?;
    println!(
        "demo finished after {:.1} s",
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Streams vehicle `v`'s scans into its service at `rate`; the ray casting runs on blocking
/// threads one scan ahead.
async fn upload_drive(
    sim: Arc<Simulation>,
    v: usize,
    frames: usize,
    rate: f64,
    repeat: bool,
    client: Client,
    progress: Arc<Progress>,
) -> anyhow::Result<()> {
    let period = Duration::from_secs_f64(1.0 / rate);
    let lap_seconds = sim.timestamp(v, frames - 1) + period.as_secs_f64();
    let mut lap = 0u32;
    loop {
        let mut next = Instant::now();
        for i in 0..frames {
            let s = sim.clone();
            let frame = tokio::task::spawn_blocking(move || s.frame(v, i)).await?;
            tokio::time::sleep_until(next.into()).await;
            next += period;
            let scan = trackd_proto::Scan {
                version: trackd_proto::SCHEMA_VERSION,
                timestamp: frame.timestamp + f64::from(lap) * lap_seconds,
                points: wire::pack_xyzi(&frame.points),
                ego: Some(trackd_proto::scan::Ego::Oxts((&frame.oxts).into())),
            };
            let answer = loop {
                match client.upload(ScanBody::Protobuf(scan.clone()), false).await {
                    Err(ClientError::Busy { retry_after_s }) => {
                        tokio::time::sleep(Duration::from_secs(retry_after_s)).await;
                    }
                    other => break other,
                }
            };
            match answer {
                Ok(Uploaded::Processed(p)) => {
                    progress.frame.store(p.frame, Ordering::Relaxed);
                    progress
                        .tracks
                        .store(p.tracks.tracks.len(), Ordering::Relaxed);
                }
                Ok(Uploaded::Queued(_)) => {}
                Err(e) => tracing::warn!(vehicle = v, frame = i, "upload failed: {e}"),
            }
            progress.uploaded.fetch_add(1, Ordering::Relaxed);
        }
        if !repeat {
            return Ok(());
        }
        lap += 1;
    }
}

async fn print_summary(
    ids: &[String],
    clients: &[Client],
    progress: &[Arc<Progress>],
    last: &mut [u64],
    started: Instant,
) {
    println!(
        "[{:>5.1} s] {:<8} {:>6} {:>6} {:>7} {:>9}",
        started.elapsed().as_secs_f64(),
        "vehicle",
        "frame",
        "Hz",
        "tracks",
        "from fleet"
    );
    for (i, id) in ids.iter().enumerate() {
        let uploaded = progress[i].uploaded.load(Ordering::Relaxed);
        let hz = uploaded.saturating_sub(last[i]);
        last[i] = uploaded;
        let learned = match clients[i].objects().await {
            Ok(o) => o
                .objects
                .iter()
                .filter(|o| !o.sources.iter().any(|s| s == id))
                .count()
                .to_string(),
            Err(_) => "-".into(),
        };
        println!(
            "          {:<8} {:>6} {:>6} {:>7} {:>9}",
            id,
            progress[i].frame.load(Ordering::Relaxed),
            hz,
            progress[i].tracks.load(Ordering::Relaxed),
            learned
        );
    }
}
