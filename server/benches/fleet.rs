//! Fleet benchmark on loopback (not a test): `cargo bench -p trackd --bench fleet`.
//!
//! 1. Publish → fused latency ([`latency`]): a peer publishes a super frame with new objects;
//!    the time until they are in a service's `GET /v1/fleet/objects`.
//! 2. Capacity ([`capacity`]): for N = 1, 2, 3, … vehicle services on this machine, each fed
//!    the real KITTI tracking drive 0000 over REST at 10 Hz, the processed frames per second,
//!    refused (429) and failed uploads, and upload → processed latency per vehicle; the sweep
//!    stops at the first N (2 at the earliest) where some vehicle is not served at 10 Hz, and
//!    the capacity is the largest N where every vehicle was. It needs
//!    `../shared/data/kitti-tracking-0000-first40` and is skipped, loudly, without it.
//!
//! `TRACKD_BENCH_SECONDS` (default 15) sets each capacity run's length,
//! `TRACKD_BENCH_MAX_VEHICLES` (default 8) bounds the sweep, `TRACKD_BENCH_SKIP_LATENCY=1`
//! runs the capacity sweep alone.

#[path = "fleet/capacity.rs"]
mod capacity;
#[path = "fleet/drive.rs"]
mod drive;
#[path = "fleet/latency.rs"]
mod latency;
#[path = "fleet/stats.rs"]
mod stats;

use std::sync::Arc;

use trackd_service::settings::Settings;

/// The sweep runs at least this many vehicles, to show how the rate falls past the capacity.
const MIN_SWEEP: usize = 2;

/// The fleet's geodetic origin (KITTI's Karlsruhe).
const ORIGIN: [f64; 3] = [49.011_213_954_206, 8.422_885_922_889_3, 112.83];

/// Default settings with the fleet origin set.
fn base_settings() -> Settings {
    let mut s = Settings::default();
    s.fleet.origin = Some(ORIGIN);
    s
}

/// An unsigned integer from the environment variable `name`, else `default`.
fn env_or(name: &str, default: u64) -> anyhow::Result<u64> {
    match std::env::var(name) {
        Ok(v) => v
            .parse()
            .map_err(|_| anyhow::anyhow!("{name}={v:?}: expected a whole number")),
        Err(_) => Ok(default),
    }
}

/// The 1, 5 and 15 minute load averages (Linux), to tell what else the machine was doing.
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .map(|text| {
            text.split_whitespace()
                .take(3)
                .collect::<Vec<_>>()
                .join(" ")
        })
        .unwrap_or_else(|| "unknown".into())
}

/// The capacity sweep: N = 1, 2, … until some vehicle is not served at 10 Hz.
async fn capacity_sweep() -> anyhow::Result<()> {
    let Some(shared) = trackd_dataset::shared_data_dir("fleet capacity benchmark") else {
        println!(
            "capacity: SKIPPED, the real KITTI drive is missing (../shared/data or \
             TRACKD_SHARED_DATA): no capacity measured"
        );
        return Ok(());
    };
    let drive = Arc::new(drive::KittiDrive::read(&shared)?);
    let seconds = env_or("TRACKD_BENCH_SECONDS", 15)?;
    let max = env_or("TRACKD_BENCH_MAX_VEHICLES", 8)?;
    println!(
        "capacity: KITTI tracking 0000 ({} scans replayed forwards and backwards, {} points \
         in the first) over REST at 10 Hz per vehicle, {seconds} s per N, services sharing \
         super frames through one router",
        drive.len(),
        drive.points_per_scan()
    );
    let mut held = 0;
    for n in 1..=max as usize {
        println!("  load average before {n} vehicle(s): {}", load_average());
        let run = capacity::run(n, seconds, drive.clone()).await?;
        run.print();
        if run.sustained() {
            held = n;
        } else if n >= MIN_SWEEP {
            break;
        }
    }
    let bound = if held == max as usize {
        "at least "
    } else {
        ""
    };
    println!(
        "  -> this machine serves {bound}{held} vehicle(s) at 10 Hz with no refused upload \
         ({} cores)",
        std::thread::available_parallelism().map_or(0, usize::from)
    );
    Ok(())
}

fn main() -> anyhow::Result<()> {
    let runtime = tokio::runtime::Runtime::new()?;
    runtime.block_on(async {
        if env_or("TRACKD_BENCH_SKIP_LATENCY", 0)? == 0 {
            latency::run().await?;
        }
        capacity_sweep().await
    })
}
