//! Prometheus metrics of one service (`GET /metrics`).

use prometheus_client::{
    encoding::text::encode,
    metrics::{
        counter::Counter,
        family::Family,
        gauge::Gauge,
        histogram::{Histogram, exponential_buckets},
    },
    registry::Registry,
};

/// Labels: `(name, value)` pairs with static names and values.
type Labels = Vec<(&'static str, &'static str)>;

fn latency_histogram() -> Histogram {
    // 0.05 ms … ~1.6 s.
    Histogram::new(exponential_buckets(0.05, 2.0, 16))
}

/// Every metric the service exports.
pub struct Metrics {
    registry: Registry,
    /// Frames the pipeline processed.
    pub frames: Counter,
    /// Scans accepted into the queue.
    pub scans_accepted: Counter,
    /// Uploads refused, by reason (`queue_full`, `bad_request`, `unsupported_media_type`,
    /// `too_large`, `unauthorized`).
    pub scans_rejected: Family<Labels, Counter>,
    /// Accepted scans that did not yield a frame, or results lost, by reason
    /// (`pipeline_error`, `pipeline_panic`, `superframe_backlog`, `sse_lagged`).
    pub drops: Family<Labels, Counter>,
    /// Per-stage wall time (ms).
    pub stage_ms: Family<Labels, Histogram>,
    /// Whole-frame wall time in the worker (ms).
    pub frame_ms: Histogram,
    /// Scans waiting in the queue.
    pub queue_depth: Gauge,
    /// Confirmed tracks after the latest frame.
    pub tracks: Gauge,
    /// Zenoh messages by direction (`in`, `out`).
    pub zenoh_messages: Family<Labels, Counter>,
    /// Zenoh messages refused, by reason.
    pub zenoh_rejected: Family<Labels, Counter>,
    /// Super frame arrival → fused view (ms): how long a remote object takes to appear.
    pub fusion_lag_ms: Histogram,
}

impl Default for Metrics {
    fn default() -> Self {
        let mut registry = Registry::with_prefix("trackd");
        let m = Self {
            frames: Counter::default(),
            scans_accepted: Counter::default(),
            scans_rejected: Family::default(),
            drops: Family::default(),
            stage_ms: Family::new_with_constructor(latency_histogram),
            frame_ms: latency_histogram(),
            queue_depth: Gauge::default(),
            tracks: Gauge::default(),
            zenoh_messages: Family::default(),
            zenoh_rejected: Family::default(),
            fusion_lag_ms: latency_histogram(),
            registry: Registry::default(),
        };
        registry.register("frames", "Frames processed", m.frames.clone());
        registry.register(
            "scans_accepted",
            "Scans accepted into the queue",
            m.scans_accepted.clone(),
        );
        registry.register(
            "scans_rejected",
            "Uploads refused, by reason",
            m.scans_rejected.clone(),
        );
        registry.register(
            "drops",
            "Accepted work that yielded nothing, by reason",
            m.drops.clone(),
        );
        registry.register(
            "stage_latency_ms",
            "Wall time per pipeline stage (ms)",
            m.stage_ms.clone(),
        );
        registry.register(
            "frame_latency_ms",
            "Wall time per frame in the worker (ms)",
            m.frame_ms.clone(),
        );
        registry.register("queue_depth", "Scans waiting", m.queue_depth.clone());
        registry.register("tracks", "Confirmed tracks", m.tracks.clone());
        registry.register(
            "zenoh_messages",
            "Zenoh messages by direction",
            m.zenoh_messages.clone(),
        );
        registry.register(
            "zenoh_rejected",
            "Zenoh messages refused, by reason",
            m.zenoh_rejected.clone(),
        );
        registry.register(
            "fleet_ingest_latency_ms",
            "Super frame publish to fused-view update (ms, Zenoh timestamps)",
            m.fusion_lag_ms.clone(),
        );
        Self { registry, ..m }
    }
}

impl Metrics {
    /// Counts a refused upload.
    pub fn reject_scan(&self, reason: &'static str) {
        self.scans_rejected
            .get_or_create(&vec![("reason", reason)])
            .inc();
    }

    /// Counts a drop.
    pub fn count_drop(&self, reason: &'static str) {
        self.drops.get_or_create(&vec![("reason", reason)]).inc();
    }

    /// Counts a Zenoh message in or out.
    pub fn zenoh(&self, direction: &'static str) {
        self.zenoh_messages
            .get_or_create(&vec![("direction", direction)])
            .inc();
    }

    /// Counts a refused Zenoh message.
    pub fn zenoh_reject(&self, reason: &'static str) {
        self.zenoh_rejected
            .get_or_create(&vec![("reason", reason)])
            .inc();
    }

    /// The Prometheus text exposition.
    pub fn render(&self) -> String {
        let mut out = String::new();
        // Writing into a String cannot fail.
        let _ = encode(&mut out, &self.registry);
        out
    }
}
