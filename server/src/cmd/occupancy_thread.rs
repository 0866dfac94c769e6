//! `trackd run`'s occupancy map on a thread of its own: each scan's update overlaps the
//! pipeline's work on the next scans (the map feeds nothing the tracker reads).

use std::sync::mpsc;
use std::thread::JoinHandle;
use std::time::Instant;

use anyhow::{Context, anyhow};
use trackd_perception::occupancy::{OccupancyConfig, OccupancyMap, OccupancyScan};

/// Scans queued for the thread before the pipeline waits for it.
const QUEUE: usize = 2;

/// What the thread gives back: the map, and each scan's integration time.
pub struct OccupancyResult {
    /// The map of every scan sent.
    pub map: OccupancyMap,
    /// (scan index, milliseconds) of each integrated scan, in order.
    pub timings: Vec<(usize, f64)>,
}

/// An occupancy map being built on its own thread.
pub struct OccupancyThread {
    scans: mpsc::SyncSender<(usize, OccupancyScan)>,
    worker: JoinHandle<OccupancyResult>,
}

impl OccupancyThread {
    /// Starts the thread with an empty map.
    pub fn spawn(config: OccupancyConfig) -> anyhow::Result<Self> {
        let (scans, queued) = mpsc::sync_channel::<(usize, OccupancyScan)>(QUEUE);
        let worker = std::thread::Builder::new()
            .name("occupancy".into())
            .spawn(move || {
                let mut map = OccupancyMap::new(config);
                let mut timings = Vec::new();
                for (index, scan) in queued {
                    let started = Instant::now();
                    map.integrate(scan.sensor, &scan.obstacles, &scan.ground);
                    timings.push((index, started.elapsed().as_secs_f64() * 1e3));
                }
                OccupancyResult { map, timings }
            })
            .context("starting the occupancy thread")?;
        Ok(Self { scans, worker })
    }

    /// Queues scan `index`'s update; waits while the thread is [`QUEUE`] scans behind.
    pub fn integrate(&self, index: usize, scan: OccupancyScan) -> anyhow::Result<()> {
        self.scans
            .send((index, scan))
            .map_err(|_| anyhow!("the occupancy thread has stopped"))
    }

    /// Waits until every queued scan is integrated.
    pub fn finish(self) -> anyhow::Result<OccupancyResult> {
        drop(self.scans);
        self.worker
            .join()
            .map_err(|_| anyhow!("the occupancy thread panicked"))
    }
}
