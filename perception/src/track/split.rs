//! Track-guided splitting: DBSCAN merges two riders a metre apart into one cluster; when a
//! cluster holds the predicted boxes of several confirmed tracks, its points are shared out
//! among them, each point to the box it lies in (or nearest to), so that every track keeps
//! its own measurement and the riders keep their ids. A cluster claimed by one moving person
//! alone and reaching well beyond their box (a walker passing a bush, a parked car, a wall) is
//! carved: the points near the box are the person, the rest a part of its own.

use std::ops::Range;

use nalgebra::Vector2;

use super::parts::PartWriter;
use super::tracker::PredictedBox;
use crate::Point;

/// A box claims a cluster when at least this many of its points lie in the box grown by
/// [`CLAIM_MARGIN`].
const MIN_CLAIMED_POINTS: usize = 5;
/// Margin (m) around a predicted box within which its points are claimed.
const CLAIM_MARGIN: f64 = 0.25;
/// Points farther than this (m) from every claiming box form a part of their own.
const OWNERLESS_DISTANCE: f64 = 1.0;
/// A cluster claimed by one moving person is carved when at least [`MIN_CLAIMED_POINTS`] of
/// its points lie this far (m) from their box: more than a swinging arm or a prediction a
/// little off.
const CARVE_REACH: f64 = 0.6;

/// Reusable buffers of the split.
#[derive(Debug, Default)]
pub struct Splitter {
    claimants: Vec<BoxFrame>,
    owner: Vec<u32>,
    writer: PartWriter,
}

impl Splitter {
    /// Splits the cluster `points` (world frame; reordered in place) among the `boxes` that
    /// claim it. Appends the ranges of the parts to `parts` (relative to `points`) and returns
    /// how many were appended: one (the whole cluster) when fewer than two boxes claim it.
    pub fn split(
        &mut self,
        points: &mut [Point],
        boxes: &[PredictedBox],
        parts: &mut Vec<Range<usize>>,
    ) -> usize {
        self.claimants.clear();
        let bounds = bev_bounds(points);
        for bx in boxes {
            let bx = BoxFrame::new(bx);
            if !bounds.is_some_and(|b| bx.may_reach(&b, CLAIM_MARGIN)) {
                continue;
            }
            let inside = points
                .iter()
                .filter(|p| bx.outside_distance(p) <= CLAIM_MARGIN)
                .take(MIN_CLAIMED_POINTS)
                .count();
            if inside >= MIN_CLAIMED_POINTS {
                self.claimants.push(bx);
            }
        }
        if let [person] = self.claimants.as_slice()
            && person.moving_person
        {
            return self.carve(points, parts);
        }
        if self.claimants.len() < 2 {
            parts.push(0..points.len());
            return 1;
        }
        // Owner of each point: the claiming box it is nearest to (inside counts as 0, ties go
        // to the nearer centre); the last slot gathers points far from every box.
        let ownerless = self.claimants.len() as u32;
        self.owner.clear();
        for p in points.iter() {
            let mut best = (f64::INFINITY, f64::INFINITY, ownerless);
            for (slot, bx) in self.claimants.iter().enumerate() {
                let d = bx.outside_distance(p);
                let c = bx.normalised_centre_distance(p);
                if d <= OWNERLESS_DISTANCE && (d, c) < (best.0, best.1) {
                    best = (d, c, slot as u32);
                }
            }
            self.owner.push(best.2);
        }
        let owners = self.claimants.len() + 1;
        self.writer.write(points, &self.owner, owners, parts)
    }

