//! Paths on the ground: chains of straight lines and circular arcs, sampled by arc length.
//!
//! Lines and arcs keep every quantity exact: heading, curvature (so yaw rate = curvature ×
//! speed) and lanes (the offset of an arc is an arc).

use nalgebra::Vector2;

/// A position and heading on the ground plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose2 {
    /// Position in metres (world x east, y north).
    pub position: Vector2<f64>,
    /// Heading in radians, counter-clockwise from east.
    pub heading: f64,
}

impl Pose2 {
    /// A pose at (x, y) heading `heading`.
    pub fn new(x: f64, y: f64, heading: f64) -> Self {
        Self {
            position: Vector2::new(x, y),
            heading,
        }
    }

    /// Unit vector along the heading.
    pub fn forward(&self) -> Vector2<f64> {
        Vector2::new(self.heading.cos(), self.heading.sin())
    }

    /// Unit vector to the left of the heading.
    pub fn left(&self) -> Vector2<f64> {
        Vector2::new(-self.heading.sin(), self.heading.cos())
    }

    /// The pose after driving `length` metres at constant `curvature` (1/m, + turns left).
    fn advance(&self, length: f64, curvature: f64) -> Self {
        if curvature.abs() < 1e-12 {
            return Self {
                position: self.position + self.forward() * length,
                heading: self.heading,
            };
        }
        let h = self.heading + curvature * length;
        let d = Vector2::new(h.sin() - self.heading.sin(), self.heading.cos() - h.cos());
        Self {
            position: self.position + d / curvature,
            heading: h,
        }
    }
}

/// A point of a path: pose and curvature.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathPoint {
    /// Pose on the path.
    pub pose: Pose2,
    /// Curvature (1/m, positive turning left).
    pub curvature: f64,
}

/// One piece of a path: constant curvature over a length.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Segment {
    /// Arc length at the segment's start.
    s0: f64,
    /// Pose at the segment's start.
    start: Pose2,
    length: f64,
    curvature: f64,
}

/// A chain of lines and arcs. Beyond its ends a path goes on straight, so a trajectory
/// sampled past them stays defined.
#[derive(Clone, Debug, PartialEq)]
pub struct Path {
    start: Pose2,
    segments: Vec<Segment>,
    length: f64,
}

impl Path {
    /// Starts building a path at `start`.
    pub fn from(start: Pose2) -> PathBuilder {
        PathBuilder {
            start,
            pieces: Vec::new(),
        }
    }

    /// A straight path of `length` metres.
    pub fn line(start: Pose2, length: f64) -> Self {
        Self::from(start).line(length).build()
    }

    /// A path through `points` (at least two, consecutive ones distinct): straight between
    /// them, corners rounded with arcs of `radius` (smaller where the legs are short).
    pub fn through(points: &[Vector2<f64>], radius: f64) -> Self {
        let heading = |a: Vector2<f64>, b: Vector2<f64>| (b.y - a.y).atan2(b.x - a.x);
        let first = match points {
            [a, b, ..] => Pose2 {
                position: *a,
                heading: heading(*a, *b),
            },
            [a] => Pose2::new(a.x, a.y, 0.0),
            [] => Pose2::new(0.0, 0.0, 0.0),
        };
        let legs: Vec<(f64, f64)> = points
            .windows(2)
            .map(|w| ((w[1] - w[0]).norm(), heading(w[0], w[1])))
            .collect();
        // Signed turn and tangent length at each interior corner.
        let corners: Vec<(f64, f64)> = legs
            .windows(2)
            .map(|w| {
                let turn = wrap_angle(w[1].1 - w[0].1);
                let half_tan = (turn.abs() / 2.0).tan();
                let tangent = (radius * half_tan).min(w[0].0 / 2.0).min(w[1].0 / 2.0);
                (turn, tangent)
            })
            .collect();
        let mut b = Self::from(first);
        for (i, (len, _)) in legs.iter().enumerate() {
            let before = if i > 0 { corners[i - 1].1 } else { 0.0 };
            let after = corners.get(i).map_or(0.0, |c| c.1);
            b = b.line((len - before - after).max(0.0));
            if let Some(&(turn, tangent)) = corners.get(i)
                && turn.abs() > 1e-9
            {
                let r = tangent / (turn.abs() / 2.0).tan();
                b = b.arc(r.max(1e-3), turn);
            }
        }
        b.build()
    }

