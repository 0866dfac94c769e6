//! Peeling people who stand by a facade off it. DBSCAN joins a person standing half a metre
//! from a wall, a fence, a hedge or a row of parked cars to it, and the whole is longer than
//! any car: it would be taken for structure, and the person with it. Seen from above, though,
//! the person's body stands apart from the wall: the points higher than `BODY` above the
//! ground fall into separate connected footprints, the wall's long and the person's small,
//! since the person hides the wall right behind them. A footprint is peeled off, with the
//! points below it, when it has a person's size, height and depth, stands on the ground, near
//! enough to be seen whole, and nothing else of the cluster stands in front of it (a piece of
//! the facade set back behind the rest is seen past it, a person is not). The rest stays as it
//! was. (A moving person's track claims its part of such a cluster by itself, later: see
//! [`super::split`].)

use std::ops::Range;

use nalgebra::Vector3;

use super::ground::Ground;
use super::parts::PartWriter;
use super::person_split::PersonShape;
use super::raster::{MARKED, Raster, UNLABELLED};
use crate::Point;

/// Points at least this high above the ground (m) are body: kerbs, low walls' footings and
/// ground clutter below it do not join a person to the facade.
const BODY: f32 = 0.3;
/// Cell edge (m): a person's footprint fills its cells 30 m away (columns 9 cm apart), and a
/// person 0.2 m from the wall stands a cell apart from it.
const CELL: f32 = 0.1;
/// Least depth (m, the footprint's shorter side) of a person: a body is round, while a piece
/// of a wall between the shadows of things in front of it is a line.
const MIN_DEPTH: f32 = 0.15;
/// How much nearer (m) than a footprint another point of the cluster in its direction must lie
/// to stand in front of it.
const SET_BACK: f32 = 0.1;
/// People farther than this (m) are not peeled: a gap to the wall is then a few missing
/// returns.
const MAX_RANGE: f32 = 30.0;

/// The footprint and height range of one group of cells.
#[derive(Clone, Copy, Debug)]
struct Footprint {
    points: usize,
    min: [f32; 2],
    max: [f32; 2],
    bottom: f32,
    top: f32,
}

impl Footprint {
    fn new() -> Self {
        Self {
            points: 0,
            min: [f32::MAX; 2],
            max: [f32::MIN; 2],
            bottom: f32::MAX,
            top: f32::MIN,
        }
    }

    fn add(&mut self, p: &Point, height: f32) {
        self.points += 1;
        self.min = [self.min[0].min(p.x), self.min[1].min(p.y)];
        self.max = [self.max[0].max(p.x), self.max[1].max(p.y)];
        self.bottom = self.bottom.min(height);
        self.top = self.top.max(height);
    }

    /// The centre of the footprint's bounds, relative to `sensor`.
    fn center_from(&self, sensor: [f64; 2]) -> [f32; 2] {
        [
            (self.min[0] + self.max[0]) / 2.0 - sensor[0] as f32,
            (self.min[1] + self.max[1]) / 2.0 - sensor[1] as f32,
        ]
    }

    /// Whether this is a person standing within `MAX_RANGE` of `sensor`. The footprint's
    /// sides are taken along x and y: a person's is small either way.
    fn is_person(&self, shape: &PersonShape, sensor: [f64; 2]) -> bool {
        let sides = [self.max[0] - self.min[0], self.max[1] - self.min[1]];
        let (long, short) = (sides[0].max(sides[1]), sides[0].min(sides[1]));
        let center = self.center_from(sensor);
        let range = center[0].hypot(center[1]);
        self.points >= shape.min_points
            && long <= shape.max_length
            && (MIN_DEPTH..=shape.max_width).contains(&short)
            && (shape.top[0]..=shape.top[1]).contains(&self.top)
            && self.bottom <= shape.max_bottom
            && range <= MAX_RANGE
    }
}

