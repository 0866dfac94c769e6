//! The solids a world is made of, and where a ray meets them.
//!
//! Every solid stands upright: it may turn about the vertical axis (yaw) but not tilt, which
//! is how buildings, poles, vehicles and people stand, and keeps every test a few flops.

use nalgebra::{Vector2, Vector3};

use crate::label::PointLabel;
use crate::material::Material;

/// The shape of a solid, in its own frame (x forward, y left, z up, origin at its centre).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A box with half extents along x (length), y (width) and z (height).
    Cuboid {
        /// Half extents in metres.
        half: Vector3<f64>,
    },
    /// An upright cylinder.
    Cylinder {
        /// Radius in metres.
        radius: f64,
        /// Half of the height in metres.
        half_height: f64,
    },
    /// An ellipsoid with semi-axes along x, y and z.
    Ellipsoid {
        /// Semi-axes in metres.
        radii: Vector3<f64>,
    },
}

impl Shape {
    /// A box of length `l` (x), width `w` (y) and height `h` (z).
    pub fn cuboid(l: f64, w: f64, h: f64) -> Self {
        Self::Cuboid {
            half: Vector3::new(l / 2.0, w / 2.0, h / 2.0),
        }
    }

    /// An upright cylinder of radius `r` and height `h`.
    pub fn cylinder(r: f64, h: f64) -> Self {
        Self::Cylinder {
            radius: r,
            half_height: h / 2.0,
        }
    }

    /// An ellipsoid with semi-axes `rx`, `ry`, `rz`.
    pub fn ellipsoid(rx: f64, ry: f64, rz: f64) -> Self {
        Self::Ellipsoid {
            radii: Vector3::new(rx, ry, rz),
        }
    }

    /// Half extents of the shape's bounding box in its own frame.
    pub fn half_extents(&self) -> Vector3<f64> {
        match *self {
            Self::Cuboid { half } => half,
            Self::Cylinder {
                radius,
                half_height,
            } => Vector3::new(radius, radius, half_height),
            Self::Ellipsoid { radii } => radii,
        }
    }
}

/// Where a ray enters and leaves a solid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter (metres along a unit direction) of the entry.
    pub t_in: f64,
    /// Ray parameter of the exit.
    pub t_out: f64,
    /// Outward unit normal at the entry, world frame.
    pub normal: Vector3<f64>,
}

/// A placed solid: shape, pose (centre and yaw), material and ground-truth label.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Primitive {
    /// The solid's shape.
    pub shape: Shape,
    /// Centre in the world frame.
    pub center: Vector3<f64>,
    /// What the laser sees.
    pub material: Material,
    /// What a return from it is.
    pub label: PointLabel,
    cos_yaw: f64,
    sin_yaw: f64,
}

impl Primitive {
    /// A solid centred at `center`, turned by `yaw` about the vertical axis.
    pub fn new(
        shape: Shape,
        center: Vector3<f64>,
        yaw: f64,
        material: Material,
        label: PointLabel,
    ) -> Self {
        Self {
            shape,
            center,
            material,
            label,
            cos_yaw: yaw.cos(),
            sin_yaw: yaw.sin(),
        }
    }

    /// The heading of the solid's x axis (radians, counter-clockwise from world x).
    pub fn yaw(&self) -> f64 {
        self.sin_yaw.atan2(self.cos_yaw)
    }

    /// A world vector expressed in the solid's frame (rotation only).
    fn rotate_in(&self, v: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(
            self.cos_yaw * v.x + self.sin_yaw * v.y,
            -self.sin_yaw * v.x + self.cos_yaw * v.y,
            v.z,
        )
    }

    /// A vector of the solid's frame expressed in the world frame (rotation only).
    fn rotate_out(&self, v: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(
            self.cos_yaw * v.x - self.sin_yaw * v.y,
            self.sin_yaw * v.x + self.cos_yaw * v.y,
            v.z,
        )
    }

    /// Whether a world point lies inside the solid (boundary included, `margin` added).
    pub fn contains(&self, p: &Vector3<f64>, margin: f64) -> bool {
        let l = self.rotate_in(&(p - self.center));
        match self.shape {
            Shape::Cuboid { half } => {
                l.x.abs() <= half.x + margin
                    && l.y.abs() <= half.y + margin
                    && l.z.abs() <= half.z + margin
            }
            Shape::Cylinder {
                radius,
                half_height,
            } => l.xy().norm() <= radius + margin && l.z.abs() <= half_height + margin,
            Shape::Ellipsoid { radii } => {
                let r = radii.add_scalar(margin);
                l.component_div(&r).norm_squared() <= 1.0
            }
        }
    }

