//! The pipeline's occupancy map, read off the worker's thread (the pipeline is locked for the
//! copy, so a read waits at most for the frame in progress).

use trackd_client::api;
use trackd_perception::occupancy::OccupancyMap;

use super::state::{AppState, lock};

/// Why no map can be given: the blocking read of the map failed (it panicked or was
/// cancelled at shutdown).
#[derive(Debug, thiserror::Error)]
#[error("reading the occupancy map failed: {0}")]
pub struct Unavailable(String);

async fn with_map<T: Send + 'static>(
    state: &AppState,
    read: impl FnOnce(&OccupancyMap) -> T + Send + 'static,
) -> Result<T, Unavailable> {
    let pipeline = state.pipeline.clone();
    tokio::task::spawn_blocking(move || {
        let guard = lock(&pipeline);
        read(guard.occupancy())
    })
    .await
    .map_err(|e| Unavailable(e.to_string()))
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
