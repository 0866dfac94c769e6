//! What the tracker's synthetic tests share: clusters that all carry one uniform signature,
//! so that the tests exercise geometry and motion, not the VFH tests.

use trackd_perception::Point;
use trackd_perception::track::ClusterInput;
use trackd_perception::vfh::{BINS, Vfh};

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
