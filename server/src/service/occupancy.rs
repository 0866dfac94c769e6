//! The pipeline's occupancy map, read off the worker's thread (the pipeline is locked for the
//! copy, so a read waits at most for the frame in progress).

use trackd_client::api;
use trackd_perception::{Pipeline, occupancy::OccupancyMap};

use super::state::{AppState, lock};

/// Why no map can be given.
#[derive(Debug, thiserror::Error)]
pub enum Unavailable {
    /// The pipeline has no occupancy map to share yet.
    #[error("this build's pipeline does not expose its occupancy map yet")]
    NotWired,
    /// The blocking read failed.
    #[error("reading the occupancy map failed: {0}")]
    Failed(String),
}

/// The map of `pipeline`. `Pipeline::occupancy` is not part of the pipeline's API yet; this is
/// the one call to connect when it lands.
fn map_of(_pipeline: &Pipeline) -> Option<&OccupancyMap> {
    None
}

async fn with_map<T: Send + 'static>(
    state: &AppState,
    read: impl FnOnce(&OccupancyMap) -> T + Send + 'static,
) -> Result<T, Unavailable> {
    let pipeline = state.pipeline.clone();
    tokio::task::spawn_blocking(move || {
        let guard = lock(&pipeline);
        map_of(&guard).map(read)
    })
    .await
    .map_err(|e| Unavailable::Failed(e.to_string()))?
    .ok_or(Unavailable::NotWired)
}

/// The map as an OctoMap `.bt` file.
pub async fn bt(state: &AppState) -> Result<Vec<u8>, Unavailable> {
    with_map(state, |map| map.to_bt()).await
}

/// A bird's-eye-view grid of half side `half_extent` metres around `center`.
pub async fn grid(
    state: &AppState,
    center: [f64; 2],
    half_extent: f64,
) -> Result<api::BevGrid, Unavailable> {
    with_map(state, move |map| {
        let g = map.bev(center, half_extent);
        api::BevGrid {
            min_x: g.min_x,
            min_y: g.min_y,
            cell: g.cell,
            width: g.width,
            height: g.height,
            cells: g.cells,
        }
    })
    .await
}
