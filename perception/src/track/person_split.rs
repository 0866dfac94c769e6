//! Peeling people off a cluster. DBSCAN, with the `eps` that keeps a distant car in one
//! piece, joins two riders side by side 0.3 m apart, or a pedestrian and the parked car beside
//! them. Their upper bodies still stand apart: seen from above, the points higher than
//! `UPPER_BODY` above the ground fall into separate connected footprints, one per torso
//! (a car's cabin gives one large footprint). Every other point of the cluster then goes to
//! the nearest such footprint. When the parts so grown are all whole people (a person-sized
//! torso, standing on the ground, person-high, person-sized) or posts beside one (a part no
//! wider than a pole and taller than any person: a sign's, a lamp's, a traffic light's), each
//! becomes a cluster of its own; a person-shaped part of a larger cluster is as often a post by
//! a hedge as a pedestrian by a car, and such clusters stay whole.
//!
//! This needs no track: it separates the two cyclists of the paper's scene from their first
//! scan on, before the track-guided split ([`super::split`]) can help.

use std::ops::Range;

use nalgebra::Vector3;

use super::classify::ClassifyConfig;
use super::ground::Ground;
use super::parts::PartWriter;
use super::raster::{MARKED, Raster, UNLABELLED};
use crate::Point;

/// Points at least this high above the ground (m) are upper body: torso, arms, head.
const UPPER_BODY: f32 = 0.9;
/// Largest footprint (m) of one upper body, along and across: a rider's torso with the arms
/// reaching for the handlebar.
const TORSO: [f32; 2] = [1.3, 0.9];
/// Points farther than this (m) from every upper body are no part of a person.
const ATTACH_DISTANCE: f32 = 1.2;
/// Cell size (m) at short range...
const MIN_CELL: f32 = 0.1;
/// ...and per metre of range: 2.5 times the azimuth spacing of a 64-beam scanner (0.17°), so
/// that one surface fills its cells without holes.
const CELL_PER_METRE: f32 = 0.0075;
/// Largest cell (m).
const MAX_CELL: f32 = 0.25;
/// Clusters with fewer points are left alone: too few to hold two people.
const MIN_POINTS: usize = 16;
/// Clusters farther than this (m) are left alone: a gap between two people is then a few
/// missing returns, and a distant car's cabin falls apart the same way.
const MAX_RANGE: f32 = 30.0;
/// Clusters larger than this (m) on a side are structure: not split.
const MAX_EXTENT: f32 = 12.0;
/// Clusters smaller than this (m) on both sides hold one person at most.
const MIN_EXTENT: f32 = 0.8;
/// Fewest points of a person peeled off a cluster.
const MIN_PERSON_POINTS: usize = 8;

/// What a part must look like to be peeled off as a person.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PersonShape {
    /// Fewest points.
    pub min_points: usize,
    /// Longest side of the footprint (m): a cyclist seen from the side.
    pub max_length: f32,
    /// Shorter side of the footprint (m).
    pub max_width: f32,
    /// Lowest and highest top above the ground (m).
    pub top: [f32; 2],
    /// Highest lowest point above the ground (m): people stand on it.
    pub max_bottom: f32,
    /// Widest footprint (m, either side) of a pole: a part this thin and taller than any
    /// person is a post, a sign's or a lamp's, and a person beside it is peeled off it.
    pub pole_max_footprint: f32,
}

impl PersonShape {
    /// A pedestrian's or a cyclist's shape as the identification's thresholds give it.
    pub fn of(c: &ClassifyConfig) -> Self {
        Self {
            min_points: MIN_PERSON_POINTS,
            max_length: c.cyclist_max_length as f32,
            max_width: c.person_max_width as f32,
            top: [c.min_object_height as f32, c.person_max_height as f32],
            max_bottom: c.person_max_bottom as f32,
            pole_max_footprint: c.pole_max_footprint as f32,
        }
    }

    /// A standing pedestrian's shape: no longer than a pedestrian.
    pub fn standing(c: &ClassifyConfig) -> Self {
        Self {
            max_length: c.pedestrian_max_length as f32,
            ..Self::of(c)
        }
    }
}

