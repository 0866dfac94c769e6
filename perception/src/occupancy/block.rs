//! Dense 8×8×8 blocks of voxels, the unit the occupancy map allocates.

/// Voxels along one edge of a block.
pub(super) const BLOCK_SIDE: usize = 8;

/// One voxel: its log-odds (NaN while unknown), the last scan that touched it, and the scan
/// since which it has been occupied.
#[derive(Clone, Copy, Debug)]
pub(super) struct Voxel {
    pub log_odds: f32,
    pub stamp: u32,
    pub since: u32,
}

impl Default for Voxel {
    fn default() -> Self {
        Self {
            log_odds: f32::NAN,
            stamp: 0,
            since: 0,
        }
    }
}

impl Voxel {
    /// Whether any scan has seen this voxel.
    pub fn is_known(&self) -> bool {
        !self.log_odds.is_nan()
    }

    /// Maximum-likelihood occupancy, as OctoMap decides it (log-odds ≥ 0).
    pub fn is_occupied(&self) -> bool {
        self.log_odds >= 0.0
    }

    /// The log-odds, 0 (probability ½) while unknown.
    pub fn known_log_odds(&self) -> f32 {
        if self.is_known() { self.log_odds } else { 0.0 }
    }
}

/// A block of `BLOCK_SIDE³` voxels, x fastest.
#[derive(Clone)]
pub(super) struct Block {
    pub voxels: Box<[Voxel; BLOCK_SIDE * BLOCK_SIDE * BLOCK_SIDE]>,
}

impl Default for Block {
    fn default() -> Self {
        Self {
            voxels: Box::new([Voxel::default(); BLOCK_SIDE * BLOCK_SIDE * BLOCK_SIDE]),
        }
    }
}

impl Block {
    /// Voxels with a known state.
    pub fn known(&self) -> usize {
        self.voxels.iter().filter(|v| v.is_known()).count()
    }
}