/// Reusable buffers of the peel.
#[derive(Debug, Default)]
pub struct StandingPeeler {
    /// Per point: its height above the ground and its cell.
    heights: Vec<f32>,
    cells: Vec<u32>,
    /// Per raster cell: its footprint, or [`MARKED`] while it waits for one; [`UNLABELLED`]
    /// between calls.
    owner: Vec<u32>,
    /// The cells holding body points.
    marked: Vec<u32>,
    stack: Vec<u32>,
    /// Per point: its footprint.
    group_of_point: Vec<u32>,
    footprints: Vec<Footprint>,
    /// Per footprint: its output slot.
    slot: Vec<u32>,
    slot_of_point: Vec<u32>,
    writer: PartWriter,
}

impl StandingPeeler {
    /// Peels the people standing by the structure `points` (world frame; reordered in
    /// place), seen from `sensor` (world x, y), above `ground`: appends to `people` the range
    /// of each person peeled off and returns the range of the rest (relative to `points`).
    pub fn peel(
        &mut self,
        points: &mut [Point],
        sensor: [f64; 2],
        ground: &Ground,
        shape: &PersonShape,
        people: &mut Vec<Range<usize>>,
    ) -> Range<usize> {
        let all = 0..points.len();
        let Some(raster) = raster_near(points, sensor) else {
            return all;
        };
        if self.owner.len() < raster.len() {
            self.owner.resize(raster.len(), UNLABELLED);
        }
        self.heights.clear();
        self.cells.clear();
        self.marked.clear();
        for p in points.iter() {
            let Some(cell) = raster.cell_inside(p) else {
                // Farther than any person peeled, and so in front of none.
                self.heights.push(f32::NAN);
                self.cells.push(OUTSIDE);
                continue;
            };
            let v = Vector3::new(f64::from(p.x), f64::from(p.y), f64::from(p.z));
            let h = ground.height(&v) as f32;
            self.heights.push(h);
            self.cells.push(cell as u32);
            if h >= BODY && self.owner[cell] != MARKED {
                self.owner[cell] = MARKED;
                self.marked.push(cell as u32);
            }
        }
        // Only the marked cells are visited: a facade 60 m long fills a fraction of its
        // raster.
        let marked = self.marked.iter().map(|&cell| cell as usize);
        let groups = raster.label_groups_from(marked, &mut self.owner, &mut self.stack) as usize;
        self.group_of_point.clear();
        for &cell in &self.cells {
            let group = match cell {
                OUTSIDE => UNLABELLED,
                cell => self.owner[cell as usize],
            };
            self.group_of_point.push(group);
        }
        // Leave every cell unlabelled for the next cluster.
        for &cell in &self.marked {
            self.owner[cell as usize] = UNLABELLED;
        }
        // Each group with every point of its cells, the low ones included (the feet).
        self.footprints.clear();
        self.footprints.resize(groups, Footprint::new());
        for (p, (&group, &h)) in points
            .iter()
            .zip(self.group_of_point.iter().zip(&self.heights))
        {
            if group != UNLABELLED {
                self.footprints[group as usize].add(p, h);
            }
        }
        self.slot.clear();
        let mut persons = 0u32;
        for (k, f) in self.footprints.iter().enumerate() {
            if f.is_person(shape, sensor) && self.stands_in_front(k as u32, points, sensor) {
                self.slot.push(persons);
                persons += 1;
            } else {
                self.slot.push(u32::MAX);
            }
        }
        if persons == 0 {
            return all;
        }
        // People first, each in its own slot; the rest in the last.
        self.slot_of_point.clear();
        for &group in &self.group_of_point {
            let slot = match group {
                UNLABELLED => persons,
                group => self.slot[group as usize].min(persons),
            };
            self.slot_of_point.push(slot);
        }
        let written = self
            .writer
            .write(points, &self.slot_of_point, persons as usize + 1, people);
        if written > persons as usize {
            people.pop().unwrap_or(all)
        } else {
            points.len()..points.len()
        }
    }

