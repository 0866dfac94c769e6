//! Ground truth as the scoring sees it, whatever it was read from: per frame the objects that
//! count, and what excuses a hypothesis from being a false positive.

mod candidates;
pub mod kitti;
pub mod oriented_box;
pub mod sim;
pub mod tracklets;

use crate::view::{ImageBox, View};

/// One labelled object in one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct GtObject {
    /// Identity, stable across frames.
    pub id: u64,
    /// Class name as labelled (e.g. `Car`, `cyclist`); only "cyclist" changes the scoring.
    pub class: String,
    /// Box centre in the Velodyne frame of that frame (metres).
    pub centre: [f64; 3],
}

/// The ground truth of one frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GtFrame {
    /// Frame index.
    pub frame: u32,
    /// Objects that count: each one unmatched is a miss.
    pub objects: Vec<GtObject>,
    /// "Don't care" objects (simulated drives: too few points or too far): a hypothesis that
    /// the per-frame assignment pairs with one of them is neither true nor false positive.
    pub dont_care: Vec<GtObject>,
    /// Boxes near which hypotheses are ignored (KITTI: Misc boxes and counted boxes dropped for
    /// too few points or outside view or range): a hypothesis within the match threshold of one
    /// is ignored unless it is within the match threshold of a counted object.
    pub ignore_near: Vec<GtObject>,
    /// Image regions in which hypotheses are ignored (KITTI DontCare boxes), unless within the
    /// match threshold of a counted object.
    pub ignore_regions: Vec<ImageBox>,
}

/// The ground truth of one sequence.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GroundTruth {
    /// Every known frame of the sequence (frames without objects included), by frame index.
    pub frames: Vec<GtFrame>,
    /// The labelled region: hypotheses outside it are not scored. `None` when everything is
    /// labelled (simulated drives).
    pub view: Option<View>,
    /// What the reader left out of `frames`.
    pub filtering: GtFiltering,
}

/// Labelled objects that a reader dropped (KITTI: they become ignore-near boxes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct GtFiltering {
    /// Boxes of counted classes outside the labelled view (camera image, BEV range).
    pub outside_view: usize,
    /// Boxes of counted classes in view with too few LiDAR points inside.
    pub too_few_points: usize,
    /// Whether LiDAR points were counted (false when the scans were not available).
    pub points_checked: bool,
}

impl GroundTruth {
    /// Counted objects over all frames.
    pub fn num_objects(&self) -> usize {
        self.frames.iter().map(|f| f.objects.len()).sum()
    }
}
