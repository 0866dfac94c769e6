//! What a simulated point hit: the ground truth of every return.

/// The ground-truth source of one LiDAR return.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PointLabel {
    /// The road or terrain surface.
    Ground,
    /// Static structure: buildings, walls, poles, trees, guard rails, furniture.
    Static,
    /// An object of the ground truth (vehicle, cyclist, pedestrian), by its global id.
    Object(u32),
}

impl PointLabel {
    /// The object id, if the point is on an object.
    pub fn object_id(&self) -> Option<u32> {
        match self {
            Self::Object(id) => Some(*id),
            _ => None,
        }
    }

    /// Whether the point is on the ground.
    pub fn is_ground(&self) -> bool {
        matches!(self, Self::Ground)
    }
}
