//! The part of the world that the ground truth labels: KITTI labels only what the front camera
//! sees, within a BEV range. Anything outside it (GT or hypothesis) is not scored.

use nalgebra::{Matrix3x4, Matrix4, Point3, Vector4};

/// The labelled region: within `max_range` (BEV, from the Velodyne origin) and, when a camera
/// is given, inside its image with positive depth.
#[derive(Clone, Debug, PartialEq)]
pub struct View {
    /// Largest BEV distance from the Velodyne origin that is labelled (metres).
    pub max_range: f64,
    /// The camera whose image bounds the labels, if known.
    pub camera: Option<Camera>,
}

/// A pinhole camera looking at Velodyne-frame points (KITTI: the left colour camera, P2).
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Velodyne frame → rectified reference camera frame (KITTI: R0_rect · Tr_velo_to_cam).
    pub velo_to_rect: Matrix4<f64>,
    /// Projection of rectified-camera points into the image (KITTI: P2).
    pub projection: Matrix3x4<f64>,
    /// Image width in pixels.
    pub width: f64,
    /// Image height in pixels.
    pub height: f64,
}

/// A 2-D box in image pixels (KITTI DontCare regions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageBox {
    /// Left edge (pixels).
    pub left: f64,
    /// Top edge (pixels).
    pub top: f64,
    /// Right edge (pixels).
    pub right: f64,
    /// Bottom edge (pixels).
    pub bottom: f64,
}

/// KITTI's image size that the protocol fixes for the field-of-view test.
pub const KITTI_IMAGE_SIZE: (f64, f64) = (1242.0, 375.0);

impl View {
    /// Whether a Velodyne-frame point lies in the labelled region.
    pub fn contains(&self, p: [f64; 3]) -> bool {
        p[0].hypot(p[1]) <= self.max_range
            && self.camera.as_ref().is_none_or(|camera| camera.sees(p))
    }
}

impl Camera {
    /// Image coordinates (u, v) of a Velodyne-frame point, if it is in front of the camera
    /// (positive depth).
    pub fn project(&self, p: [f64; 3]) -> Option<[f64; 2]> {
        let rect = self.velo_to_rect * Vector4::new(p[0], p[1], p[2], 1.0);
        self.project_rect(&Point3::new(rect.x, rect.y, rect.z))
    }

    /// Image coordinates (u, v) of a point in the rectified camera frame, if it has positive
    /// depth.
    pub fn project_rect(&self, p: &Point3<f64>) -> Option<[f64; 2]> {
        let q = self.projection * p.to_homogeneous();
        (q.z > 0.0).then(|| [q.x / q.z, q.y / q.z])
    }

    /// Whether a Velodyne-frame point projects into the image with positive depth.
    pub fn sees(&self, p: [f64; 3]) -> bool {
        self.project(p).is_some_and(|uv| self.in_image(uv))
    }

    /// Whether image coordinates fall inside the image.
    pub fn in_image(&self, [u, v]: [f64; 2]) -> bool {
        (0.0..self.width).contains(&u) && (0.0..self.height).contains(&v)
    }
}

impl ImageBox {
    /// Whether image coordinates fall inside the box (edges included).
    pub fn contains(&self, [u, v]: [f64; 2]) -> bool {
        (self.left..=self.right).contains(&u) && (self.top..=self.bottom).contains(&v)
    }
}

/// A camera looking along Velodyne +x: rect x = −velo y, rect y = −velo z, rect z = velo x;
/// focal 700 px, principal point (621, 187.5).
#[cfg(test)]
pub(crate) fn forward_camera() -> Camera {
    #[rustfmt::skip]
    let velo_to_rect = Matrix4::new(
        0.0, -1.0, 0.0, 0.0,
        0.0, 0.0, -1.0, 0.0,
        1.0, 0.0, 0.0, 0.0,
        0.0, 0.0, 0.0, 1.0,
    );
    #[rustfmt::skip]
    let projection = Matrix3x4::new(
        700.0, 0.0, 621.0, 0.0,
        0.0, 700.0, 187.5, 0.0,
        0.0, 0.0, 1.0, 0.0,
    );
    Camera {
        velo_to_rect,
        projection,
        width: KITTI_IMAGE_SIZE.0,
        height: KITTI_IMAGE_SIZE.1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fov_filter_keeps_only_what_the_camera_sees_within_range() {
        let view = View {
            max_range: 40.0,
            camera: Some(forward_camera()),
        };
        assert!(view.contains([10.0, 0.0, 0.0]));
        // Behind the camera: negative depth.
        assert!(!view.contains([-10.0, 0.0, 0.0]));
        // Far to the side: u = 621 + 700 · 10 / 5 > 1242.
        assert!(!view.contains([5.0, -10.0, 0.0]));
        // Just inside and just outside the left edge: u = 621 − 700 · y / x.
        assert!(view.contains([10.0, 8.87, 0.0]));
        assert!(!view.contains([10.0, 8.88, 0.0]));
        // In the image but beyond 40 m BEV.
        assert!(view.contains([39.9, 2.0, 0.0]));
        assert!(!view.contains([40.0, 2.0, 0.0]));
        // Without a camera only the range counts.
        let range_only = View {
            max_range: 40.0,
            camera: None,
        };
        assert!(range_only.contains([-10.0, 0.0, 0.0]));
        assert!(!range_only.contains([0.0, 40.5, 0.0]));
    }

    #[test]
    fn projects_to_pixels() {
        let camera = forward_camera();
        let [u, v] = camera.project([10.0, -1.0, 0.5]).unwrap();
        assert!((u - (621.0 + 70.0)).abs() < 1e-9);
        assert!((v - (187.5 - 35.0)).abs() < 1e-9);
        assert!(camera.project([0.0, 1.0, 0.0]).is_none());
        let region = ImageBox {
            left: 680.0,
            top: 150.0,
            right: 700.0,
            bottom: 160.0,
        };
        assert!(region.contains([u, v]));
        assert!(!region.contains([u, v + 10.0]));
    }
}