    /// The four corners of the solid's footprint (its bounding rectangle seen from above).
    pub fn footprint(&self) -> [Vector2<f64>; 4] {
        let h = self.shape.half_extents();
        let c = self.center.xy();
        [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)].map(|(sx, sy)| {
            let v = self.rotate_out(&Vector3::new(sx * h.x, sy * h.y, 0.0));
            c + v.xy()
        })
    }

    /// Radius of the circle around the centre that holds the footprint.
    pub fn radius_xy(&self) -> f64 {
        self.shape.half_extents().xy().norm()
    }

    /// Lowest and highest z of the solid.
    pub fn z_range(&self) -> (f64, f64) {
        let hz = self.shape.half_extents().z;
        (self.center.z - hz, self.center.z + hz)
    }

    /// Where the ray `origin + t·dir` (unit `dir`) enters and leaves the solid, if it does so
    /// in front of the origin. A ray starting inside the solid does not hit it.
    pub fn intersect(&self, origin: &Vector3<f64>, dir: &Vector3<f64>) -> Option<Hit> {
        let o = self.rotate_in(&(origin - self.center));
        let d = self.rotate_in(dir);
        let (t_in, t_out, n) = match self.shape {
            Shape::Cuboid { half } => slab(&o, &d, &half)?,
            Shape::Cylinder {
                radius,
                half_height,
            } => cylinder(&o, &d, radius, half_height)?,
            Shape::Ellipsoid { radii } => ellipsoid(&o, &d, &radii)?,
        };
        (t_in > 0.0 && t_out >= t_in).then(|| Hit {
            t_in,
            t_out,
            normal: self.rotate_out(&n),
        })
    }
}

/// Ray against an axis-aligned box centred at the origin (Kay–Kajiya slabs).
fn slab(
    o: &Vector3<f64>,
    d: &Vector3<f64>,
    half: &Vector3<f64>,
) -> Option<(f64, f64, Vector3<f64>)> {
    let mut t_in = f64::NEG_INFINITY;
    let mut t_out = f64::INFINITY;
    let mut normal = Vector3::zeros();
    for axis in 0..3 {
        if d[axis].abs() < 1e-12 {
            if o[axis].abs() > half[axis] {
                return None;
            }
            continue;
        }
        let inv = 1.0 / d[axis];
        let t1 = (-half[axis] - o[axis]) * inv;
        let t2 = (half[axis] - o[axis]) * inv;
        let (near, far) = if t1 < t2 { (t1, t2) } else { (t2, t1) };
        if near > t_in {
            t_in = near;
            normal = Vector3::zeros();
            normal[axis] = -d[axis].signum();
        }
        t_out = t_out.min(far);
        if t_in > t_out {
            return None;
        }
    }
    Some((t_in, t_out, normal))
}

/// Ray against an upright cylinder centred at the origin.
fn cylinder(
    o: &Vector3<f64>,
    d: &Vector3<f64>,
    radius: f64,
    half_height: f64,
) -> Option<(f64, f64, Vector3<f64>)> {
    let a = d.x * d.x + d.y * d.y;
    let (mut t_in, mut t_out, mut normal);
    if a < 1e-12 {
        if o.x * o.x + o.y * o.y > radius * radius {
            return None;
        }
        t_in = f64::NEG_INFINITY;
        t_out = f64::INFINITY;
        normal = Vector3::zeros();
    } else {
        let b = o.x * d.x + o.y * d.y;
        let c = o.x * o.x + o.y * o.y - radius * radius;
        let disc = b * b - a * c;
        if disc < 0.0 {
            return None;
        }
        let sq = disc.sqrt();
        t_in = (-b - sq) / a;
        t_out = (-b + sq) / a;
        let p = o + d * t_in;
        normal = Vector3::new(p.x, p.y, 0.0) / radius;
    }
    if d.z.abs() < 1e-12 {
        if o.z.abs() > half_height {
            return None;
        }
    } else {
        let t1 = (-half_height - o.z) / d.z;
        let t2 = (half_height - o.z) / d.z;
        let (near, far) = if t1 < t2 { (t1, t2) } else { (t2, t1) };
        if near > t_in {
            t_in = near;
            normal = Vector3::new(0.0, 0.0, -d.z.signum());
        }
        t_out = t_out.min(far);
    }
    (t_in <= t_out).then_some((t_in, t_out, normal))
}

