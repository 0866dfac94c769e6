//! `trackd run`'s front half on a thread of its own: each scan is read and segmented (pose to
//! DBSCAN, and the clusters' VFHs) a few scans ahead, while the main thread tracks the ones
//! before.

use std::sync::mpsc;
use std::time::Instant;

use anyhow::Context;
use trackd_dataset::Source;
use trackd_perception::PipelineError;
use trackd_perception::pipeline::{Segmentation, Segmented};

/// Scans segmented ahead of the tracking thread.
const AHEAD: usize = 3;

/// What the thread made of scan `index`.
pub struct SegmentedScan {
    /// The scan's index in the input.
    pub index: usize,
    /// The segmented scan, or why the pipeline refused it.
    pub result: Result<Segmented, PipelineError>,
    /// Milliseconds spent segmenting it.
    pub ms: f64,
}

/// Scans being read and segmented on their own thread, in order.
pub struct SegmentThread {
    scans: mpsc::Receiver<anyhow::Result<SegmentedScan>>,
    spare: mpsc::Sender<Segmented>,
}

impl SegmentThread {
    /// Starts reading and segmenting the first `frames` scans of `source`.
    pub fn spawn(
        source: Source,
        frames: usize,
        mut segmentation: Segmentation,
    ) -> anyhow::Result<Self> {
        let (sender, scans) = mpsc::sync_channel(AHEAD);
        let (spare, spares) = mpsc::channel::<Segmented>();
        std::thread::Builder::new()
            .name("segmentation".into())
            .spawn(move || {
                let mut buffer = None;
                for index in 0..frames {
                    let frame = match source.frame(index) {
                        Ok(frame) => frame,
                        Err(e) => {
                            let name = scan_name(&source, index);
                            let _ = sender.send(
                                Err(e).with_context(|| format!("reading scan {index} ({name})")),
                            );
                            return;
                        }
                    };
                    let mut scan = buffer
                        .take()
                        .or_else(|| spares.try_recv().ok())
                        .unwrap_or_default();
                    let started = Instant::now();
                    let result = match segmentation.segment(&frame, &mut scan) {
                        Ok(()) => Ok(scan),
                        Err(e) => {
                            buffer = Some(scan);
                            Err(e)
                        }
                    };
                    let ms = started.elapsed().as_secs_f64() * 1e3;
                    if sender
                        .send(Ok(SegmentedScan { index, result, ms }))
                        .is_err()
                    {
                        return;
                    }
                }
            })
            .context("starting the segmentation thread")?;
        Ok(Self { scans, spare })
    }

    /// The segmented scans, in order; ends after the last scan or a read error.
    pub fn scans(&self) -> impl Iterator<Item = anyhow::Result<SegmentedScan>> + '_ {
        self.scans.iter()
    }

    /// Hands a tracked scan's buffers back, for a later scan.
    pub fn recycle(&self, scan: Segmented) {
        // The thread may have finished: the buffers are then simply dropped.
        let _ = self.spare.send(scan);
    }
}

/// The file name of scan `i`, for error messages.
pub fn scan_name(source: &Source, i: usize) -> String {
    source
        .scan_path(i)
        .map(|p| p.display().to_string())
        .unwrap_or_default()
}