    /// Total length in metres.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// The start pose.
    pub fn start(&self) -> Pose2 {
        self.start
    }

    /// The pose and curvature at arc length `s` (straight continuation outside [0, length]).
    pub fn sample(&self, s: f64) -> PathPoint {
        if s <= 0.0 || self.segments.is_empty() {
            return PathPoint {
                pose: self.start.advance(s, 0.0),
                curvature: 0.0,
            };
        }
        let i = self.segments.partition_point(|seg| seg.s0 <= s) - 1;
        let seg = &self.segments[i];
        let u = s - seg.s0;
        if u > seg.length {
            // Past the end of the last segment.
            let end = seg.start.advance(seg.length, seg.curvature);
            return PathPoint {
                pose: end.advance(u - seg.length, 0.0),
                curvature: 0.0,
            };
        }
        PathPoint {
            pose: seg.start.advance(u, seg.curvature),
            curvature: seg.curvature,
        }
    }

    /// The end pose.
    pub fn end(&self) -> Pose2 {
        self.sample(self.length).pose
    }

    /// The path `d` metres to the left (right if negative): a lane of a road. Arcs must have
    /// radii larger than `d` on their inner side.
    pub fn offset(&self, d: f64) -> Self {
        let start = Pose2 {
            position: self.start.position + self.start.left() * d,
            heading: self.start.heading,
        };
        let mut b = Self::from(start);
        for seg in &self.segments {
            let k = 1.0 - seg.curvature * d;
            b.pieces.push((seg.length * k, seg.curvature / k));
        }
        b.build()
    }

    /// The same path driven the other way.
    pub fn reversed(&self) -> Self {
        let end = self.end();
        let mut b = Self::from(Pose2 {
            position: end.position,
            heading: end.heading + std::f64::consts::PI,
        });
        for seg in self.segments.iter().rev() {
            b.pieces.push((seg.length, -seg.curvature));
        }
        b.build()
    }
}

/// Builds a [`Path`] piece by piece.
#[derive(Clone, Debug)]
pub struct PathBuilder {
    start: Pose2,
    /// (length, curvature) of each piece.
    pieces: Vec<(f64, f64)>,
}

impl PathBuilder {
    /// Adds a straight piece of `length` metres.
    pub fn line(mut self, length: f64) -> Self {
        self.pieces.push((length, 0.0));
        self
    }

    /// Adds an arc of `radius` metres turning by `angle` radians (positive: left).
    pub fn arc(mut self, radius: f64, angle: f64) -> Self {
        let curvature = angle.signum() / radius;
        self.pieces.push((radius * angle.abs(), curvature));
        self
    }

    /// Adds a lane change: two opposite arcs moving the path `lateral` metres to the left
    /// (right if negative) over `length` metres of travel.
    pub fn lane_change(self, lateral: f64, length: f64) -> Self {
        let (dx, dy) = (length / 2.0, lateral.abs() / 2.0);
        let r = (dx * dx + dy * dy) / (2.0 * dy);
        let angle = (dx / r).asin() * lateral.signum();
        self.arc(r, angle).arc(r, -angle)
    }

    /// The finished path.
    pub fn build(self) -> Path {
        let mut segments = Vec::with_capacity(self.pieces.len());
        let mut pose = self.start;
        let mut s0 = 0.0;
        for (length, curvature) in self.pieces {
            if length <= 0.0 {
                continue;
            }
            segments.push(Segment {
                s0,
                start: pose,
                length,
                curvature,
            });
            pose = pose.advance(length, curvature);
            s0 += length;
        }
        Path {
            start: self.start,
            segments,
            length: s0,
        }
    }
}

