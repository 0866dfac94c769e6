//! Capacity: N vehicle services on this machine (one router, explicit loopback endpoints, no
//! multicast scouting), each fed the real KITTI drive over REST at 10 Hz while the services
//! share their super frames with each other. Every upload is synchronous and in flight on its
//! own, so a slow service is not waited for: its queue fills and it refuses (429).

use std::{
    sync::Arc,
    time::{Duration, Instant},
};

use tokio::task::JoinSet;
use trackd_client::{Client, ClientError, Uploaded};
use trackd_service::local_fleet::LocalFleet;

use crate::base_settings;
use crate::drive::KittiDrive;
use crate::stats::{percentile, sorted};

/// Seconds between the uploads of one vehicle (10 Hz).
const PERIOD: Duration = Duration::from_millis(100);
/// The lowest processed rate that counts as keeping up with 10 Hz.
const SUSTAINED_HZ: f64 = 9.5;
/// Scans of the replay between the starting points of consecutive vehicles.
const REPLAY_OFFSET: u64 = 7;

/// What became of one upload.
enum Outcome {
    /// Processed: the time from sending to the answer, and when the answer came.
    Processed { latency: Duration, at: Instant },
    /// Refused with 429: the service's queue was full.
    Refused,
    /// Any other error.
    Failed(String),
}

/// One vehicle's uploads over a run.
pub struct VehicleTally {
    /// Vehicle id.
    pub id: String,
    /// Uploads sent.
    pub sent: usize,
    /// Upload → processed latency of each processed scan (ms).
    pub latencies_ms: Vec<f64>,
    /// Processed scans per second, from the first upload to the last answer.
    pub processed_hz: f64,
    /// Uploads refused with 429.
    pub refused: usize,
    /// Uploads that failed otherwise.
    pub failed: usize,
    /// The first failure's message.
    pub first_failure: Option<String>,
}

impl VehicleTally {
    /// Whether this vehicle was served at 10 Hz: every upload processed, none refused.
    pub fn sustained(&self) -> bool {
        self.refused == 0 && self.failed == 0 && self.processed_hz >= SUSTAINED_HZ
    }
}

/// The result of one run with N vehicles.
pub struct CapacityRun {
    /// The vehicles' tallies.
    pub vehicles: Vec<VehicleTally>,
}

impl CapacityRun {
    /// Whether every vehicle was served at 10 Hz.
    pub fn sustained(&self) -> bool {
        self.vehicles.iter().all(VehicleTally::sustained)
    }

    /// Prints one line for the run and one per vehicle.
    pub fn print(&self) {
        let n = self.vehicles.len();
        let latencies = sorted(
            self.vehicles
                .iter()
                .flat_map(|v| v.latencies_ms.iter().copied())
                .collect(),
        );
        let worst_hz = self
            .vehicles
            .iter()
            .map(|v| v.processed_hz)
            .fold(f64::INFINITY, f64::min);
        let refused: usize = self.vehicles.iter().map(|v| v.refused).sum();
        let failed: usize = self.vehicles.iter().map(|v| v.failed).sum();
        println!(
            "  {n} vehicle(s): slowest {worst_hz:.2} processed frames/s, {refused} refused, \
             {failed} failed, upload -> processed p50 {:.0} ms, p99 {:.0} ms: {}",
            percentile(&latencies, 0.5),
            percentile(&latencies, 0.99),
            if self.sustained() {
                "every vehicle at 10 Hz"
            } else {
                "NOT every vehicle at 10 Hz"
            }
        );
        for v in &self.vehicles {
            let own = sorted(v.latencies_ms.clone());
            println!(
                "      {}: sent {}, processed {} ({:.2}/s), refused {}, failed {}, \
                 p50 {:.0} ms, p99 {:.0} ms{}",
                v.id,
                v.sent,
                v.latencies_ms.len(),
                v.processed_hz,
                v.refused,
                v.failed,
                percentile(&own, 0.5),
                percentile(&own, 0.99),
                v.first_failure
                    .as_ref()
                    .map(|e| format!(" (first failure: {e})"))
                    .unwrap_or_default()
            );
        }
    }
}

/// Runs `n` vehicles for `seconds`, each fed `drive` at 10 Hz from its own point of the
/// replay and its own phase of the period.
pub async fn run(n: usize, seconds: u64, drive: Arc<KittiDrive>) -> anyhow::Result<CapacityRun> {
    let ids: Vec<String> = (0..n).map(|i| format!("v{i}")).collect();
    let fleet = LocalFleet::start(&ids, &base_settings()).await?;
    let start = Instant::now() + PERIOD;
    let mut feeds = JoinSet::new();
    for (i, (service, id)) in fleet.services.iter().zip(&ids).enumerate() {
        let client = Client::new(&service.url(), None);
        let first = start + PERIOD.mul_f64(i as f64 / n as f64);
        feeds.spawn(feed(
            client,
            id.clone(),
            drive.clone(),
            first,
            i as u64 * REPLAY_OFFSET,
            Duration::from_secs(seconds),
        ));
    }
    let mut vehicles = Vec::with_capacity(n);
    while let Some(tally) = feeds.join_next().await {
        vehicles.push(tally?);
    }
    vehicles.sort_by(|a, b| a.id.cmp(&b.id));
    fleet.stop().await?;
    Ok(CapacityRun { vehicles })
}

/// Feeds one service at 10 Hz for `window` from `first`, starting at scan `replay_start` of
/// the replay, and tallies what became of each upload.
async fn feed(
    client: Client,
    id: String,
    drive: Arc<KittiDrive>,
    first: Instant,
    replay_start: u64,
    window: Duration,
) -> VehicleTally {
    let mut uploads = JoinSet::new();
    let mut next = first;
    let mut k = replay_start;
    while next < first + window {
        tokio::time::sleep_until(next.into()).await;
        let client = client.clone();
        let body = drive.upload(k);
        uploads.spawn(async move {
            let sent = Instant::now();
            match client.upload(body, false).await {
                Ok(Uploaded::Processed(_)) => Outcome::Processed {
                    latency: sent.elapsed(),
                    at: Instant::now(),
                },
                Ok(Uploaded::Queued(q)) => {
                    Outcome::Failed(format!("scan {} queued, not processed", q.scan_id))
                }
                Err(ClientError::Busy { .. }) => Outcome::Refused,
                Err(e) => Outcome::Failed(e.to_string()),
            }
        });
        next += PERIOD;
        k += 1;
    }
    let mut tally = VehicleTally {
        id,
        sent: uploads.len(),
        latencies_ms: Vec::new(),
        processed_hz: 0.0,
        refused: 0,
        failed: 0,
        first_failure: None,
    };
    let mut last_answer = first;
    while let Some(outcome) = uploads.join_next().await {
        match outcome {
            Ok(Outcome::Processed { latency, at }) => {
                tally.latencies_ms.push(latency.as_secs_f64() * 1000.0);
                last_answer = last_answer.max(at);
            }
            Ok(Outcome::Refused) => tally.refused += 1,
            Ok(Outcome::Failed(e)) => {
                tally.failed += 1;
                tally.first_failure.get_or_insert(e);
            }
            Err(e) => {
                tally.failed += 1;
                tally.first_failure.get_or_insert(e.to_string());
            }
        }
    }
    // The first upload went out at `first`; a rate over at least one period.
    let span = (last_answer - first).max(PERIOD).as_secs_f64();
    tally.processed_hz = tally.latencies_ms.len() as f64 / span;
    tally
}
