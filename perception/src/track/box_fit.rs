//! Oriented boxes from partial views, in bird's-eye view.
//!
//! A LiDAR sees the faces of an object that look at it: a car seen from behind is a 1.8 m
//! segment whose centroid lies some 2 m before the car's centre. Two steps turn a cluster into
//! a box whose centre is right:
//! 1. [`fit_rectangle`]: the orientation of the visible outline, by L-shape fitting (search
//!    over angles, closeness criterion of Zhang et al., "Efficient L-shape fitting for vehicle
//!    detection using laser scanners", IV 2017).
//! 2. [`place_box`]: given a heading and the object's full size (a class prior or the track's
//!    smoothed size), the box keeps the visible faces nearest the sensor and extends away from
//!    it.

use std::f64::consts::FRAC_PI_2;

use nalgebra::Vector2;

/// At most this many points enter the angle search (the cluster is strided down).
const MAX_FIT_POINTS: usize = 256;
/// Coarse angle step of the search, then the fine step around the best coarse angle (rad).
const COARSE_STEP: f64 = 3.0 * std::f64::consts::PI / 180.0;
const FINE_STEP: f64 = 0.5 * std::f64::consts::PI / 180.0;
/// Distances below this (m) count as this in the closeness score, so points on an edge do
/// not dominate.
const MIN_CLOSENESS_DISTANCE: f32 = 0.05;

/// An oriented rectangle in the ground plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// Centre of the visible outline (m).
    pub center: Vector2<f64>,
    /// Direction of the first axis (rad, in [0, π/2)).
    pub yaw: f64,
    /// Extent along the first axis and along the second (m).
    pub extent: Vector2<f64>,
}

impl Rect {
    /// The first axis' direction as a unit vector.
    pub fn axis(&self) -> Vector2<f64> {
        Vector2::new(self.yaw.cos(), self.yaw.sin())
    }

    /// The direction of the longer side as a unit vector (the first axis on a tie).
    pub fn long_axis(&self) -> Vector2<f64> {
        let axis = self.axis();
        if self.extent.x >= self.extent.y {
            axis
        } else {
            Vector2::new(-axis.y, axis.x)
        }
    }
}

/// Orientation and visible extents of the outline of `points` (x, y). An empty input gives a
/// zero rectangle at the origin.
pub fn fit_rectangle(points: &[Vector2<f64>]) -> Rect {
    if points.is_empty() {
        return Rect {
            center: Vector2::zeros(),
            yaw: 0.0,
            extent: Vector2::zeros(),
        };
    }
    let stride = points.len().div_ceil(MAX_FIT_POINTS);
    let mut sample = Sample {
        x: [0.0; MAX_FIT_POINTS],
        y: [0.0; MAX_FIT_POINTS],
        len: 0,
    };
    // The score does not change with translation: the sample is taken relative to the first
    // point, where f32 is precise to micrometres.
    let origin = points[0];
    for p in points.iter().step_by(stride) {
        sample.x[sample.len] = (p.x - origin.x) as f32;
        sample.y[sample.len] = (p.y - origin.y) as f32;
        sample.len += 1;
    }
    let score = |angle: f64| sample.closeness(angle);
    let mut best = (f64::NEG_INFINITY, 0.0);
    let mut angle = 0.0;
    while angle < FRAC_PI_2 {
        let s = score(angle);
        if s > best.0 {
            best = (s, angle);
        }
        angle += COARSE_STEP;
    }
    let coarse = best.1;
    let mut offset = -COARSE_STEP;
    while offset <= COARSE_STEP {
        let a = coarse + offset;
        let s = score(a);
        if s > best.0 {
            best = (s, a);
        }
        offset += FINE_STEP;
    }
    let yaw = best.1.rem_euclid(FRAC_PI_2);
    let (lo, hi) = extents(points, yaw);
    let axis = Vector2::new(yaw.cos(), yaw.sin());
    let normal = Vector2::new(-axis.y, axis.x);
    let mid = (lo + hi) / 2.0;
    Rect {
        center: axis * mid.x + normal * mid.y,
        yaw,
        extent: hi - lo,
    }
}

