//! Street furniture and buildings: the static structure scenarios are dressed with.

use nalgebra::Vector2;

use crate::geometry::Shape;
use crate::material::Material;
use crate::path::Path;
use crate::random::between;
use crate::scenario::builder::WorldBuilder;

/// A point `offset` metres to the left of `road` at arc length `s`, and the road's heading.
pub fn beside(road: &Path, s: f64, offset: f64) -> (Vector2<f64>, f64) {
    let p = road.sample(s).pose;
    (p.position + p.left() * offset, p.heading)
}

/// A unit vector at heading `yaw`.
fn along(yaw: f64) -> Vector2<f64> {
    Vector2::new(yaw.cos(), yaw.sin())
}

/// A building of footprint `l` × `w` and height `h`; sometimes with a lower annex.
pub fn building(b: &mut WorldBuilder, xy: Vector2<f64>, yaw: f64, l: f64, w: f64, h: f64) {
    // Sunk 2 m so it meets sloping ground everywhere.
    b.add_static(
        Shape::cuboid(l, w, h + 2.0),
        xy,
        -2.0,
        yaw,
        Material::FACADE,
    );
    if l > 12.0 && crate::random::chance(&mut b.rng, 0.3) {
        // A ground-floor shop front or porch on the street side.
        let annex = Vector2::new(-yaw.sin(), yaw.cos()) * (w / 2.0 + 1.0);
        b.add_static(
            Shape::cuboid(l * 0.4, 2.0, 3.5 + 2.0),
            xy - annex,
            -2.0,
            yaw,
            Material::CONCRETE,
        );
    }
}

/// A wall or fence from `a` to `b` of `height` and `thickness`.
pub fn wall(
    b: &mut WorldBuilder,
    from: Vector2<f64>,
    to: Vector2<f64>,
    height: f64,
    thickness: f64,
    material: Material,
) {
    let d = to - from;
    let yaw = d.y.atan2(d.x);
    b.add_static(
        Shape::cuboid(d.norm(), thickness, height + 1.0),
        (from + to) / 2.0,
        -1.0,
        yaw,
        material,
    );
}

/// A street lamp whose arm reaches towards heading `facing`.
pub fn lamp_post(b: &mut WorldBuilder, xy: Vector2<f64>, facing: f64) {
    let h = between(&mut b.rng, 6.0, 8.0);
    b.add_static(Shape::cylinder(0.09, h), xy, 0.0, 0.0, Material::POLE);
    b.add_static(
        Shape::cuboid(1.6, 0.1, 0.1),
        xy + along(facing) * 0.8,
        h - 0.1,
        facing,
        Material::POLE,
    );
    b.add_static(
        Shape::cuboid(0.6, 0.3, 0.15),
        xy + along(facing) * 1.5,
        h - 0.3,
        facing,
        Material::POLE,
    );
}

/// A traffic sign on a post, its face towards heading `facing`.
pub fn sign(b: &mut WorldBuilder, xy: Vector2<f64>, facing: f64) {
    b.add_static(Shape::cylinder(0.04, 2.2), xy, 0.0, 0.0, Material::POLE);
    b.add_static(
        Shape::cuboid(0.04, 0.65, 0.65),
        xy + along(facing) * 0.06,
        2.0,
        facing,
        Material::SIGN,
    );
}

/// A traffic light on a post, facing heading `facing`.
pub fn traffic_light(b: &mut WorldBuilder, xy: Vector2<f64>, facing: f64) {
    b.add_static(Shape::cylinder(0.1, 3.4), xy, 0.0, 0.0, Material::POLE);
    b.add_static(
        Shape::cuboid(0.3, 0.35, 0.95),
        xy + along(facing) * 0.25,
        2.5,
        facing,
        Material::POLE,
    );
}

