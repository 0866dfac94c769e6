//! Dense 8×8×8 blocks of voxels, the unit the occupancy map allocates.

/// Voxels along one edge of a block.
pub(super) const BLOCK_SIDE: usize = 8;

/// Voxels in a block.
const BLOCK_VOXELS: usize = BLOCK_SIDE * BLOCK_SIDE * BLOCK_SIDE;

/// One voxel: its log-odds (NaN while unknown) and the scan since which it has been occupied.
#[derive(Clone, Copy, Debug)]
pub(super) struct Voxel {
    pub log_odds: f32,
    pub since: u32,
}

impl Default for Voxel {
    fn default() -> Self {
        Self {
            log_odds: f32::NAN,
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

/// One bit per voxel of a block (slot `i` is bit `i % 64` of word `i / 64`): the voxels the
/// scan being integrated has already updated. 64 bytes, so that the many rays crossing the
/// same voxels test them without touching the voxels themselves.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Touched([u64; BLOCK_VOXELS / 64]);

impl Touched {
    /// Marks `slot`; true when it was not marked yet.
    #[inline]
    pub fn mark(&mut self, slot: usize) -> bool {
        let (word, bit) = (&mut self.0[slot / 64], 1u64 << (slot % 64));
        let first = *word & bit == 0;
        *word |= bit;
        first
    }
}

/// A block of `BLOCK_SIDE³` voxels, x fastest, and which of them the current scan updated.
#[derive(Clone)]
pub(super) struct Block {
    pub voxels: Box<[Voxel; BLOCK_VOXELS]>,
    touched: Touched,
    /// The scan `touched` is about.
    touched_scan: u32,
}

impl Default for Block {
    fn default() -> Self {
        Self {
            voxels: Box::new([Voxel::default(); BLOCK_VOXELS]),
            touched: Touched::default(),
            touched_scan: 0,
        }
    }
}

impl Block {
    /// Voxels with a known state.
    pub fn known(&self) -> usize {
        self.voxels.iter().filter(|v| v.is_known()).count()
    }

    /// The voxels and which of them scan `scan` has updated so far (none, when the block was
    /// last touched by an earlier scan).
    pub fn for_scan(&mut self, scan: u32) -> (&mut [Voxel; BLOCK_VOXELS], &mut Touched) {
        if self.touched_scan != scan {
            self.touched_scan = scan;
            self.touched = Touched::default();
        }
        (&mut self.voxels, &mut self.touched)
    }
}
