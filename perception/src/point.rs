//! The point type every stage reads and writes.

use bytemuck::{Pod, Zeroable};

/// One LiDAR return: position in metres and reflectance (0..1 for KITTI).
///
/// `#[repr(C)]` and `Pod`, so a KITTI `.bin` file (N x 4 little-endian f32) is a `&[Point]`.
#[repr(C)]
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable, serde::Serialize, serde::Deserialize,
)]
pub struct Point {
    /// Metres (Velodyne: forward).
    pub x: f32,
    /// Metres (Velodyne: left).
    pub y: f32,
    /// Metres (Velodyne: up).
    pub z: f32,
    /// Reflectance; 0 when the source has none.
    pub intensity: f32,
}

impl Point {
    /// A point with the given coordinates and intensity.
    pub const fn new(x: f32, y: f32, z: f32, intensity: f32) -> Self {
        Self { x, y, z, intensity }
    }

    /// The position as an array.
    pub const fn xyz(&self) -> [f32; 3] {
        [self.x, self.y, self.z]
    }

    /// Squared distance from the origin.
    pub fn norm_squared(&self) -> f32 {
        self.x * self.x + self.y * self.y + self.z * self.z
    }

    /// Whether all four values are finite.
    pub fn is_finite(&self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite() && self.intensity.is_finite()
    }
}
