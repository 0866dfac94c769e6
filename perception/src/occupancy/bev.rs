//! A bird's-eye view of the occupancy map: one cell per voxel column.

use serde::Serialize;

use super::block::Voxel;

/// What a bird's-eye-view cell holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[repr(u8)]
pub enum BevCell {
    /// No voxel of the column is known.
    Unknown = 0,
    /// Some voxel is free and none occupied.
    Free = 1,
    /// Some voxel of the column is occupied.
    Occupied = 2,
}

/// A square bird's-eye-view grid, row-major from (`min_x`, `min_y`), rows along +y.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BevGrid {
    /// World x of the grid's first column edge (metres).
    pub min_x: f64,
    /// World y of the grid's first row edge (metres).
    pub min_y: f64,
    /// Cell edge (metres).
    pub cell: f64,
    /// Cells per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width × height` cells: 0 unknown, 1 free, 2 occupied.
    pub cells: Vec<u8>,
}

impl BevGrid {
    /// The grid of the square of half side `half_extent` around `center`, from voxels.
    pub(super) fn from_voxels(
        resolution: f64,
        center: [f64; 2],
        half_extent: f64,
        voxels: impl Iterator<Item = ([i32; 3], Voxel)>,
    ) -> Self {
        let half_cells = (half_extent / resolution).ceil().max(0.0) as i64;
        let x0 = (center[0] / resolution).floor() as i64 - half_cells;
        let y0 = (center[1] / resolution).floor() as i64 - half_cells;
        let side = (2 * half_cells) as usize;
        let mut cells = vec![BevCell::Unknown as u8; side * side];
        for (key, voxel) in voxels {
            let (cx, cy) = (i64::from(key[0]) - x0, i64::from(key[1]) - y0);
            if cx < 0 || cy < 0 || cx >= side as i64 || cy >= side as i64 {
                continue;
            }
            let cell = &mut cells[cy as usize * side + cx as usize];
            let state = if voxel.is_occupied() {
                BevCell::Occupied
            } else {
                BevCell::Free
            };
            *cell = (*cell).max(state as u8);
        }
        Self {
            min_x: x0 as f64 * resolution,
            min_y: y0 as f64 * resolution,
            cell: resolution,
            width: side,
            height: side,
            cells,
        }
    }

    /// The cell holding world point (x, y), if inside the grid.
    pub fn at(&self, x: f64, y: f64) -> Option<BevCell> {
        let cx = ((x - self.min_x) / self.cell).floor();
        let cy = ((y - self.min_y) / self.cell).floor();
        if cx < 0.0 || cy < 0.0 || cx >= self.width as f64 || cy >= self.height as f64 {
            return None;
        }
        Some(match self.cells[cy as usize * self.width + cx as usize] {
            2 => BevCell::Occupied,
            1 => BevCell::Free,
            _ => BevCell::Unknown,
        })
    }
}
