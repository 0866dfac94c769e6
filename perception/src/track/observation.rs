//! What the tracker measures of one cluster: its visible outline in bird's-eye view, its
//! height profile above the ground and its shape verdict.

use nalgebra::{Point3, Vector2, Vector3};

use super::box_fit::{Rect, fit_rectangle};
use super::classify::{ClassifyConfig, ShapeFeatures, ShapeVerdict, classify_shape};
use super::tracker::ScanContext;
use super::visibility::Visibility;
use crate::Point;

/// An outline thinner than this (m) is one face.
const ONE_FACE_DEPTH: f64 = 0.3;
/// Faces shorter than this (m) are not judged: a rider's back hides no second face worth
/// seeing.
const MIN_OBLIQUE_FACE: f64 = 1.2;
/// A face is seen edge-on when the sensor lies farther than this (m) beyond its ends, and
/// far enough beyond them that a box's second face would show (see [`second_face_offset`]).
const OBLIQUE_MARGIN: f64 = 1.0;
/// Horizontal angle between two columns of a KITTI-like scan (rad, ~0.17°).
pub(crate) const SCAN_AZIMUTH_STEP: f64 = 0.003;
/// Columns a second face must span to be surely seen.
const SECOND_FACE_COLUMNS: f64 = 3.0;
/// The narrowest second face of a box-shaped object (m): a car's rear.
const SECOND_FACE_DEPTH: f64 = 1.6;

/// A cluster with a point this close (m) to the range limit is cut by it. Where the limit
/// cuts a surface, its returns run on to the limit, 0.15 m apart along a scan line at 50 m;
/// 1 m left every person and car in the last 2-3 m before a 50 m limit unidentified (on the
/// simulated drives 0.4 m scored a mean MOTA 0.4 point higher, 0.15 m took more clutter
/// at the limit for objects).
const CLIP_MARGIN: f64 = 0.4;

/// A view's lower part counts as hidden ([`ShapeFeatures::lower_hidden`]) only within this
/// range (m): farther, the lower beams of most directions hit something nearer, and a hidden
/// lower part says little (without this limit an object 48 m away on KITTI tracking 0000, 6-7 m
/// long and up to 3.9 m tall, outside the labelled view, was reported as a car for 15 scans)...
const LOWER_HIDDEN_MAX_RANGE: f64 = 35.0;
/// ...when the view is smooth, a vehicle's panels and not a crown's leaves (views of cars
/// measure 0.02-0.04)...
const LOWER_HIDDEN_MAX_SURFACE_VARIATION: f64 = 0.03;
/// ...and when its upper third spans more (m) than a sign or a small crown. Without these
/// three tests, clutter whose lower part something nearer hid became cars: the simulated
/// drives of seeds 1-3 scored a mean MOTA of 89.20 % instead of 90.39 % (19.7 more false
/// positives a drive); with the smoothness test alone, 89.64 %.
const LOWER_HIDDEN_MIN_UPPER_WIDTH: f64 = 2.5;

/// One cluster as the tracker sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct Observation {
    /// Mean of the points (world frame).
    pub centroid: Vector3<f64>,
    /// Visible outline in bird's-eye view.
    pub rect: Rect,
    /// World z of the ground below the centroid.
    pub ground_z: f64,
    /// Shape measures.
    pub shape: ShapeFeatures,
    /// The shape's verdict.
    pub verdict: ShapeVerdict,
    /// Number of points.
    pub points: usize,
    /// Whether the cluster reaches the range filter's outer limit: cut by it, its shape and
    /// its motion are those of the cut (a wall's far end slides along with the vehicle).
    pub clipped: bool,
}

impl Observation {
    /// The four corners of the visible outline.
    pub fn corners(&self) -> [Vector2<f64>; 4] {
        let axis = self.rect.axis();
        let normal = Vector2::new(-axis.y, axis.x);
        let (a, b) = (
            axis * self.rect.extent.x / 2.0,
            normal * self.rect.extent.y / 2.0,
        );
        let c = self.rect.center;
        [c + a + b, c + a - b, c - a + b, c - a - b]
    }
}

