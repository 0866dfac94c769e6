//! `trackctl upload`: stream scans to a service at a rate, with progress.

use std::{
    path::Path,
    time::{Duration, Instant},
};

use indicatif::{ProgressBar, ProgressStyle};
use trackd_client::{Client, ClientError, ScanBody, Uploaded};
use trackd_dataset::{OpenOptions, open};
use trackd_perception::{Ego, Frame, wire};

/// A frame as the protobuf `Scan` the service takes.
pub fn scan_of(frame: &Frame) -> trackd_proto::Scan {
    trackd_proto::Scan {
        version: trackd_proto::SCHEMA_VERSION,
        timestamp: frame.timestamp,
        points: wire::pack_xyzi(&frame.points),
        ego: match &frame.ego {
            Ego::Oxts(o) => Some(trackd_proto::scan::Ego::Oxts(o.into())),
            Ego::Pose(p) => Some(trackd_proto::scan::Ego::Pose(wire::pose_to_proto(p))),
            Ego::None => None,
        },
    }
}

/// Uploads every scan of `path` (a scan file, a folder of scans or a KITTI drive).
pub async fn run(
    client: &Client,
    path: &Path,
    rate: f64,
    queue_only: bool,
    json: bool,
) -> anyhow::Result<()> {
    let source = open(path, &OpenOptions::default())?;
    let n = source.len();
    let bar = ProgressBar::new(n as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} scans {per_sec} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let period = (rate > 0.0).then(|| Duration::from_secs_f64(1.0 / rate));
    let start = Instant::now();
    for i in 0..n {
        if let Some(p) = period {
            let due = start + p * i as u32;
            tokio::time::sleep_until(due.into()).await;
        }
        let scan = scan_of(&source.frame(i)?);
        let result = loop {
            match client
                .upload(ScanBody::Protobuf(scan.clone()), queue_only)
                .await
            {
                Err(ClientError::Busy { retry_after_s }) => {
                    bar.set_message(format!("service busy, retrying in {retry_after_s} s"));
                    tokio::time::sleep(Duration::from_secs(retry_after_s)).await;
                }
                other => break other?,
            }
        };
        match result {
            Uploaded::Processed(p) => {
                if json {
                    bar.suspend(|| println!("{}", serde_json::to_string(&p).unwrap_or_default()));
                }
                bar.set_message(format!(
                    "frame {} · {} tracks",
                    p.frame,
                    p.tracks.tracks.len()
                ));
            }
            Uploaded::Queued(q) => {
                bar.set_message(format!(
                    "scan {} queued (depth {})",
                    q.scan_id, q.queue_depth
                ));
            }
        }
        bar.inc(1);
    }
    bar.finish();
    eprintln!(
        "uploaded {n} scans from {} in {:.1} s",
        path.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