/// A tree: trunk and a crown of foliage.
pub fn tree(b: &mut WorldBuilder, xy: Vector2<f64>) {
    let trunk_h = between(&mut b.rng, 1.8, 3.5);
    let trunk_r = between(&mut b.rng, 0.1, 0.25);
    let crown_r = between(&mut b.rng, 1.4, 3.0);
    let crown_h = between(&mut b.rng, 1.5, 3.5);
    let squash = between(&mut b.rng, 0.8, 1.2);
    let turn = between(&mut b.rng, 0.0, 3.0);
    b.add_static(
        Shape::cylinder(trunk_r, trunk_h + 0.5),
        xy,
        0.0,
        0.0,
        Material::BARK,
    );
    b.add_static(
        Shape::ellipsoid(crown_r, crown_r * squash, crown_h),
        xy,
        trunk_h - 0.3,
        turn,
        Material::FOLIAGE,
    );
}

/// A bush.
pub fn bush(b: &mut WorldBuilder, xy: Vector2<f64>) {
    let r = between(&mut b.rng, 0.5, 1.4);
    let h = between(&mut b.rng, 0.4, 0.9);
    let squash = between(&mut b.rng, 0.6, 1.4);
    let turn = between(&mut b.rng, 0.0, 3.0);
    b.add_static(
        Shape::ellipsoid(r, r * squash, h),
        xy,
        -0.3 * h,
        turn,
        Material::FOLIAGE,
    );
}

/// A bench with its seat along heading `yaw`.
pub fn bench(b: &mut WorldBuilder, xy: Vector2<f64>, yaw: f64) {
    let back = Vector2::new(-yaw.sin(), yaw.cos()) * 0.25;
    b.add_static(
        Shape::cuboid(1.8, 0.5, 0.08),
        xy,
        0.42,
        yaw,
        Material::CONCRETE,
    );
    b.add_static(
        Shape::cuboid(1.8, 0.06, 0.45),
        xy + back,
        0.5,
        yaw,
        Material::CONCRETE,
    );
    for side in [-0.75, 0.75] {
        b.add_static(
            Shape::cuboid(0.08, 0.45, 0.42),
            xy + along(yaw) * side,
            0.0,
            yaw,
            Material::CONCRETE,
        );
    }
}

/// A round planter with a bush in it.
pub fn planter(b: &mut WorldBuilder, xy: Vector2<f64>) {
    b.add_static(Shape::cylinder(0.8, 0.6), xy, 0.0, 0.0, Material::CONCRETE);
    b.add_static(
        Shape::ellipsoid(0.7, 0.7, 0.5),
        xy,
        0.5,
        0.0,
        Material::FOLIAGE,
    );
}

/// A bollard.
pub fn bollard(b: &mut WorldBuilder, xy: Vector2<f64>) {
    b.add_static(Shape::cylinder(0.1, 0.9), xy, 0.0, 0.0, Material::POLE);
}

/// A litter bin.
pub fn bin(b: &mut WorldBuilder, xy: Vector2<f64>) {
    b.add_static(Shape::cylinder(0.3, 1.0), xy, 0.0, 0.0, Material::POLE);
}

/// A guard rail `offset` metres left of `road` from arc length `s0` to `s1`: a rail on
/// posts every 2 m.
pub fn guard_rail(b: &mut WorldBuilder, road: &Path, s0: f64, s1: f64, offset: f64) {
    let piece = 4.0;
    let mut s = s0;
    while s < s1 {
        let (xy, yaw) = beside(road, s + piece / 2.0, offset);
        b.add_static(
            Shape::cuboid(piece + 0.02, 0.06, 0.32),
            xy,
            0.45,
            yaw,
            Material::GUARD_RAIL,
        );
        for post in [0.0, piece / 2.0] {
            let (p, yaw) = beside(road, s + post, offset - offset.signum() * 0.1);
            b.add_static(Shape::cuboid(0.1, 0.1, 0.75), p, 0.0, yaw, Material::POLE);
        }
        s += piece;
    }
}