/// How far (m) beyond a face's end a sensor `range` metres away must stand to see a box's
/// second face across [`SECOND_FACE_COLUMNS`] columns: a face `D` deep seen from `b` beyond
/// the end spans about `D b / r` across, `D b / r²` radians. At 10 m that is 0.6 m, at 40 m
/// 9 m: a car's rear seen almost head-on at range hides its side.
fn second_face_offset(range: f64) -> f64 {
    SECOND_FACE_COLUMNS * SCAN_AZIMUTH_STEP * range * range / SECOND_FACE_DEPTH
}

/// Computes observations, reusing its buffers from cluster to cluster.
#[derive(Debug, Default)]
pub struct Observer {
    bev: Vec<Vector2<f64>>,
    heights: Vec<f64>,
}

impl Observer {
    /// Measures the cluster made of `points` (world frame), of mean surface variation
    /// `surface_variation`, in `scan`.
    pub fn observe(
        &mut self,
        points: &[Point],
        surface_variation: f32,
        scan: &ScanContext<'_>,
        classify: &ClassifyConfig,
    ) -> Observation {
        let (pose, ground) = (&scan.pose, scan.ground);
        self.bev.clear();
        self.heights.clear();
        let mut sum = Vector3::zeros();
        let sensor = pose.translation.vector;
        let mut farthest: f64 = 0.0;
        for p in points {
            let v = Vector3::new(p.x as f64, p.y as f64, p.z as f64);
            sum += v;
            farthest = farthest.max((v - sensor).norm_squared());
            self.bev.push(v.xy());
            self.heights.push(ground.height(&v));
        }
        let centroid = sum / points.len().max(1) as f64;
        let rect = fit_rectangle(&self.bev);
        let (bottom, top, lowest, highest) = self.heights.iter().enumerate().fold(
            (f64::MAX, f64::MIN, 0, 0),
            |(lo, hi, low_at, high_at), (i, &h)| {
                (
                    lo.min(h),
                    hi.max(h),
                    if h < lo { i } else { low_at },
                    if h > hi { i } else { high_at },
                )
            },
        );
        let (bottom, top) = if points.is_empty() {
            (0.0, 0.0)
        } else {
            (bottom, top)
        };
        // The highest point's elevation in the sensor frame.
        let truncated = points.get(highest).is_some_and(|p| {
            let q = pose.inverse_transform_point(&Point3::new(p.x as f64, p.y as f64, p.z as f64));
            let elevation = q.z.atan2(q.xy().coords.norm());
            elevation.to_degrees()
                >= classify.sensor_upper_fov_deg - classify.truncation_tolerance_deg
        });
        let third = (top - bottom) / 3.0;
        let upper_width = self.spread(&rect, |h| h >= top - third);
        let lower_width = self.spread(&rect, |h| h <= bottom + third);
        // One face only, and the sensor well beyond its ends: seen edge-on.
        let long_axis = rect.long_axis();
        let to_sensor = sensor.xy() - rect.center;
        let beyond_end = to_sensor.dot(&long_axis).abs() - rect.extent.max() / 2.0;
        let oblique_face = rect.extent.min() < ONE_FACE_DEPTH
            && rect.extent.max() > MIN_OBLIQUE_FACE
            && beyond_end > OBLIQUE_MARGIN.max(second_face_offset(to_sensor.norm()));
        let range = (centroid - sensor).xy().norm();
        // Under the lowest point, half way down to the ground.
        let feet_hidden = bottom > classify.person_max_bottom
            && bottom <= classify.max_hidden_bottom
            && points
                .get(lowest)
                .is_some_and(|p| hidden_at(p, -bottom / 2.0, scan));
        // Under either end of the upper third, half way up the lower third.
        let lower_hidden = upper_width > lower_width
            && upper_width > LOWER_HIDDEN_MIN_UPPER_WIDTH
            && range <= LOWER_HIDDEN_MAX_RANGE
            && f64::from(surface_variation) <= LOWER_HIDDEN_MAX_SURFACE_VARIATION
            && self
                .upper_ends(&rect, top - third)
                .any(|i| hidden_at(&points[i], bottom + third / 2.0 - self.heights[i], scan));
        let shape = ShapeFeatures {
            length: rect.extent.max(),
            width: rect.extent.min(),
            top,
            bottom,
            upper_width,
            lower_width,
            truncated,
            oblique_face,
            surface_variation: f64::from(surface_variation),
            points_at_10m: points.len() as f64 * range * range / 100.0,
            range,
            feet_hidden,
            lower_hidden,
        };
        let clipped = farthest.sqrt() >= scan.range_limit - CLIP_MARGIN;
        Observation {
            centroid,
            rect,
            ground_z: ground.z_below(&centroid),
            shape,
            verdict: if clipped {
                ShapeVerdict::Unknown
            } else {
                classify_shape(&shape, classify)
            },
            points: points.len(),
            clipped,
        }
    }

