//! What objects are made of: vehicles with wheels and a cabin, cyclists on bicycles,
//! walking pedestrians — each a handful of solids inside the object's box.

use nalgebra::Vector3;

use crate::class::Class;
use crate::geometry::Shape;
use crate::material::Material;

/// One solid of a body, in the object's frame (x forward, y left, z up from the ground under
/// the box centre).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Part {
    /// The solid.
    pub shape: Shape,
    /// Centre of the solid in the object's frame.
    pub offset: Vector3<f64>,
    /// What the laser sees.
    pub material: Material,
    /// Amplitude (metres along x) of the part's swing while moving: legs and arms.
    pub swing: f64,
    /// Phase of the swing (radians), so left and right legs alternate.
    pub swing_phase: f64,
}

impl Part {
    fn fixed(shape: Shape, offset: [f64; 3], material: Material) -> Self {
        Self {
            shape,
            offset: Vector3::from(offset),
            material,
            swing: 0.0,
            swing_phase: 0.0,
        }
    }

    fn swinging(mut self, swing: f64, phase: f64) -> Self {
        self.swing = swing;
        self.swing_phase = phase;
        self
    }

    /// The offset of the part after moving `stride_phase` radians into the gait cycle.
    pub fn offset_at(&self, stride_phase: f64) -> Vector3<f64> {
        let mut o = self.offset;
        o.x += self.swing * (stride_phase + self.swing_phase).sin();
        o
    }
}

/// The solids of one object, all inside its box.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// The solids.
    pub parts: Vec<Part>,
    /// Metres travelled per gait cycle (legs); 0 for bodies that do not swing.
    pub stride: f64,
}

impl Body {
    /// The body of an object of `class` and size `[l, w, h]`.
    pub fn of(class: Class, [l, w, h]: [f64; 3], paint: Material) -> Self {
        match class {
            Class::Car => car(l, w, h, paint),
            Class::Van => van(l, w, h, paint),
            Class::Truck => truck(l, w, h, paint),
            Class::Cyclist => cyclist(l, w, h),
            Class::Pedestrian => pedestrian(l, w, h),
        }
    }
}

/// Four wheels `base` metres apart under a body of width `w`.
fn wheels(w: f64, base: f64, radius: f64) -> [Part; 4] {
    [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)].map(|(sx, sy)| {
        Part::fixed(
            Shape::cuboid(2.0 * radius, 0.22, 2.0 * radius),
            [sx * base / 2.0, sy * (w / 2.0 - 0.11), radius],
            Material::RUBBER,
        )
    })
}

/// A saloon: wheels, a lower body up to the belt line, a glass cabin and a roof.
fn car(l: f64, w: f64, h: f64, paint: Material) -> Body {
    let sill = 0.3;
    let belt = 0.62 * h;
    let mut parts = wheels(w, 0.62 * l, 0.31).to_vec();
    parts.push(Part::fixed(
        Shape::cuboid(l, w, belt - sill),
        [0.0, 0.0, (sill + belt) / 2.0],
        paint,
    ));
    parts.push(Part::fixed(
        Shape::cuboid(0.5 * l, w - 0.16, h - 0.06 - belt),
        [-0.05 * l, 0.0, (belt + h - 0.06) / 2.0],
        Material::GLASS,
    ));
    parts.push(Part::fixed(
        Shape::cuboid(0.42 * l, w - 0.2, 0.06),
        [-0.05 * l, 0.0, h - 0.03],
        paint,
    ));
    Body { parts, stride: 0.0 }
}

/// A van: a tall lower body, a box body behind a glass windscreen.
fn van(l: f64, w: f64, h: f64, paint: Material) -> Body {
    let belt = 0.5 * h;
    let mut parts = wheels(w, 0.6 * l, 0.33).to_vec();
    parts.push(Part::fixed(
        Shape::cuboid(l, w, belt - 0.3),
        [0.0, 0.0, (0.3 + belt) / 2.0],
        paint,
    ));
    parts.push(Part::fixed(
        Shape::cuboid(0.78 * l, w, h - belt),
        [-0.11 * l, 0.0, (belt + h) / 2.0],
        paint,
    ));
    parts.push(Part::fixed(
        Shape::cuboid(0.14 * l, w - 0.1, 0.8 * (h - belt)),
        [0.35 * l, 0.0, belt + 0.4 * (h - belt)],
        Material::GLASS,
    ));
    Body { parts, stride: 0.0 }
}

/// A lorry: a cab in front, a chassis and a cargo box behind.
fn truck(l: f64, w: f64, h: f64, paint: Material) -> Body {
    let cab = 2.2;
    let cab_x = l / 2.0 - cab / 2.0;
    let (sill, glass_lo, glass_hi, top) = (0.5, 0.45 * h, 0.7 * h, 0.85 * h);
    let mut parts = wheels(w, l - 2.4, 0.5).to_vec();
    for (z0, z1, material) in [
        (sill, glass_lo, paint),
        (glass_lo, glass_hi, Material::GLASS),
        (glass_hi, top, paint),
    ] {
        parts.push(Part::fixed(
            Shape::cuboid(cab, w, z1 - z0),
            [cab_x, 0.0, (z0 + z1) / 2.0],
            material,
        ));
    }
    parts.push(Part::fixed(
        Shape::cuboid(l - cab - 0.3, w - 0.3, 0.4),
        [-(cab + 0.3) / 2.0, 0.0, 0.75],
        Material::POLE,
    ));
    parts.push(Part::fixed(
        Shape::cuboid(l - cab - 0.3, w, h - 1.0),
        [-(cab + 0.3) / 2.0, 0.0, 1.0 + (h - 1.0) / 2.0],
        Material::FACADE,
    ));
    Body { parts, stride: 0.0 }
}