    /// Whether nothing else of the cluster `points` lies in front of footprint `k`, seen from
    /// `sensor`: a person stands before the facade and hides it, while a piece of the facade
    /// set back behind the rest of it (a doorway, a recess, a gap in a fence) is seen past it.
    fn stands_in_front(&self, k: u32, points: &[Point], sensor: [f64; 2]) -> bool {
        let (sx, sy) = (sensor[0] as f32, sensor[1] as f32);
        let f = &self.footprints[k as usize];
        let center = f.center_from(sensor);
        let norm = center[0].hypot(center[1]).max(1e-3);
        let d = [center[0] / norm, center[1] / norm];
        // Along the footprint's direction `d`: the distance and the tangent of the bearing.
        let seen = |p: &Point| {
            let v = [p.x - sx, p.y - sy];
            let along = d[0] * v[0] + d[1] * v[1];
            let across = d[0] * v[1] - d[1] * v[0];
            (along, across / along.max(1e-3))
        };
        let (mut nearest, mut spread) = (f32::MAX, 0.0f32);
        for (p, &group) in points.iter().zip(&self.group_of_point) {
            if group == k {
                let (along, bearing) = seen(p);
                nearest = nearest.min(along);
                spread = spread.max(bearing.abs());
            }
        }
        // What hides a footprint stands in front of it at the height of its body: a crown
        // above a walker's head or the kerb at their feet does not.
        let body = BODY..=f.top;
        let mut others = points.iter().zip(&self.group_of_point).zip(&self.heights);
        !others.any(|((p, &group), h)| {
            let (along, bearing) = seen(p);
            group != k
                && body.contains(h)
                && along > 0.0
                && along < nearest - SET_BACK
                && bearing.abs() <= spread
        })
    }
}

/// Cell of the points outside the raster.
const OUTSIDE: u32 = u32::MAX;