/// Ray against an axis-aligned ellipsoid centred at the origin.
fn ellipsoid(
    o: &Vector3<f64>,
    d: &Vector3<f64>,
    radii: &Vector3<f64>,
) -> Option<(f64, f64, Vector3<f64>)> {
    let os = o.component_div(radii);
    let ds = d.component_div(radii);
    let a = ds.norm_squared();
    let b = os.dot(&ds);
    let c = os.norm_squared() - 1.0;
    let disc = b * b - a * c;
    if disc < 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    let t_in = (-b - sq) / a;
    let t_out = (-b + sq) / a;
    let p = o + d * t_in;
    let normal = p
        .component_div(&radii.component_mul(radii))
        .try_normalize(1e-12)
        .unwrap_or_else(Vector3::z);
    Some((t_in, t_out, normal))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prim(shape: Shape, center: Vector3<f64>, yaw: f64) -> Primitive {
        Primitive::new(shape, center, yaw, Material::FACADE, PointLabel::Static)
    }

    #[test]
    fn ray_hits_the_near_face_of_a_box() {
        let b = prim(
            Shape::cuboid(2.0, 2.0, 2.0),
            Vector3::new(10.0, 0.0, 0.0),
            0.0,
        );
        let hit = b.intersect(&Vector3::zeros(), &Vector3::x()).unwrap();
        assert!((hit.t_in - 9.0).abs() < 1e-12);
        assert!((hit.t_out - 11.0).abs() < 1e-12);
        assert!((hit.normal + Vector3::x()).norm() < 1e-12);
    }

    #[test]
    fn a_turned_box_is_hit_at_its_corner() {
        // A unit-half box turned by 45°: its corner points at the origin, √2 from the centre.
        let b = prim(
            Shape::cuboid(2.0, 2.0, 2.0),
            Vector3::new(10.0, 0.0, 0.0),
            std::f64::consts::FRAC_PI_4,
        );
        let hit = b.intersect(&Vector3::zeros(), &Vector3::x()).unwrap();
        assert!((hit.t_in - (10.0 - 2f64.sqrt())).abs() < 1e-9);
    }

    #[test]
    fn ray_misses_a_box_beside_it_and_behind_it() {
        let b = prim(
            Shape::cuboid(2.0, 2.0, 2.0),
            Vector3::new(10.0, 3.0, 0.0),
            0.0,
        );
        assert!(b.intersect(&Vector3::zeros(), &Vector3::x()).is_none());
        let behind = prim(
            Shape::cuboid(2.0, 2.0, 2.0),
            Vector3::new(-10.0, 0.0, 0.0),
            0.0,
        );
        assert!(behind.intersect(&Vector3::zeros(), &Vector3::x()).is_none());
    }

    #[test]
    fn cylinder_side_and_cap() {
        let c = prim(Shape::cylinder(0.5, 4.0), Vector3::new(5.0, 0.0, 0.0), 0.0);
        let side = c.intersect(&Vector3::zeros(), &Vector3::x()).unwrap();
        assert!((side.t_in - 4.5).abs() < 1e-12);
        assert!((side.normal + Vector3::x()).norm() < 1e-12);
        // Straight down onto the top cap from above.
        let cap = c
            .intersect(&Vector3::new(5.0, 0.0, 10.0), &-Vector3::z())
            .unwrap();
        assert!((cap.t_in - 8.0).abs() < 1e-12);
        assert!((cap.normal - Vector3::z()).norm() < 1e-12);
        // Over the top.
        assert!(
            c.intersect(&Vector3::new(0.0, 0.0, 3.0), &Vector3::x())
                .is_none()
        );
    }

    #[test]
    fn ellipsoid_hit_and_normal() {
        let e = prim(
            Shape::ellipsoid(1.0, 2.0, 3.0),
            Vector3::new(0.0, 10.0, 0.0),
            0.0,
        );
        let hit = e.intersect(&Vector3::zeros(), &Vector3::y()).unwrap();
        assert!((hit.t_in - 8.0).abs() < 1e-12);
        assert!((hit.t_out - 12.0).abs() < 1e-12);
        assert!((hit.normal + Vector3::y()).norm() < 1e-12);
    }

    #[test]
    fn entry_points_lie_on_the_solid() {
        let shapes = [
            Shape::cuboid(4.0, 1.8, 1.5),
            Shape::cylinder(0.3, 2.0),
            Shape::ellipsoid(0.4, 0.8, 1.2),
        ];
        for shape in shapes {
            let p = prim(shape, Vector3::new(6.0, 1.0, 0.3), 0.7);
            for k in 0..50 {
                let a = -0.5 + k as f64 * 0.02;
                let dir = Vector3::new(a.cos(), a.sin(), 0.05 * (k as f64 * 0.3).sin()).normalize();
                if let Some(hit) = p.intersect(&Vector3::zeros(), &dir) {
                    let q = dir * hit.t_in;
                    assert!(p.contains(&q, 1e-9), "{shape:?} {q}");
                    assert!(!p.contains(&(dir * (hit.t_in - 1e-3)), 0.0));
                }
            }
        }
    }

    #[test]
    fn footprint_corners_are_turned() {
        let b = prim(
            Shape::cuboid(4.0, 2.0, 1.0),
            Vector3::new(1.0, 1.0, 0.0),
            std::f64::consts::FRAC_PI_2,
        );
        let f = b.footprint();
        assert!((f[0] - Vector2::new(0.0, 3.0)).norm() < 1e-12, "{}", f[0]);
        assert!((b.radius_xy() - 5f64.sqrt()).abs() < 1e-12);
    }
}
