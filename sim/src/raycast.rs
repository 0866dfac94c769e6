//! First-hit ray casting against the ground and a set of solids, culled per azimuth sector.
//!
//! For one sensor position, every solid within range is filed under the azimuth sectors its
//! footprint covers, nearest first. A ray tests the ground, then only its sector's solids,
//! and stops once the next solid cannot be nearer than the hit it has.

use nalgebra::Vector3;

use crate::geometry::Primitive;
use crate::label::PointLabel;
use crate::material::Material;
use crate::random::RayRng;
use crate::terrain::Terrain;

/// Number of azimuth sectors (0.5° each).
const SECTORS: usize = 720;

/// The first surface a ray meets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    /// Distance along the (unit) ray in metres.
    pub range: f64,
    /// Outward unit normal of the surface (world frame); `None` inside foliage.
    pub normal: Option<Vector3<f64>>,
    /// The surface's material.
    pub material: Material,
    /// What was hit.
    pub label: PointLabel,
}

/// Everything one sensor position can see, filed by azimuth sector.
#[derive(Debug)]
pub struct Scene<'a> {
    terrain: &'a Terrain,
    origin: Vector3<f64>,
    max_range: f64,
    primitives: Vec<Primitive>,
    /// Nearest horizontal distance from the origin to each solid's footprint.
    near: Vec<f64>,
    /// CSR layout: solids of sector `k` are `members[starts[k]..starts[k + 1]]`.
    starts: Vec<u32>,
    members: Vec<u32>,
}

impl<'a> Scene<'a> {
    /// Files the solids of `layers` within `max_range` of `origin`.
    pub fn new(
        terrain: &'a Terrain,
        layers: &[&[Primitive]],
        origin: Vector3<f64>,
        max_range: f64,
    ) -> Self {
        let mut primitives = Vec::new();
        let mut near = Vec::new();
        let mut spans = Vec::new();
        for prim in layers.iter().flat_map(|l| l.iter()) {
            let d = (prim.center.xy() - origin.xy()).norm();
            let r = prim.radius_xy();
            if d - r > max_range {
                continue;
            }
            near.push((d - r).max(0.0));
            spans.push(sector_span(prim, &origin, d, r));
            primitives.push(*prim);
        }
        // Nearest first, so rays can stop early.
        let mut order: Vec<u32> = (0..primitives.len() as u32).collect();
        order.sort_by(|&a, &b| near[a as usize].total_cmp(&near[b as usize]));
        let mut counts = vec![0u32; SECTORS + 1];
        for &i in &order {
            for k in sectors_of(spans[i as usize]) {
                counts[k + 1] += 1;
            }
        }
        for k in 0..SECTORS {
            counts[k + 1] += counts[k];
        }
        let starts = counts.clone();
        let mut fill = counts;
        let mut members = vec![0u32; starts[SECTORS] as usize];
        for &i in &order {
            for k in sectors_of(spans[i as usize]) {
                members[fill[k] as usize] = i;
                fill[k] += 1;
            }
        }
        Self {
            terrain,
            origin,
            max_range,
            primitives,
            near,
            starts,
            members,
        }
    }

    /// Number of solids within range.
    pub fn len(&self) -> usize {
        self.primitives.len()
    }

    /// Whether no solid is within range.
    pub fn is_empty(&self) -> bool {
        self.primitives.is_empty()
    }

    /// The first surface along the unit world direction `dir` from the scene's origin,
    /// within the maximum range. `rng` decides beams that pass through glass and foliage.
    pub fn first_hit(&self, dir: &Vector3<f64>, rng: &mut RayRng) -> Option<SurfaceHit> {
        let mut best = self
            .terrain
            .intersect(&self.origin, dir, self.max_range)
            .map(|t| {
                let p = self.origin + dir * t;
                SurfaceHit {
                    range: t,
                    normal: Some(self.terrain.normal(p.xy())),
                    material: Material::ASPHALT,
                    label: PointLabel::Ground,
                }
            });
        let mut best_t = best.map_or(self.max_range, |h| h.range);
        let horizontal = dir.xy().norm();
        let sector = sector_of(dir.y.atan2(dir.x));
        let (a, b) = (
            self.starts[sector] as usize,
            self.starts[sector + 1] as usize,
        );
        for &i in &self.members[a..b] {
            let i = i as usize;
            if self.near[i] > best_t * horizontal {
                break;
            }
            let prim = &self.primitives[i];
            let Some(hit) = prim.intersect(&self.origin, dir) else {
                continue;
            };
            if hit.t_in >= best_t {
                continue;
            }
            let m = prim.material;
            if m.pass_through > 0.0 && rng.uniform() < f64::from(m.pass_through) {
                continue;
            }
            let (range, normal) = if m.volumetric {
                let depth = rng.uniform() * (hit.t_out - hit.t_in).min(1.5);
                (hit.t_in + depth, None)
            } else {
                (hit.t_in, Some(hit.normal))
            };
            if range < best_t {
                best_t = range;
                best = Some(SurfaceHit {
                    range,
                    normal,
                    material: m,
                    label: prim.label,
                });
            }
        }
        best
    }
}