/// A rider on a bicycle: two wheels, a frame, pedalling legs, a torso, arms and a head.
fn cyclist(l: f64, w: f64, h: f64) -> Body {
    let r = 0.34;
    let axle = l / 2.0 - r - 0.02;
    let s = h / 1.75;
    let parts = vec![
        Part::fixed(
            Shape::cuboid(2.0 * r, 0.05, 2.0 * r),
            [axle, 0.0, r],
            Material::BIKE,
        ),
        Part::fixed(
            Shape::cuboid(2.0 * r, 0.05, 2.0 * r),
            [-axle, 0.0, r],
            Material::BIKE,
        ),
        Part::fixed(
            Shape::cuboid(0.9, 0.06, 0.1),
            [0.0, 0.0, 0.62],
            Material::BIKE,
        ),
        Part::fixed(
            Shape::cylinder(0.06, 0.55 * s),
            [0.0, 0.12, 0.62 * s],
            Material::CLOTH,
        )
        .swinging(0.12, 0.0),
        Part::fixed(
            Shape::cylinder(0.06, 0.55 * s),
            [0.0, -0.12, 0.62 * s],
            Material::CLOTH,
        )
        .swinging(0.12, std::f64::consts::PI),
        Part::fixed(
            Shape::ellipsoid(0.25, 0.18, 0.3 * s),
            [0.05, 0.0, 1.2 * s],
            Material::CLOTH,
        ),
        Part::fixed(
            Shape::cuboid(0.4, 0.08, 0.08),
            [0.3, w / 2.0 - 0.1, 1.15 * s],
            Material::SKIN,
        ),
        Part::fixed(
            Shape::cuboid(0.4, 0.08, 0.08),
            [0.3, -(w / 2.0 - 0.1), 1.15 * s],
            Material::SKIN,
        ),
        Part::fixed(
            Shape::ellipsoid(0.11, 0.09, 0.12),
            [0.2, 0.0, h - 0.13],
            Material::SKIN,
        ),
    ];
    // Pedal cycles: one per ~4.5 m at a typical gear.
    Body { parts, stride: 4.5 }
}

/// A walking person: swinging legs and arms, a torso and a head.
fn pedestrian(_l: f64, w: f64, h: f64) -> Body {
    let leg = 0.48 * h;
    let arm_y = w / 2.0 - 0.06;
    let parts = vec![
        Part::fixed(
            Shape::cylinder(0.075, leg),
            [0.0, 0.1, leg / 2.0],
            Material::CLOTH,
        )
        .swinging(0.22, 0.0),
        Part::fixed(
            Shape::cylinder(0.075, leg),
            [0.0, -0.1, leg / 2.0],
            Material::CLOTH,
        )
        .swinging(0.22, std::f64::consts::PI),
        Part::fixed(
            Shape::ellipsoid(0.13, 0.2, 0.17 * h),
            [0.0, 0.0, 0.66 * h],
            Material::CLOTH,
        ),
        Part::fixed(
            Shape::cylinder(0.04, 0.33 * h),
            [0.0, arm_y, 0.62 * h],
            Material::CLOTH,
        )
        .swinging(0.15, std::f64::consts::PI),
        Part::fixed(
            Shape::cylinder(0.04, 0.33 * h),
            [0.0, -arm_y, 0.62 * h],
            Material::CLOTH,
        )
        .swinging(0.15, 0.0),
        Part::fixed(
            Shape::ellipsoid(0.1, 0.09, 0.12),
            [0.0, 0.0, h - 0.12],
            Material::SKIN,
        ),
    ];
    Body { parts, stride: 1.5 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Primitive;
    use crate::label::PointLabel;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn every_part_stays_inside_the_box_at_every_gait_phase() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        for class in Class::ALL {
            for _ in 0..20 {
                let size = class.random_size(&mut rng);
                let body = Body::of(class, size, Material::PAINT);
                for k in 0..16 {
                    let phase = k as f64 * std::f64::consts::TAU / 16.0;
                    for part in &body.parts {
                        let prim = Primitive::new(
                            part.shape,
                            part.offset_at(phase),
                            0.0,
                            part.material,
                            PointLabel::Static,
                        );
                        let (z0, z1) = prim.z_range();
                        assert!(z0 >= -1e-9 && z1 <= size[2] + 1e-9, "{class:?} {part:?}");
                        for c in prim.footprint() {
                            assert!(c.x.abs() <= size[0] / 2.0 + 1e-9, "{class:?} {part:?}");
                            assert!(c.y.abs() <= size[1] / 2.0 + 1e-9, "{class:?} {part:?}");
                        }
                    }
                }
            }
        }
    }
}
