//! What the tracker's synthetic tests share: clusters that all carry one uniform signature,
//! so that the tests exercise geometry and motion, not the VFH tests.

use nalgebra::{Isometry3, Vector2};
use trackd_perception::track::{ClusterInput, Ground, ScanContext, TrackConfig, Tracker};
use trackd_perception::vfh::{BINS, Vfh};
use trackd_perception::{Point, TrackState};

/// A uniform signature.
pub const FLAT: Vfh = Vfh {
    bins: [1.0 / BINS as f32; BINS],
};

/// The clusters of `clouds`, each with [`FLAT`] as its signature and `cdf` (`FLAT.cdf()`) as
/// its cumulative distribution.
pub fn flat_clusters<'a>(clouds: &'a [Vec<Point>], cdf: &'a [f32; BINS]) -> Vec<ClusterInput<'a>> {
    clouds
        .iter()
        .map(|points| ClusterInput {
            points,
            vfh: &FLAT,
            cdf,
            surface_variation: 0.0,
        })
        .collect()
}

/// Runs `scans` scans at 10 Hz with the default config, scan `k` showing the one world-frame
/// cluster `cloud(k)` to a sensor 1.73 m above the origin (ground at z = 0, no range images);
/// returns, per scan, whether a track is reported.
#[allow(dead_code)] // Not every test that includes this module runs static scenes.
pub fn reported_per_scan(scans: u32, cloud: impl Fn(u32) -> Vec<Point>) -> Vec<bool> {
    reported_states_per_scan(scans, cloud)
        .iter()
        .map(|reported| !reported.is_empty())
        .collect()
}

/// As [`reported_per_scan`], but returns, per scan, the reported tracks' states.
#[allow(dead_code)] // Not every test that includes this module runs static scenes.
pub fn reported_states_per_scan(
    scans: u32,
    cloud: impl Fn(u32) -> Vec<Point>,
) -> Vec<Vec<TrackState>> {
    let mut tracker = Tracker::new(TrackConfig::default());
    let ground = Ground::horizontal(0.0);
    let cdf = FLAT.cdf();
    (0..scans)
        .map(|k| {
            let clouds = vec![cloud(k)];
            let scan = ScanContext {
                timestamp: f64::from(k) * 0.1,
                pose: Isometry3::translation(0.0, 0.0, 1.73),
                ground: &ground,
                range_limit: f64::INFINITY,
                views: None,
            };
            tracker.step(&scan, &flat_clusters(&clouds, &cdf));
            tracker.reported().map(|t| t.state()).collect()
        })
        .collect()
}

/// Per scan `k` of `reported`, the distance (m) from `truth(k)` to the nearest reported track's
/// centre; infinite when no track is reported.
#[allow(dead_code)] // Not every test that includes this module places its objects.
pub fn nearest_distances(
    reported: &[Vec<TrackState>],
    truth: impl Fn(usize) -> Vector2<f64>,
) -> Vec<f64> {
    reported
        .iter()
        .enumerate()
        .map(|(k, tracks)| {
            tracks
                .iter()
                .map(|t| (t.center.xy() - truth(k)).norm())
                .fold(f64::INFINITY, f64::min)
        })
        .collect()
}