    /// The points at either end of the upper part (heights from `from` up) along the
    /// rectangle's longer side: indices into the cluster's points.
    fn upper_ends(&self, rect: &Rect, from: f64) -> impl Iterator<Item = usize> {
        let axis = rect.long_axis();
        let along = |i: usize| axis.dot(&self.bev[i]);
        let upper = (0..self.bev.len()).filter(|&i| self.heights[i] >= from);
        let first = upper.clone().min_by(|&a, &b| along(a).total_cmp(&along(b)));
        let last = upper.max_by(|&a, &b| along(a).total_cmp(&along(b)));
        first.into_iter().chain(last)
    }

    /// Largest extent along the rectangle's axes of the points whose height passes `keep`.
    fn spread(&self, rect: &Rect, keep: impl Fn(f64) -> bool) -> f64 {
        let axis = rect.axis();
        let normal = Vector2::new(-axis.y, axis.x);
        let mut lo = Vector2::repeat(f64::MAX);
        let mut hi = Vector2::repeat(f64::MIN);
        for (p, &h) in self.bev.iter().zip(&self.heights) {
            if keep(h) {
                let q = Vector2::new(axis.dot(p), normal.dot(p));
                lo = lo.inf(&q);
                hi = hi.sup(&q);
            }
        }
        if lo.x > hi.x { 0.0 } else { (hi - lo).max() }
    }
}

/// Whether the scan `scan` shows something nearer than the point `dz` metres above `p`
/// (below, if negative): what hides that part of a view. `false` without the scan's range
/// image (no pose).
fn hidden_at(p: &Point, dz: f64, scan: &ScanContext<'_>) -> bool {
    let Some(view) = scan.views.and_then(|v| v.at(scan.timestamp)) else {
        return false;
    };
    let mut probe = Vector3::new(p.x, p.y, p.z).map(f64::from);
    probe.z += dz;
    let seen_from_sensor = view.pose.inverse_transform_point(&Point3::from(probe));
    view.image.visibility_across(&seen_from_sensor.coords, 0.0) == Visibility::Hidden
}

#[cfg(test)]
mod tests {
    use nalgebra::Isometry3;

    use super::*;
    use crate::ObjectClass;
    use crate::track::classify::StructureKind;
    use crate::track::ground::Ground;
    use crate::track::views::{RecentViews, View};
    use crate::track::visibility::RangeImage;

    /// The observation of `points` by a sensor 1.73 m above the origin, scan cut at 50 m.
    fn observe(points: &[Point], ground: &Ground) -> Observation {
        let scan = ScanContext {
            timestamp: 0.0,
            pose: Isometry3::translation(0.0, 0.0, 1.73),
            ground,
            range_limit: 50.0,
            views: None,
        };
        Observer::default().observe(points, 0.0, &scan, &ClassifyConfig::default())
    }

    /// A solid box of points (a grid over its four vertical faces).
    pub(crate) fn box_points(center: Vector3<f64>, l: f64, w: f64, h: f64) -> Vec<Point> {
        let mut out = Vec::new();
        let step = 0.1;
        let mut z = 0.0;
        while z <= h {
            let mut t = -l / 2.0;
            while t <= l / 2.0 {
                for s in [-w / 2.0, w / 2.0] {
                    out.push(Point::new(
                        (center.x + t) as f32,
                        (center.y + s) as f32,
                        (center.z + z) as f32,
                        0.0,
                    ));
                }
                t += step;
            }
            let mut t = -w / 2.0;
            while t <= w / 2.0 {
                for s in [-l / 2.0, l / 2.0] {
                    out.push(Point::new(
                        (center.x + s) as f32,
                        (center.y + t) as f32,
                        (center.z + z) as f32,
                        0.0,
                    ));
                }
                t += step;
            }
            z += step;
        }
        out
    }