/// The footprint and height range of a set of points.
#[derive(Clone, Copy, Debug)]
struct Extent {
    points: usize,
    /// Sums of x, y, x², xy, y² (relative to the raster's corner).
    moments: [f64; 5],
    bottom: f32,
    top: f32,
    /// Lowest and highest coordinate along the principal axis, then across it.
    along: [f32; 2],
    across: [f32; 2],
}

impl Extent {
    fn new() -> Self {
        Self {
            points: 0,
            moments: [0.0; 5],
            bottom: f32::MAX,
            top: f32::MIN,
            along: [f32::MAX, f32::MIN],
            across: [f32::MAX, f32::MIN],
        }
    }

    fn add(&mut self, x: f32, y: f32, height: f32) {
        let (x, y) = (f64::from(x), f64::from(y));
        self.points += 1;
        for (m, v) in self.moments.iter_mut().zip([x, y, x * x, x * y, y * y]) {
            *m += v;
        }
        self.bottom = self.bottom.min(height);
        self.top = self.top.max(height);
    }

    /// The unit principal axis of the footprint.
    fn axis(&self) -> [f32; 2] {
        let n = self.points.max(1) as f64;
        let [sx, sy, sxx, sxy, syy] = self.moments;
        let (mx, my) = (sx / n, sy / n);
        let (cxx, cxy, cyy) = (sxx / n - mx * mx, sxy / n - mx * my, syy / n - my * my);
        let angle = 0.5 * (2.0 * cxy).atan2(cxx - cyy);
        [angle.cos() as f32, angle.sin() as f32]
    }

    /// Widens the extents along `axis` to hold (x, y).
    fn stretch(&mut self, axis: [f32; 2], x: f32, y: f32) {
        let along = axis[0] * x + axis[1] * y;
        let across = -axis[1] * x + axis[0] * y;
        self.along = [self.along[0].min(along), self.along[1].max(along)];
        self.across = [self.across[0].min(across), self.across[1].max(across)];
    }

    /// Distance (m) from (x, y) to the footprint's rectangle along `axis`; 0 inside.
    fn distance(&self, axis: [f32; 2], x: f32, y: f32) -> f32 {
        let along = axis[0] * x + axis[1] * y;
        let across = -axis[1] * x + axis[0] * y;
        let da = (self.along[0] - along).max(along - self.along[1]).max(0.0);
        let dc = (self.across[0] - across)
            .max(across - self.across[1])
            .max(0.0);
        da.hypot(dc)
    }

    /// Longer and shorter side of the footprint.
    fn sides(&self) -> [f32; 2] {
        let (a, b) = (
            self.along[1] - self.along[0],
            self.across[1] - self.across[0],
        );
        [a.max(b), a.min(b)]
    }
}

/// What a torso's part is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Part {
    /// A whole person.
    Person,
    /// A post beside a person.
    Pole,
    /// Anything else: left with the rest.
    Other,
}

/// Reusable buffers of the split.
#[derive(Debug, Default)]
pub struct PersonSplitter {
    heights: Vec<f32>,
    cells: Vec<u32>,
    /// Per cell: the upper body it belongs to.
    owner: Vec<u32>,
    stack: Vec<u32>,
    torsos: Vec<Extent>,
    parts: Vec<Extent>,
    slot_of_point: Vec<u32>,
    writer: PartWriter,
}

impl PersonSplitter {
    /// Splits the cluster `points` (world frame; reordered in place), seen from `sensor`
    /// (world x, y), above `ground`: appends the ranges of its parts to `parts` (relative to
    /// `points`) — each person peeled off, then the rest — and returns how many.
    pub fn split(
        &mut self,
        points: &mut [Point],
        sensor: [f64; 2],
        ground: &Ground,
        shape: &PersonShape,
        parts: &mut Vec<Range<usize>>,
    ) -> usize {
        match self.raster(points, sensor) {
            Some(raster) => match self.find_torsos(points, ground, &raster) {
                torsos if torsos >= 2 => self.share_out(points, &raster, torsos, shape, parts),
                _ => {
                    parts.push(0..points.len());
                    1
                }
            },
            None => {
                parts.push(0..points.len());
                1
            }
        }
    }