/// The sector of a world azimuth (radians).
fn sector_of(azimuth: f64) -> usize {
    let u = (azimuth + std::f64::consts::PI) / std::f64::consts::TAU;
    ((u * SECTORS as f64) as usize).min(SECTORS - 1)
}

/// First and last sector (inclusive, possibly wrapping) a solid covers seen from `origin`;
/// `None` when it surrounds the origin (every sector).
fn sector_span(prim: &Primitive, origin: &Vector3<f64>, d: f64, r: f64) -> Option<(usize, usize)> {
    if d <= r + 1e-6 {
        return None;
    }
    // Seen from outside its bounding circle a solid spans less than 180°: measure its corners
    // from the direction of its centre, where no wrap-around can occur.
    let to_center = prim.center.xy() - origin.xy();
    let mid = to_center.y.atan2(to_center.x);
    let (mut lo, mut hi) = (0.0f64, 0.0f64);
    for c in prim.footprint() {
        let v = c - origin.xy();
        let rel = crate::path::wrap_angle(v.y.atan2(v.x) - mid);
        lo = lo.min(rel);
        hi = hi.max(rel);
    }
    Some((sector_of(mid + lo), sector_of(mid + hi)))
}

/// The sectors of a span, in order.
fn sectors_of(span: Option<(usize, usize)>) -> impl Iterator<Item = usize> {
    let (first, count) = match span {
        None => (0, SECTORS),
        Some((a, b)) if b >= a => (a, b - a + 1),
        Some((a, b)) => (a, SECTORS - a + b + 1),
    };
    (0..count).map(move |k| (first + k) % SECTORS)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Shape;

    fn wall(center: [f64; 3], l: f64, yaw: f64, id: u32) -> Primitive {
        Primitive::new(
            Shape::cuboid(l, 0.5, 4.0),
            Vector3::from(center),
            yaw,
            Material::FACADE,
            PointLabel::Object(id),
        )
    }

    /// The first hit by testing every solid, without sectors.
    fn brute_force(
        terrain: &Terrain,
        prims: &[Primitive],
        o: &Vector3<f64>,
        d: &Vector3<f64>,
    ) -> Option<(f64, PointLabel)> {
        let mut best = terrain
            .intersect(o, d, 120.0)
            .map(|t| (t, PointLabel::Ground));
        for p in prims {
            if let Some(h) = p.intersect(o, d)
                && h.t_in < best.map_or(120.0, |b| b.0)
            {
                best = Some((h.t_in, p.label));
            }
        }
        best
    }

    #[test]
    fn sectors_give_the_same_first_hits_as_testing_everything() {
        let terrain = Terrain::flat();
        let mut prims = Vec::new();
        for i in 0..60 {
            let a = i as f64 * 0.37;
            let d = 3.0 + (i % 13) as f64 * 6.0;
            prims.push(wall(
                [d * a.cos(), d * a.sin(), 2.0],
                1.0 + (i % 5) as f64 * 4.0,
                a * 1.7,
                i,
            ));
        }
        // One solid around the sensor's column and one across the ±180° seam.
        prims.push(wall(
            [-20.0, 0.0, 2.0],
            0.5,
            std::f64::consts::FRAC_PI_2,
            100,
        ));
        let origin = Vector3::new(0.5, -0.3, 1.73);
        let scene = Scene::new(&terrain, &[&prims], origin, 120.0);
        let mut rng = RayRng::new(1);
        let mut hits = 0;
        for j in 0..2000 {
            for el in [-20.0f64, -5.0, -1.0, 0.0, 1.5] {
                let az = -std::f64::consts::PI + (j as f64 + 0.5) * std::f64::consts::TAU / 2000.0;
                let el = el.to_radians();
                let d = Vector3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin());
                let fast = scene.first_hit(&d, &mut rng).map(|h| (h.range, h.label));
                let slow = brute_force(&terrain, &prims, &origin, &d);
                assert_eq!(fast, slow, "az {az} el {el}");
                hits += usize::from(fast.is_some_and(|h| h.1 != PointLabel::Ground));
            }
        }
        assert!(hits > 1000, "{hits}");
    }

    #[test]
    fn a_nearer_solid_occludes_a_farther_one() {
        let terrain = Terrain::flat();
        let prims = [
            wall([20.0, 0.0, 2.0], 2.0, std::f64::consts::FRAC_PI_2, 1),
            wall([10.0, 0.0, 2.0], 2.0, std::f64::consts::FRAC_PI_2, 2),
        ];
        let scene = Scene::new(&terrain, &[&prims], Vector3::new(0.0, 0.0, 1.73), 120.0);
        let hit = scene.first_hit(&Vector3::x(), &mut RayRng::new(0)).unwrap();
        assert_eq!(hit.label, PointLabel::Object(2));
        assert!((hit.range - 9.75).abs() < 1e-9);
    }
}