    /// Height of the sensor above the flat ground of [`scan_over`].
    const SENSOR_HEIGHT: f64 = 1.73;

    /// A vertical face across the x axis: at `x`, spanning `y` across and `z` up from the
    /// ground.
    #[derive(Clone, Debug)]
    struct Face {
        x: f64,
        y: (f64, f64),
        z: (f64, f64),
    }

    /// A face 1 m wide across the x axis.
    fn narrow_face(x: f64, z_low: f64, z_high: f64) -> Face {
        Face {
            x,
            y: (-0.5, 0.5),
            z: (z_low, z_high),
        }
    }

    /// The returns (sensor frame) of a scan 0.1° by 0.2° fine, 10° to either side of the x
    /// axis and from 20° down to level, over flat ground and `faces`.
    fn scan_over(faces: &[Face]) -> Vec<Point> {
        scan_up_to(faces, 0)
    }

    /// [`scan_over`] with rays up to `top_row` × 0.2° above level.
    fn scan_up_to(faces: &[Face], top_row: i32) -> Vec<Point> {
        let mut out = Vec::new();
        for a in -100..=100 {
            for e in -100..=top_row {
                let (azimuth, elevation) = (f64::from(a) * 0.1, f64::from(e) * 0.2);
                let (azimuth, elevation) = (azimuth.to_radians(), elevation.to_radians());
                let ray = Vector3::new(
                    elevation.cos() * azimuth.cos(),
                    elevation.cos() * azimuth.sin(),
                    elevation.sin(),
                );
                let face = faces
                    .iter()
                    .map(|f| (ray * (f.x / ray.x), f))
                    .filter(|(p, f)| {
                        let z = p.z + SENSOR_HEIGHT;
                        (f.y.0..=f.y.1).contains(&p.y) && (f.z.0..=f.z.1).contains(&z)
                    })
                    .map(|(p, _)| p)
                    .min_by(|p, q| p.x.total_cmp(&q.x));
                let ground = (ray.z < 0.0).then(|| ray * (-SENSOR_HEIGHT / ray.z));
                let hit = match (face, ground) {
                    (Some(f), Some(g)) if g.x < f.x => Some(g),
                    (Some(f), _) => Some(f),
                    (None, g) => g,
                };
                if let Some(p) = hit.filter(|p| p.norm() < 60.0) {
                    out.push(Point::new(p.x as f32, p.y as f32, p.z as f32, 0.0));
                }
            }
        }
        out
    }

    /// The observation of the returns of `faces` beyond `from` metres (and 0.3 m above the
    /// ground), by a sensor 1.73 m above the origin that took the scan, with mean surface
    /// variation 0.
    fn observe_scan(faces: &[Face], from: f64) -> Observation {
        observe_returns(&scan_over(faces), from)
    }

    /// [`observe_scan`] of the scan `returns`.
    fn observe_returns(returns: &[Point], from: f64) -> Observation {
        let ground = Ground::horizontal(0.0);
        let sensor = Isometry3::translation(0.0, 0.0, SENSOR_HEIGHT);
        let cluster: Vec<Point> = returns
            .iter()
            .filter(|p| f64::from(p.x) > from && f64::from(p.z) + SENSOR_HEIGHT > 0.3)
            .map(|p| Point::new(p.x, p.y, p.z + SENSOR_HEIGHT as f32, 0.0))
            .collect();
        assert!(cluster.len() > 20, "{} returns", cluster.len());
        let mut image = RangeImage::default();
        image.build(returns);
        let mut views = RecentViews::new(1.0);
        views.push(View {
            timestamp: 0.0,
            pose: sensor,
            image,
        });
        let scan = ScanContext {
            timestamp: 0.0,
            pose: sensor,
            ground: &ground,
            range_limit: 50.0,
            views: Some(&views),
        };
        Observer::default().observe(&cluster, 0.0, &scan, &ClassifyConfig::default())
    }