/// The points the angle search scores, coordinates apart (x, then y) and in `f32` so that
/// each angle's two passes over them run on whole registers, four points at a time.
struct Sample {
    x: [f32; MAX_FIT_POINTS],
    y: [f32; MAX_FIT_POINTS],
    len: usize,
}

impl Sample {
    /// Closeness score of the rectangle at `angle`: points near its edges score high. The
    /// scores are added in point order.
    fn closeness(&self, angle: f64) -> f64 {
        let (c, s) = (angle.cos() as f32, angle.sin() as f32);
        let (x, y) = (&self.x[..self.len], &self.y[..self.len]);
        let (mut min1, mut max1, mut min2, mut max2) = (f32::MAX, f32::MIN, f32::MAX, f32::MIN);
        for (&px, &py) in x.iter().zip(y) {
            let (a, b) = (c * px + s * py, -s * px + c * py);
            min1 = min1.min(a);
            max1 = max1.max(a);
            min2 = min2.min(b);
            max2 = max2.max(b);
        }
        let mut scores = [0.0f32; MAX_FIT_POINTS];
        for ((score, &px), &py) in scores.iter_mut().zip(x).zip(y) {
            let (a, b) = (c * px + s * py, -s * px + c * py);
            let d1 = (a - min1).min(max1 - a);
            let d2 = (b - min2).min(max2 - b);
            *score = 1.0 / d1.min(d2).max(MIN_CLOSENESS_DISTANCE);
        }
        scores[..self.len].iter().map(|&s| f64::from(s)).sum()
    }
}

/// Lowest and highest coordinates of `points` along the axis at `yaw` and its normal.
fn extents(points: &[Vector2<f64>], yaw: f64) -> (Vector2<f64>, Vector2<f64>) {
    let (c, s) = (yaw.cos(), yaw.sin());
    let mut lo = Vector2::repeat(f64::MAX);
    let mut hi = Vector2::repeat(f64::MIN);
    for p in points {
        let q = Vector2::new(c * p.x + s * p.y, -s * p.x + c * p.y);
        lo = lo.inf(&q);
        hi = hi.sup(&q);
    }
    (lo, hi)
}

/// Two faces both shorter than the prior width plus this (m) do not tell length from width.
const AMBIGUOUS_FACE_MARGIN: f64 = 0.5;

/// Which of the rectangle's axes is the object's length, from one view seen from
/// `viewpoint`. When the view shows one face (the other extent below `single_face_depth`),
/// that face is the width if its extent is nearer the prior `width` than the prior `length`
/// (a car seen from behind), else the length. When it shows two faces the longer one is the
/// length, unless both could be the width (a distant van's back and the first metre of its
/// side): then the length is the axis nearer the line of sight, as a face seen at a grazing
/// angle is sparse and breaks off at range while a face turned to the sensor shows whole.
/// Returns the heading (modulo π).
pub fn length_heading(
    rect: &Rect,
    length: f64,
    width: f64,
    single_face_depth: f64,
    viewpoint: &Vector2<f64>,
) -> f64 {
    let (e1, e2) = (rect.extent.x, rect.extent.y);
    let first_is_length = if e1.min(e2) < single_face_depth {
        let face = e1.max(e2);
        let face_is_width = (face - width).abs() < (face - length).abs();
        // The face is the first axis when e1 is the larger extent.
        (e1 >= e2) != face_is_width
    } else if e1.max(e2) <= width + AMBIGUOUS_FACE_MARGIN && length > width + AMBIGUOUS_FACE_MARGIN
    {
        let sight = rect.center - viewpoint;
        let across = (rect.axis().perp(&sight) / sight.norm().max(1e-9)).abs();
        across < std::f64::consts::FRAC_1_SQRT_2
    } else {
        e1 >= e2
    };
    if first_is_length {
        rect.yaw
    } else {
        rect.yaw + FRAC_PI_2
    }
}