/// The raster over the points of `points` within [`MAX_RANGE`] of `sensor` (plus a margin),
/// if there are any.
fn raster_near(points: &[Point], sensor: [f64; 2]) -> Option<Raster> {
    let reach = (MAX_RANGE + 1.0).powi(2);
    let (mut min, mut max) = ([f32::MAX; 2], [f32::MIN; 2]);
    let (sx, sy) = (sensor[0] as f32, sensor[1] as f32);
    for p in points {
        if (p.x - sx).powi(2) + (p.y - sy).powi(2) <= reach {
            min = [min[0].min(p.x), min[1].min(p.y)];
            max = [max[0].max(p.x), max[1].max(p.y)];
        }
    }
    (min[0] <= max[0] && min[1] <= max[1]).then(|| Raster::over(min, max, CELL))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::track::classify::ClassifyConfig;

    /// A wall along x at y = `y`, 2.5 m tall, from x = -5 to 10, but where `hidden` says the
    /// sensor at the origin does not see it.
    fn wall(y: f32, hidden: impl Fn(&Point) -> bool) -> Vec<Point> {
        let mut out = Vec::new();
        for i in 0..300 {
            for k in 0..25 {
                let p = Point::new(-5.0 + i as f32 * 0.05, y, k as f32 * 0.1, 0.0);
                if !hidden(&p) {
                    out.push(p);
                }
            }
        }
        out
    }

    /// The sensor-facing half of a 0.5 m wide, `top` m tall column centred at (x, y).
    fn column(x: f32, y: f32, top: f32) -> Vec<Point> {
        let mut out = Vec::new();
        for i in 0..=12 {
            let a = std::f32::consts::PI * (1.0 + i as f32 / 12.0);
            let (cx, cy) = (x + 0.25 * a.cos(), y + 0.25 * a.sin());
            for k in 0..=(top / 0.1) as usize {
                out.push(Point::new(cx, cy, k as f32 * 0.1, 0.0));
            }
        }
        out
    }

    /// Whether `p` lies in the shadow of the column at (x, y), seen from the origin.
    fn behind(x: f32, y: f32) -> impl Fn(&Point) -> bool {
        move |p: &Point| {
            let (bearing, column) = (p.x.atan2(p.y), x.atan2(y));
            (bearing - column).abs() < 0.3 / y.hypot(x) && p.y > y
        }
    }

    /// Peels `points` with `peeler`: the sizes of the people peeled off and of the rest.
    fn peel_with(peeler: &mut StandingPeeler, points: &mut [Point]) -> (Vec<usize>, usize) {
        let shape = PersonShape::standing(&ClassifyConfig::default());
        let mut people = Vec::new();
        let rest = peeler.peel(
            points,
            [0.0, 0.0],
            &Ground::horizontal(0.0),
            &shape,
            &mut people,
        );
        (people.iter().map(|r| r.len()).collect(), rest.len())
    }

    /// Peels `points` with a new peeler.
    fn peel(points: &mut [Point]) -> (Vec<usize>, usize) {
        peel_with(&mut StandingPeeler::default(), points)
    }

    #[test]
    fn a_person_before_a_wall_is_peeled_off_it() {
        let person = column(2.0, 7.5, 1.7);
        let mut points = wall(8.0, behind(2.0, 7.5));
        let wall_points = points.len();
        points.extend(&person);
        let (people, rest) = peel(&mut points);
        assert_eq!(people, vec![person.len()]);
        assert_eq!(rest, wall_points);
        // The person comes first, whole; the wall after.
        assert!(points[..person.len()].iter().all(|p| p.y < 7.9));
        // A peeler used before peels the same (its buffers are left clean).
        let mut peeler = StandingPeeler::default();
        let mut points = wall(8.0, behind(2.0, 7.5));
        points.extend(&person);
        let mut shifted = points.clone();
        shifted.iter_mut().for_each(|p| p.x -= 3.0);
        assert_eq!(peel_with(&mut peeler, &mut points).0, vec![person.len()]);
        assert_eq!(peel_with(&mut peeler, &mut shifted).0, vec![person.len()]);
        // A canopy over their head (a tree's crown, an awning) does not hide them.
        let mut points = wall(8.0, behind(2.0, 7.5));
        points.extend(&person);
        for i in 0..40 {
            points.push(Point::new(1.0 + i as f32 * 0.05, 7.0, 2.6, 0.0));
        }
        assert_eq!(peel(&mut points).0, vec![person.len()]);
    }

    #[test]
    fn what_is_no_standing_person_stays_with_the_wall() {
        let whole = |points: &mut Vec<Point>| {
            let n = points.len();
            assert_eq!(peel(points), (vec![], n));
        };
        // Taller than a person: a post.
        let mut points = wall(8.0, behind(2.0, 7.5));
        points.extend(column(2.0, 7.5, 3.0));
        whole(&mut points);
        // Lower than a person: a bin.
        let mut points = wall(8.0, behind(2.0, 7.5));
        points.extend(column(2.0, 7.5, 0.9));
        whole(&mut points);
        // Too far to be seen whole.
        let mut points: Vec<Point> = wall(8.0, behind(2.0, 7.5));
        points.extend(column(2.0, 7.5, 1.7));
        for p in &mut points {
            p.x += 40.0;
        }
        whole(&mut points);
        // A piece of the wall between two shadows: as tall as a person, but a line.
        let mut points = wall(8.0, |p| {
            (1.0..1.4).contains(&p.x) || (2.2..2.6).contains(&p.x)
        });
        whole(&mut points);
        // Something seen behind a rail of the same structure: a person stands before it.
        let mut points = wall(9.5, behind(2.0, 8.6));
        let rail = |p: &Point| (0.95..1.25).contains(&p.z);
        points.extend(column(2.0, 8.6, 1.7).into_iter().filter(|p| !rail(p)));
        for i in 0..40 {
            for k in 0..3 {
                points.push(Point::new(
                    1.0 + i as f32 * 0.05,
                    8.0,
                    1.0 + k as f32 * 0.1,
                    0.0,
                ));
            }
        }
        whole(&mut points);
    }
}