    #[test]
    fn legs_behind_something_nearer_are_hidden_under_a_floating_thing_seen_through() {
        // A person's upper body 10 m away, 0.85-1.7 m up, with or without a car's side
        // (1.2 m tall) 6 m away in front of the legs.
        let upper_body = narrow_face(10.0, 0.85, 1.7);
        for (faces, hidden) in [
            (vec![narrow_face(6.0, 0.0, 1.2), upper_body.clone()], true),
            (vec![upper_body], false),
        ] {
            let o = observe_scan(&faces, 9.9);
            assert!((o.shape.bottom - 0.85).abs() < 0.1, "{}", o.shape.bottom);
            assert_eq!(o.shape.feet_hidden, hidden, "{faces:?}");
            let expected = if hidden {
                ShapeVerdict::Movable(ObjectClass::Pedestrian)
            } else {
                ShapeVerdict::Unknown
            };
            assert_eq!(o.verdict, expected);
        }
    }

    #[test]
    fn a_van_half_hidden_by_parked_cars_is_no_tree() {
        // 16 m away, a crown 3 m wide (1.2-2.2 m up) on a trunk 0.6 m wide: a tree.
        let crown = Face {
            x: 16.0,
            y: (-1.5, 1.5),
            z: (1.2, 2.2),
        };
        let trunk = Face {
            x: 16.0,
            y: (-0.3, 0.3),
            z: (0.0, 1.2),
        };
        let tree = observe_scan(&[crown, trunk], 15.9);
        assert!(!tree.shape.lower_hidden);
        assert_eq!(tree.verdict, ShapeVerdict::Structure(StructureKind::Tree));
        // A van's side (0.2-2.2 m up) as wide, behind two parked cars 10 m away (1.4 m tall)
        // with a gap between them: as narrow at the bottom, because the cars hide it.
        let van = Face {
            x: 16.0,
            y: (-1.5, 1.5),
            z: (0.2, 2.2),
        };
        let car = |y| Face {
            x: 10.0,
            y,
            z: (0.0, 1.4),
        };
        let faces = [car((-3.0, -0.25)), car((0.25, 3.0)), van];
        let van = observe_scan(&faces, 15.9);
        assert!(
            van.shape.upper_width > 2.5 * van.shape.lower_width,
            "{:?}",
            van.shape
        );
        assert!(van.shape.lower_hidden);
        assert_eq!(van.verdict, ShapeVerdict::Object(ObjectClass::Car));
    }

    #[test]
    fn a_van_seen_over_a_car_in_front_does_not_float() {
        // A van's rear 2 m wide (0.2-2.1 m up) 19 m away, the sensor's rays up to 1.4° above
        // level; a car's rear 1.45 m tall 10 m away hides it up to 1.2 m.
        let van = Face {
            x: 19.0,
            y: (-1.0, 1.0),
            z: (0.2, 2.1),
        };
        let car = Face {
            x: 10.0,
            y: (-1.5, 1.5),
            z: (0.0, 1.45),
        };
        let o = observe_returns(&scan_up_to(&[car, van.clone()], 7), 18.9);
        assert!(
            o.shape.bottom > ClassifyConfig::default().max_bottom_gap,
            "{:?}",
            o.shape
        );
        assert!(o.shape.feet_hidden);
        assert_eq!(o.verdict, ShapeVerdict::Object(ObjectClass::Car));
        // The same view with nothing in front: a sign, floating.
        let sign = Face {
            z: (1.2, 2.1),
            ..van
        };
        let o = observe_returns(&scan_up_to(&[sign], 7), 18.9);
        assert!(!o.shape.feet_hidden);
        assert_eq!(o.verdict, ShapeVerdict::Structure(StructureKind::Floating));
    }

    #[test]
    fn measures_a_car_on_a_tilted_ground() {
        // Ground rising 2 % along x; a 4.5 × 1.8 × 1.5 car starting 0.2 m above it at x = 10.
        let normal = Vector3::new(-0.02, 0.0, 1.0).normalize();
        let ground = Ground::plane(normal, 0.0);
        let base = Vector3::new(
            10.0,
            3.0,
            0.2 + ground.z_below(&Vector3::new(10.0, 3.0, 0.0)),
        );
        let points = box_points(base, 4.5, 1.8, 1.3);
        let o = observe(&points, &ground);
        assert!(!o.shape.truncated);
        assert!((o.shape.length - 4.5).abs() < 0.1);
        assert!((o.shape.width - 1.8).abs() < 0.1);
        assert!(
            (o.shape.bottom - 0.2).abs() < 0.1,
            "bottom {}",
            o.shape.bottom
        );
        assert!((o.shape.top - 1.5).abs() < 0.1, "top {}", o.shape.top);
        assert!((o.ground_z - 0.2).abs() < 0.05, "ground {}", o.ground_z);
        assert_eq!(o.verdict, ShapeVerdict::Object(ObjectClass::Car));
    }