/// Centre of a box of full `size` (length, width) with heading `heading` that holds the
/// visible `points`: along each axis the face nearest to `viewpoint` stays where it is seen
/// and the box extends away from the viewpoint; an axis seen wider than `size` keeps its
/// visible extent.
pub fn place_box(
    points: &[Vector2<f64>],
    heading: f64,
    size: Vector2<f64>,
    viewpoint: &Vector2<f64>,
) -> Vector2<f64> {
    let (lo, hi) = extents(points, heading);
    let (c, s) = (heading.cos(), heading.sin());
    let view = Vector2::new(
        c * viewpoint.x + s * viewpoint.y,
        -s * viewpoint.x + c * viewpoint.y,
    );
    let mut center = Vector2::zeros();
    for k in 0..2 {
        let visible = hi[k] - lo[k];
        let full = size[k].max(visible);
        center[k] = if view[k] <= lo[k] {
            lo[k] + full / 2.0
        } else if view[k] >= hi[k] {
            hi[k] - full / 2.0
        } else {
            (lo[k] + hi[k]) / 2.0
        };
    }
    Vector2::new(c * center.x - s * center.y, s * center.x + c * center.y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::track::motion::wrap_angle;
    use std::f64::consts::PI;

    /// Points on the faces of a `l` × `w` box at `center`/`yaw` visible from `viewpoint`
    /// (a face is visible when the viewpoint is on its outer side).
    fn visible_outline(
        center: Vector2<f64>,
        yaw: f64,
        l: f64,
        w: f64,
        viewpoint: Vector2<f64>,
    ) -> Vec<Vector2<f64>> {
        let axis = Vector2::new(yaw.cos(), yaw.sin());
        let normal = Vector2::new(-axis.y, axis.x);
        let mut out = Vec::new();
        // (face centre offset, face direction, face half extent)
        let faces = [
            (axis * l / 2.0, normal, w / 2.0),
            (-axis * l / 2.0, normal, w / 2.0),
            (normal * w / 2.0, axis, l / 2.0),
            (-normal * w / 2.0, axis, l / 2.0),
        ];
        for (offset, dir, half) in faces {
            let face_center = center + offset;
            if (viewpoint - face_center).dot(&offset) <= 0.0 {
                continue;
            }
            let n = (half * 2.0 / 0.1).ceil() as i32;
            for i in 0..=n {
                let t = -half + 2.0 * half * i as f64 / n as f64;
                out.push(face_center + dir * t);
            }
        }
        out
    }

    fn heading_error(a: f64, b: f64) -> f64 {
        let d = wrap_angle(a - b).abs();
        d.min(PI - d)
    }

    #[test]
    fn fits_the_orientation_of_an_l_shaped_view() {
        for yaw in [0.0, 0.3, 0.8, 1.2, 2.0, -0.6] {
            let center = Vector2::new(12.0, 5.0);
            let pts = visible_outline(center, yaw, 4.5, 1.8, Vector2::zeros());
            let rect = fit_rectangle(&pts);
            let heading = length_heading(&rect, 4.5, 1.8, 0.5, &Vector2::zeros());
            assert!(heading_error(heading, yaw) < 0.03, "yaw {yaw}: {heading}");
        }
    }

    #[test]
    fn a_car_seen_from_behind_gets_its_centre_two_metres_further() {
        // Car 10 m ahead, driving away along +x: only its rear face is visible.
        let center = Vector2::new(10.0, 0.0);
        let pts = visible_outline(center, 0.0, 4.5, 1.8, Vector2::zeros());
        let centroid = pts.iter().sum::<Vector2<f64>>() / pts.len() as f64;
        assert!((centroid - center).norm() > 2.0);
        let rect = fit_rectangle(&pts);
        let heading = length_heading(&rect, 4.5, 1.8, 0.5, &Vector2::zeros());
        assert!(heading_error(heading, 0.0) < 0.03, "heading {heading}");
        let placed = place_box(&pts, heading, Vector2::new(4.5, 1.8), &Vector2::zeros());
        assert!((placed - center).norm() < 0.1, "placed at {placed}");
    }

    #[test]
    fn a_distant_vans_back_and_a_metre_of_its_side_give_a_length_along_the_sight() {
        // A 5.1 x 2.0 m van 40 m ahead, slightly to the left, pointing away: its back is seen
        // whole, its side only for the first metre (the rest breaks off at a grazing angle).
        let (center, yaw) = (Vector2::new(40.0, 3.0), 0.0);
        let near_end = center.x - 2.55;
        let pts: Vec<_> = visible_outline(center, yaw, 5.1, 2.0, Vector2::zeros())
            .into_iter()
            .filter(|p| p.x < near_end + 1.0)
            .collect();
        let rect = fit_rectangle(&pts);
        assert!(
            rect.extent.min() > 0.5 && rect.extent.max() < 2.5,
            "{rect:?}"
        );
        let heading = length_heading(&rect, 4.5, 1.8, 0.5, &Vector2::zeros());
        assert!(heading_error(heading, yaw) < 0.05, "heading {heading}");
        // The same outline seen from beside the van is a side turned to the sensor.
        let beside = Vector2::new(center.x - 2.0, center.y + 30.0);
        let heading = length_heading(&rect, 4.5, 1.8, 0.5, &beside);
        assert!(
            heading_error(heading, yaw + FRAC_PI_2) < 0.05,
            "heading {heading}"
        );
    }

    #[test]
    fn a_car_seen_from_the_side_keeps_its_length_axis() {
        let center = Vector2::new(0.0, 8.0);
        let pts = visible_outline(center, 0.0, 4.5, 1.8, Vector2::zeros());
        let rect = fit_rectangle(&pts);
        let heading = length_heading(&rect, 4.5, 1.8, 0.5, &Vector2::zeros());
        assert!(heading_error(heading, 0.0) < 0.03);
        let placed = place_box(&pts, heading, Vector2::new(4.5, 1.8), &Vector2::zeros());
        assert!((placed - center).norm() < 0.1, "placed at {placed}");
    }

    #[test]
    fn a_corner_view_anchors_on_the_visible_corner() {
        let center = Vector2::new(15.0, -6.0);
        let yaw: f64 = 0.5;
        // Only part of each face is seen (occlusion): keep points near the visible corner.
        let axis = Vector2::new(yaw.cos(), yaw.sin());
        let normal = Vector2::new(-axis.y, axis.x);
        let corner = [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)]
            .map(|(a, b)| center + axis * 2.25 * a + normal * 0.9 * b)
            .into_iter()
            .min_by(|a, b| a.norm().total_cmp(&b.norm()))
            .unwrap_or(center);
        let pts: Vec<_> = visible_outline(center, yaw, 4.5, 1.8, Vector2::zeros())
            .into_iter()
            .filter(|p| (p - corner).norm() < 1.5)
            .collect();
        let rect = fit_rectangle(&pts);
        let placed = place_box(&pts, yaw, Vector2::new(4.5, 1.8), &Vector2::zeros());
        assert!(heading_error(rect.yaw, yaw) < 0.05);
        assert!((placed - center).norm() < 0.15, "placed at {placed}");
    }

    #[test]
    fn a_box_seen_larger_than_its_prior_keeps_the_visible_extent() {
        let center = Vector2::new(10.0, 8.0);
        let pts = visible_outline(center, 0.2, 12.0, 2.5, Vector2::zeros());
        let placed = place_box(&pts, 0.2, Vector2::new(4.5, 1.8), &Vector2::zeros());
        // The 12 m length and 2.5 m width are seen whole (side and rear): the centre is the
        // outline's middle.
        assert!((placed - center).norm() < 0.05, "placed at {placed}");
    }
}
