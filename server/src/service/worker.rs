//! The perception worker: one thread owns the (synchronous) pipeline and takes scans from a
//! bounded queue, so the async side never blocks on it.

use std::{
    panic::{AssertUnwindSafe, catch_unwind},
    sync::{Arc, Mutex},
    thread::JoinHandle,
};

use tokio::sync::{broadcast, mpsc, oneshot, watch};
use trackd_client::api;
use trackd_perception::{Frame, Pipeline};
use trackd_proto::SuperFrame;

use super::{
    clock::Clock,
    history::History,
    metrics::Metrics,
    state::{Latest, lock},
    views,
};

/// What the worker answers a synchronous upload.
pub type Reply = Result<api::ScanProcessed, String>;

/// One accepted scan.
pub struct Job {
    /// The upload's id.
    pub scan_id: u64,
    /// The scan.
    pub frame: Frame,
    /// Where to send the result (synchronous uploads).
    pub reply: Option<oneshot::Sender<Reply>>,
}

/// Where the worker puts its results.
pub struct Outputs {
    /// The vehicle id.
    pub vehicle: String,
    /// The service clock.
    pub clock: Clock,
    /// Latest state.
    pub latest: watch::Sender<Arc<Latest>>,
    /// Per-frame tracks for SSE.
    pub events: broadcast::Sender<Arc<api::Tracks>>,
    /// Track positions.
    pub history: Arc<Mutex<History>>,
    /// Super frames to publish.
    pub superframes: mpsc::Sender<SuperFrame>,
    /// Metrics.
    pub metrics: Arc<Metrics>,
}

/// Starts the worker; it ends when every queue sender is dropped.
pub fn spawn(
    pipeline: Arc<Mutex<Pipeline>>,
    mut queue: mpsc::Receiver<Job>,
    out: Outputs,
) -> std::io::Result<JoinHandle<()>> {
    std::thread::Builder::new()
        .name(format!("perception-{}", out.vehicle))
        .spawn(move || {
            while let Some(job) = queue.blocking_recv() {
                out.metrics.queue_depth.set(queue.len() as i64);
                let reply = process(&pipeline, job.scan_id, job.frame, &out);
                if let Some(tx) = job.reply {
                    // The uploader may have given up waiting (timeout): the frame still counts.
                    let _ = tx.send(reply);
                }
            }
        })
}

fn process(pipeline: &Mutex<Pipeline>, scan_id: u64, frame: Frame, out: &Outputs) -> Reply {
    let points = frame.points.len();
    let started = std::time::Instant::now();
    let result = catch_unwind(AssertUnwindSafe(|| lock(pipeline).process(frame)));
    let output = match result {
        Ok(Ok(output)) => output,
        Ok(Err(e)) => {
            out.metrics.count_drop("pipeline_error");
            tracing::warn!(scan_id, "scan refused by the pipeline: {e}");
            return Err(e.to_string());
        }
        Err(_) => {
            out.metrics.count_drop("pipeline_panic");
            tracing::error!(
                scan_id,
                "the pipeline panicked on this scan; it was skipped"
            );
            return Err("internal error: the pipeline failed on this scan".into());
        }
    };
    let m = &out.metrics;
    m.frames.inc();
    m.frame_ms.observe(started.elapsed().as_secs_f64() * 1000.0);
    for &(stage, ms) in &output.timings.stages {
        m.stage_ms
            .get_or_create(&vec![("stage", stage)])
            .observe(ms);
    }
    m.tracks.set(output.tracks.len() as i64);

    let tracks = views::tracks(&out.vehicle, &output);
    lock(&out.history).record(output.index, output.timestamp, &output.tracks);
    let made_superframe = output.superframe.is_some();
    let superframe = output.superframe.map(Arc::new);
    if let Some(sf) = &superframe
        && out.superframes.try_send(sf.as_ref().clone()).is_err()
    {
        m.count_drop("superframe_backlog");
    }
    let at_ms = out.clock.now_ms();
    out.latest.send_modify(|latest| {
        *latest = Arc::new(Latest {
            tracks: tracks.clone(),
            states: output.tracks,
            ego_xy: [
                output.ego_pose.translation.vector.x,
                output.ego_pose.translation.vector.y,
            ],
            at_ms: Some(at_ms),
            superframe: superframe.or_else(|| latest.superframe.clone()),
            frames: latest.frames + 1,
        });
    });
    // No subscriber is no error.
    let _ = out.events.send(Arc::new(tracks.clone()));
    Ok(api::ScanProcessed {
        scan_id,
        frame: output.index,
        points,
        timings: output
            .timings
            .stages
            .iter()
            .map(|&(stage, ms)| api::StageTime {
                stage: stage.to_string(),
                ms,
            })
            .collect(),
        superframe: made_superframe,
        tracks,
    })
}