    /// The raster of a cluster worth splitting.
    fn raster(&self, points: &[Point], sensor: [f64; 2]) -> Option<Raster> {
        if points.len() < MIN_POINTS {
            return None;
        }
        let (mut min, mut max) = ([f32::MAX; 2], [f32::MIN; 2]);
        for p in points {
            min = [min[0].min(p.x), min[1].min(p.y)];
            max = [max[0].max(p.x), max[1].max(p.y)];
        }
        let extent = [max[0] - min[0], max[1] - min[1]];
        let longest = extent[0].max(extent[1]);
        if !longest.is_finite() || !(MIN_EXTENT..=MAX_EXTENT).contains(&longest) {
            return None;
        }
        let range = (f64::from(min[0] + max[0]) / 2.0 - sensor[0])
            .hypot(f64::from(min[1] + max[1]) / 2.0 - sensor[1]) as f32;
        if range > MAX_RANGE {
            return None;
        }
        let cell = (range * CELL_PER_METRE).clamp(MIN_CELL, MAX_CELL);
        Some(Raster::over(min, max, cell))
    }

    /// Labels the connected footprints of the upper-body points; returns how many.
    fn find_torsos(&mut self, points: &[Point], ground: &Ground, raster: &Raster) -> usize {
        self.owner.clear();
        self.owner.resize(raster.len(), UNLABELLED);
        self.heights.clear();
        self.cells.clear();
        for p in points {
            let v = Vector3::new(f64::from(p.x), f64::from(p.y), f64::from(p.z));
            let h = ground.height(&v) as f32;
            let cell = raster.cell_of(p);
            self.heights.push(h);
            self.cells.push(cell as u32);
            if h >= UPPER_BODY {
                self.owner[cell] = MARKED;
            }
        }
        raster.label_groups(&mut self.owner, &mut self.stack) as usize
    }