    #[test]
    fn only_a_view_reaching_the_range_limit_is_clipped() {
        let ground = Ground::horizontal(0.0);
        // A pedestrian whose far side is 0.6 m short of the 50 m limit is whole...
        let whole = box_points(Vector3::new(49.1, 0.0, 0.0), 0.6, 0.5, 1.7);
        let o = observe(&whole, &ground);
        assert!(!o.clipped);
        assert_eq!(o.verdict, ShapeVerdict::Object(ObjectClass::Pedestrian));
        // ...a car whose returns run on to it may be longer than it looks.
        let cut: Vec<Point> = box_points(Vector3::new(48.0, 0.0, 0.0), 4.5, 1.8, 1.5)
            .into_iter()
            .filter(|p| p.x.hypot(p.y) <= 50.0)
            .collect();
        let o = observe(&cut, &ground);
        assert!(o.clipped);
        assert_eq!(o.verdict, ShapeVerdict::Unknown);
    }

    #[test]
    fn a_tree_is_wider_at_the_top() {
        let ground = Ground::horizontal(0.0);
        let mut points = box_points(Vector3::new(5.0, 5.0, 0.0), 0.3, 0.3, 2.0);
        points.extend(box_points(Vector3::new(5.0, 5.0, 2.0), 3.0, 3.0, 1.5));
        let o = observe(&points, &ground);
        assert!(o.shape.upper_width > 2.5 && o.shape.lower_width < 0.5);
        assert!(matches!(o.verdict, ShapeVerdict::Structure(_)));
    }

    #[test]
    fn a_top_at_the_edge_of_the_field_of_view_is_truncated() {
        let ground = Ground::horizontal(0.0);
        // At 8 m the +2° ray passes 1.73 + 8 tan 2° = 2.01 m above the ground.
        let post = box_points(Vector3::new(8.0, 0.0, 0.2), 0.5, 0.5, 1.9);
        let o = observe(&post, &ground);
        assert!(o.shape.truncated);
        let person = box_points(Vector3::new(8.0, 0.0, 0.2), 0.5, 0.5, 1.5);
        let o = observe(&person, &ground);
        assert!(!o.shape.truncated);
    }

    /// A vertical face `length` long through `center`, along `axis` (one column of points
    /// every 0.1 m, 0.3 to 1.8 m above the ground).
    fn face(center: Vector2<f64>, axis: Vector2<f64>, length: f64) -> Vec<Point> {
        let axis = axis.normalize();
        let mut out = Vec::new();
        for i in 0..=(length / 0.1).round() as i32 {
            let p = center + axis * (i as f64 * 0.1 - length / 2.0);
            for j in 0..6 {
                out.push(Point::new(
                    p.x as f32,
                    p.y as f32,
                    0.3 + j as f32 * 0.3,
                    0.0,
                ));
            }
        }
        out
    }

    #[test]
    fn a_face_is_edge_on_only_when_a_second_face_would_show() {
        let ground = Ground::horizontal(0.0);
        // A car's rear 2 m wide, 44 m ahead, the sensor 2.6 m to the side of its axis: 1.6 m
        // beyond its end, from where a car's side would span about one column. Not edge-on.
        let rear = face(Vector2::new(44.0, 2.6), Vector2::new(0.0, 1.0), 2.0);
        assert!(!observe(&rear, &ground).shape.oblique_face);
        // A fence strip 4 m long, 30 m away, seen along its length: edge-on.
        let strip = face(Vector2::new(30.0, 3.0), Vector2::new(1.0, 0.2), 4.0);
        let o = observe(&strip, &ground);
        assert!(o.shape.oblique_face);
        assert_eq!(o.verdict, ShapeVerdict::Unknown);
        // Near the sensor 1.6 m beyond the end is enough.
        let near = face(Vector2::new(8.0, 2.6), Vector2::new(0.0, 1.0), 2.0);
        assert!(observe(&near, &ground).shape.oblique_face);
    }
}