    /// Carves the one claimant, a moving person, out of `points` when enough of them lie
    /// [`CARVE_REACH`] beyond its box: the points within [`CLAIM_MARGIN`] of it are one part,
    /// the others another. Otherwise the cluster stays whole.
    fn carve(&mut self, points: &mut [Point], parts: &mut Vec<Range<usize>>) -> usize {
        let person = &self.claimants[0];
        let beyond = points
            .iter()
            .filter(|p| person.outside_distance(p) > CARVE_REACH)
            .take(MIN_CLAIMED_POINTS)
            .count();
        if beyond < MIN_CLAIMED_POINTS {
            parts.push(0..points.len());
            return 1;
        }
        self.owner.clear();
        self.owner.extend(
            points
                .iter()
                .map(|p| u32::from(person.outside_distance(p) > CLAIM_MARGIN)),
        );
        self.writer.write(points, &self.owner, 2, parts)
    }
}

/// The ground-plane bounds `[min_x, min_y, max_x, max_y]` of `points`; `None` when empty.
fn bev_bounds(points: &[Point]) -> Option<[f64; 4]> {
    let first = points.first()?;
    let mut b = [first.x, first.y, first.x, first.y];
    for p in points {
        b = [b[0].min(p.x), b[1].min(p.y), b[2].max(p.x), b[3].max(p.y)];
    }
    Some(b.map(f64::from))
}

/// A predicted box with its heading's sine and cosine worked out once.
#[derive(Debug)]
struct BoxFrame {
    center: Vector2<f64>,
    half: Vector2<f64>,
    sin: f64,
    cos: f64,
    moving_person: bool,
}

impl BoxFrame {
    fn new(bx: &PredictedBox) -> Self {
        let (sin, cos) = bx.heading.sin_cos();
        Self {
            center: bx.center,
            half: bx.size / 2.0,
            sin,
            cos,
            moving_person: bx.moving_person,
        }
    }

    /// Whether any point within `margin` of the box can lie in `bounds`: the box's enclosing
    /// circle, grown by `margin`, meets them.
    fn may_reach(&self, bounds: &[f64; 4], margin: f64) -> bool {
        let reach = self.half.norm() + margin;
        let dx = (bounds[0] - self.center.x)
            .max(self.center.x - bounds[2])
            .max(0.0);
        let dy = (bounds[1] - self.center.y)
            .max(self.center.y - bounds[3])
            .max(0.0);
        dx * dx + dy * dy <= reach * reach
    }

    /// The point in the box's frame.
    fn local(&self, p: &Point) -> Vector2<f64> {
        let d = Vector2::new(p.x as f64, p.y as f64) - self.center;
        Vector2::new(
            self.cos * d.x + self.sin * d.y,
            -self.sin * d.x + self.cos * d.y,
        )
    }

    /// Distance (m, ground plane) from `p` to the box; 0 inside.
    fn outside_distance(&self, p: &Point) -> f64 {
        let q = self.local(p);
        let dx = (q.x.abs() - self.half.x).max(0.0);
        let dy = (q.y.abs() - self.half.y).max(0.0);
        (dx * dx + dy * dy).sqrt()
    }