    /// Measures the torsos, gives every point to the nearest one (or to the rest when all
    /// are far), measures the parts so grown and writes them out.
    fn share_out(
        &mut self,
        points: &mut [Point],
        raster: &Raster,
        torsos: usize,
        shape: &PersonShape,
        parts: &mut Vec<Range<usize>>,
    ) -> usize {
        let local = |p: &Point| (p.x - raster.min[0], p.y - raster.min[1]);
        self.torsos.clear();
        self.torsos.resize(torsos, Extent::new());
        for (p, (&cell, &h)) in points.iter().zip(self.cells.iter().zip(&self.heights)) {
            if h >= UPPER_BODY {
                let (x, y) = local(p);
                self.torsos[self.owner[cell as usize] as usize].add(x, y, h);
            }
        }
        let axes: Vec<[f32; 2]> = self.torsos.iter().map(Extent::axis).collect();
        for (p, (&cell, &h)) in points.iter().zip(self.cells.iter().zip(&self.heights)) {
            if h >= UPPER_BODY {
                let owner = self.owner[cell as usize] as usize;
                let (x, y) = local(p);
                self.torsos[owner].stretch(axes[owner], x, y);
            }
        }
        // Each point's torso: its own for upper-body points, else the nearest within reach.
        const REST: u32 = UNLABELLED;
        self.slot_of_point.clear();
        for (p, (&cell, &h)) in points.iter().zip(self.cells.iter().zip(&self.heights)) {
            let owner = if h >= UPPER_BODY {
                self.owner[cell as usize]
            } else {
                let (x, y) = local(p);
                self.torsos
                    .iter()
                    .zip(&axes)
                    .map(|(t, &axis)| t.distance(axis, x, y))
                    .enumerate()
                    .filter(|&(_, d)| d <= ATTACH_DISTANCE)
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .map_or(REST, |(k, _)| k as u32)
            };
            self.slot_of_point.push(owner);
        }
        self.parts.clear();
        self.parts.resize(torsos, Extent::new());
        for (p, (&owner, &h)) in points
            .iter()
            .zip(self.slot_of_point.iter().zip(&self.heights))
        {
            if owner != REST {
                let (x, y) = local(p);
                self.parts[owner as usize].add(x, y, h);
            }
        }
        let part_axes: Vec<[f32; 2]> = self.parts.iter().map(Extent::axis).collect();
        for (p, &owner) in points.iter().zip(&self.slot_of_point) {
            if owner != REST {
                let (x, y) = local(p);
                self.parts[owner as usize].stretch(part_axes[owner as usize], x, y);
            }
        }
        // A person: a torso-sized upper body, and grown from it a whole person. A pole: a
        // thin part taller than any person.
        let kinds: Vec<Part> = self
            .torsos
            .iter()
            .zip(&self.parts)
            .map(|(t, p)| {
                let (torso, part) = (t.sides(), p.sides());
                let person = torso[0] <= TORSO[0]
                    && torso[1] <= TORSO[1]
                    && p.points >= shape.min_points
                    && part[0] <= shape.max_length
                    && part[1] <= shape.max_width
                    && (shape.top[0]..=shape.top[1]).contains(&p.top)
                    && p.bottom <= shape.max_bottom;
                if person {
                    Part::Person
                } else if part[0] <= shape.pole_max_footprint && p.top > shape.top[1] {
                    Part::Pole
                } else {
                    Part::Other
                }
            })
            .collect();
        let people = kinds.iter().filter(|&&k| k == Part::Person).count();
        let apart = people + kinds.iter().filter(|&&k| k == Part::Pole).count();
        // Output slot of each torso's part: people and poles first, in order; the rest last.
        let mut slot = vec![apart as u32; torsos];
        let mut next = 0;
        for (k, kind) in kinds.iter().enumerate() {
            if *kind != Part::Other {
                slot[k] = next;
                next += 1;
            }
        }
        let mut sizes = vec![0usize; apart + 1];
        for s in &mut self.slot_of_point {
            *s = if *s == REST {
                apart as u32
            } else {
                slot[*s as usize]
            };
            sizes[*s as usize] += 1;
        }
        // Only a cluster made of people (and poles) is split: a person-shaped part of a
        // larger cluster is as often a post by a hedge as a pedestrian by a car.
        let split = people >= 1 && apart >= 2 && sizes[apart] <= points.len() / 10;
        if !split {
            parts.push(0..points.len());
            return 1;
        }
        self.writer
            .write(points, &self.slot_of_point, apart + 1, parts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rider seen from behind at x = `x`: a 0.6 m wide upper body from 0.9 to 1.8 m and a
    /// bicycle wheel below it, 0.7 m nearer the sensor and not touching it from above.
    fn rider(x: f32, y: f32) -> Vec<Point> {
        let mut out = Vec::new();
        for i in 0..13 {
            for k in 9..18 {
                out.push(Point::new(
                    x,
                    y - 0.3 + i as f32 * 0.05,
                    k as f32 * 0.1,
                    0.0,
                ));
            }
        }
        for k in 0..7 {
            out.push(Point::new(x - 0.7, y, k as f32 * 0.1, 0.0));
            out.push(Point::new(x - 0.7, y + 0.03, k as f32 * 0.1, 0.0));
        }
        out
    }

    fn split(points: &mut [Point]) -> Vec<Range<usize>> {
        let mut parts = Vec::new();
        PersonSplitter::default().split(
            points,
            [0.0, 0.0],
            &Ground::horizontal(0.0),
            &PersonShape::of(&ClassifyConfig::default()),
            &mut parts,
        );
        parts
    }

    fn spread_y(points: &[Point]) -> f32 {
        let ys = points.iter().map(|p| p.y);
        ys.clone().fold(f32::MIN, f32::max) - ys.fold(f32::MAX, f32::min)
    }

    #[test]
    fn two_riders_a_hand_apart_become_two_whole_riders() {
        // Centres 0.9 m apart: a 0.3 m gap, which DBSCAN with eps 0.7 bridges.
        let one = rider(14.0, 0.0).len();
        let mut points = rider(14.0, 0.0);
        points.extend(rider(14.0, 0.9));
        let parts = split(&mut points);
        assert_eq!(parts.len(), 2, "{parts:?}");
        for r in &parts {
            assert_eq!(r.len(), one, "each rider keeps their wheel");
            assert!(spread_y(&points[r.clone()]) < 0.7);
        }
    }

    #[test]
    fn a_person_beside_a_car_stays_with_it() {
        // A car's side seen from y = -10: 4 m long, 1.4 m high, at y = 0; a person 0.4 m
        // beyond its end. A person-shaped part of a larger cluster is as often a post by a
        // hedge: only clusters made of people are split.
        let mut points = Vec::new();
        for i in 0..80 {
            for k in 0..14 {
                points.push(Point::new(10.0 + i as f32 * 0.05, 0.0, k as f32 * 0.1, 0.0));
            }
        }
        for i in 0..10 {
            for k in 0..17 {
                points.push(Point::new(14.4 + i as f32 * 0.05, 0.0, k as f32 * 0.1, 0.0));
            }
        }
        let parts = split(&mut points);
        assert_eq!(parts, vec![0..points.len()]);
    }

    #[test]
    fn three_people_in_a_row_become_three() {
        let one = rider(14.0, 0.0).len();
        let mut points = rider(14.0, 0.0);
        points.extend(rider(14.0, 0.9));
        points.extend(rider(14.0, 1.8));
        let parts = split(&mut points);
        assert_eq!(parts.len(), 3, "{parts:?}");
        assert!(parts.iter().all(|r| r.len() == one));
    }

    #[test]
    fn one_object_without_a_gap_stays_whole() {
        let mut points = rider(14.0, 0.0);
        points.extend(rider(14.0, 0.6));
        let before = points.clone();
        let parts = split(&mut points);
        assert_eq!(parts, vec![0..points.len()]);
        assert_eq!(points, before);
    }

    #[test]
    fn low_parts_are_not_people() {
        // Two knee-high blocks a metre apart: nothing reaches the upper body.
        let mut points: Vec<Point> = rider(14.0, 0.0)
            .into_iter()
            .map(|mut p| {
                p.z *= 0.4;
                p
            })
            .collect();
        points.extend(points.clone().into_iter().map(|mut p| {
            p.y += 1.0;
            p
        }));
        let parts = split(&mut points);
        assert_eq!(parts, vec![0..points.len()]);
    }

    /// A post at (x, y): 0.1 m thick, from the ground to `top`.
    fn post(x: f32, y: f32, top: f32) -> Vec<Point> {
        let mut out = Vec::new();
        for k in 0..(top * 10.0) as usize {
            for i in 0..3 {
                out.push(Point::new(x, y + i as f32 * 0.05, k as f32 * 0.1, 0.0));
            }
        }
        out
    }

    #[test]
    fn a_person_beside_a_post_is_peeled_off_it() {
        // A 3.5 m sign post 0.5 m from a rider: DBSCAN joins them, and the cluster, taller
        // than a person, would be nothing but structure.
        let one = rider(14.0, 0.0).len();
        let mut points = rider(14.0, 0.0);
        points.extend(post(14.0, 0.8, 3.5));
        let parts = split(&mut points);
        assert_eq!(parts.len(), 2, "{parts:?}");
        let rider = parts
            .iter()
            .find(|r| r.len() == one)
            .expect("the rider, whole");
        let top = points[rider.clone()]
            .iter()
            .map(|p| p.z)
            .fold(f32::MIN, f32::max);
        assert!(
            top < 2.0,
            "the rider's part holds none of the post: top {top}"
        );
    }

    #[test]
    fn posts_alone_are_not_split() {
        // Two posts and no person: a gantry, a fence; nothing to peel.
        let mut points = post(14.0, 0.0, 3.5);
        points.extend(post(14.0, 0.8, 3.5));
        let parts = split(&mut points);
        assert_eq!(parts, vec![0..points.len()]);
    }

    #[test]
    fn a_person_beside_a_sign_wider_than_a_post_stays_with_it() {
        // A 1.2 m board on its post is no post: the cluster stays whole.
        let mut points = rider(14.0, 0.0);
        points.extend(post(14.0, 0.8, 3.5));
        for i in 0..24 {
            for k in 0..5 {
                points.push(Point::new(
                    14.0,
                    0.4 + i as f32 * 0.05,
                    2.5 + k as f32 * 0.1,
                    0.0,
                ));
            }
        }
        let parts = split(&mut points);
        assert_eq!(parts, vec![0..points.len()]);
    }
}