/// An angle wrapped into (-π, π].
pub fn wrap_angle(a: f64) -> f64 {
    let w = a.rem_euclid(std::f64::consts::TAU);
    if w > std::f64::consts::PI {
        w - std::f64::consts::TAU
    } else {
        w
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    #[test]
    fn line_then_quarter_arc_ends_where_expected() {
        let p = Path::from(Pose2::new(0.0, 0.0, 0.0))
            .line(10.0)
            .arc(5.0, FRAC_PI_2)
            .build();
        let end = p.end();
        assert!(
            (end.position - Vector2::new(15.0, 5.0)).norm() < 1e-9,
            "{end:?}"
        );
        assert!((end.heading - FRAC_PI_2).abs() < 1e-12);
        assert!((p.length() - (10.0 + 5.0 * FRAC_PI_2)).abs() < 1e-12);
        assert!((p.sample(12.0).curvature - 0.2).abs() < 1e-12);
        // Past the end it goes on straight north.
        let after = p.sample(p.length() + 3.0).pose.position;
        assert!((after - Vector2::new(15.0, 8.0)).norm() < 1e-9);
    }

    #[test]
    fn offset_lane_stays_parallel() {
        let p = Path::from(Pose2::new(0.0, 0.0, 0.3))
            .line(20.0)
            .arc(40.0, 0.6)
            .line(10.0)
            .arc(30.0, -0.4)
            .build();
        let lane = p.offset(-1.75);
        for i in 0..50 {
            let s = i as f64 * p.length() / 49.0;
            let a = p.sample(s).pose;
            // The lane point nearest to a is 1.75 m to its right.
            let expected = a.position - a.left() * 1.75;
            let best = (0..2000)
                .map(|j| lane.sample(j as f64 * lane.length() / 1999.0).pose.position)
                .map(|q| (q - expected).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(best < 0.05, "s {s}: {best}");
        }
    }

    #[test]
    fn reversed_path_retraces_backwards() {
        let p = Path::from(Pose2::new(1.0, 2.0, 0.0))
            .line(5.0)
            .arc(10.0, 1.0)
            .build();
        let r = p.reversed();
        for i in 0..=10 {
            let s = i as f64 * p.length() / 10.0;
            let a = p.sample(s).pose;
            let b = r.sample(p.length() - s).pose;
            assert!((a.position - b.position).norm() < 1e-9);
            assert!(wrap_angle(a.heading + PI - b.heading).abs() < 1e-9);
        }
    }

    #[test]
    fn through_waypoints_passes_near_each_corner_and_ends_on_the_last() {
        let pts = [
            Vector2::new(0.0, 0.0),
            Vector2::new(10.0, 0.0),
            Vector2::new(10.0, 10.0),
            Vector2::new(0.0, 12.0),
        ];
        let p = Path::through(&pts, 2.0);
        assert!((p.end().position - pts[3]).norm() < 1e-9, "{:?}", p.end());
        // The corner is cut by r (√2 − 1) at most.
        let near = (0..1000)
            .map(|i| p.sample(i as f64 * p.length() / 999.0).pose.position)
            .map(|q| (q - pts[1]).norm())
            .fold(f64::INFINITY, f64::min);
        assert!(near < 2.0 * (2f64.sqrt() - 1.0) + 1e-3, "{near}");
    }

    #[test]
    fn lane_change_moves_sideways_and_keeps_heading() {
        let p = Path::from(Pose2::new(0.0, 0.0, 0.0))
            .lane_change(3.75, 60.0)
            .build();
        let end = p.end();
        assert!(
            (end.position - Vector2::new(60.0, 3.75)).norm() < 1e-9,
            "{end:?}"
        );
        assert!(end.heading.abs() < 1e-12);
    }
}