    /// Distance from the box centre in units of the half extents.
    fn normalised_centre_distance(&self, p: &Point) -> f64 {
        let q = self.local(p);
        let u = q.x / self.half.x.max(0.1);
        let v = q.y / self.half.y.max(0.1);
        (u * u + v * v).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rider(cx: f64, cy: f64) -> Vec<Point> {
        let mut out = Vec::new();
        for i in 0..18 {
            for z in 0..15 {
                let x = cx - 0.9 + i as f64 * 0.1;
                out.push(Point::new(x as f32, cy as f32, z as f32 * 0.12, 0.0));
            }
        }
        out
    }

    fn predicted(id: u64, cx: f64, cy: f64) -> PredictedBox {
        PredictedBox {
            id,
            center: Vector2::new(cx, cy),
            heading: 0.0,
            size: Vector2::new(1.8, 0.6),
            moving_vehicle: false,
            moving_person: false,
        }
    }

    #[test]
    fn shares_a_merged_cluster_between_the_riders_it_holds() {
        let mut points = rider(10.0, 0.0);
        points.extend(rider(10.0, 1.0));
        let n = points.len();
        let boxes = [
            predicted(1, 10.1, 0.05),
            predicted(2, 9.9, 0.95),
            predicted(3, 30.0, 0.0),
        ];
        let mut parts = Vec::new();
        assert_eq!(
            Splitter::default().split(&mut points, &boxes, &mut parts),
            2
        );
        assert_eq!(parts, vec![0..n / 2, n / 2..n]);
        assert!(points[parts[0].clone()].iter().all(|p| p.y.abs() < 0.01));
        assert!(
            points[parts[1].clone()]
                .iter()
                .all(|p| (p.y - 1.0).abs() < 0.01)
        );
    }

    #[test]
    fn a_cluster_claimed_once_stays_whole() {
        let mut points = rider(10.0, 0.0);
        let before = points.clone();
        let mut parts = Vec::new();
        let boxes = [predicted(1, 10.0, 0.0), predicted(2, 10.0, 3.0)];
        assert_eq!(
            Splitter::default().split(&mut points, &boxes, &mut parts),
            1
        );
        assert_eq!(parts, vec![0..points.len()]);
        assert_eq!(points, before);
    }

    /// A low bush 1.6 m wide beside (x > 10.4) a pedestrian standing at (10, 0).
    fn walker_by_a_bush() -> Vec<Point> {
        let mut points = Vec::new();
        for i in 0..5 {
            for z in 0..15 {
                let x = 9.8 + i as f32 * 0.1;
                points.push(Point::new(x, 0.0, z as f32 * 0.12, 0.0));
            }
        }
        for i in 0..16 {
            for j in 0..8 {
                let (x, y) = (10.5 + i as f32 * 0.1, -0.4 + j as f32 * 0.1);
                points.push(Point::new(x, y, 0.5, 0.0));
            }
        }
        points
    }

    #[test]
    fn a_moving_person_is_carved_out_of_what_they_pass() {
        let mut points = walker_by_a_bush();
        let walker = PredictedBox {
            size: Vector2::new(0.8, 0.6),
            moving_person: true,
            ..predicted(1, 10.0, 0.0)
        };
        let mut parts = Vec::new();
        assert_eq!(
            Splitter::default().split(&mut points, &[walker], &mut parts),
            2
        );
        let person = &points[parts[0].clone()];
        assert!(
            person.iter().all(|p| p.x < 10.7),
            "only the walker and the bush's edge"
        );
        assert_eq!(person.iter().filter(|p| p.x < 10.3).count(), 5 * 15);
        assert!(points[parts[1].clone()].iter().all(|p| p.x > 10.6));
        // A person not seen to move (a post by a hedge looks alike) leaves the cluster whole.
        let still = PredictedBox {
            moving_person: false,
            ..walker
        };
        parts.clear();
        assert_eq!(
            Splitter::default().split(&mut walker_by_a_bush(), &[still], &mut parts),
            1
        );
    }

    #[test]
    fn a_moving_person_with_little_beyond_their_box_stays_whole() {
        let mut points = rider(10.0, 0.0);
        // An arm's few returns 0.7 m beyond the box.
        points.extend((0..3).map(|i| Point::new(11.6, 0.0, 1.0 + i as f32 * 0.1, 0.0)));
        let rider_box = PredictedBox {
            moving_person: true,
            ..predicted(1, 10.0, 0.0)
        };
        let mut parts = Vec::new();
        assert_eq!(
            Splitter::default().split(&mut points, &[rider_box], &mut parts),
            1
        );
    }

    #[test]
    fn points_far_from_every_box_form_their_own_part() {
        let mut points = rider(10.0, 0.0);
        points.extend(rider(10.0, 1.0));
        points.extend(rider(13.5, 0.5));
        let boxes = [predicted(1, 10.0, 0.0), predicted(2, 10.0, 1.0)];
        let mut parts = Vec::new();
        assert_eq!(
            Splitter::default().split(&mut points, &boxes, &mut parts),
            3
        );
        assert!(points[parts[2].clone()].iter().all(|p| p.x > 12.5));
    }
}
