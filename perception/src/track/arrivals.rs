//! Peeling newcomers off large clusters. DBSCAN joins a pedestrian walking along a wall, a
//! fence or a hedge to it, and the cluster so made is structure: the person is never tracked.
//! What tells the person from the wall is where each stands: the wall was there a moment ago,
//! while the place the person stands now was free space then, the laser having passed through
//! it to hit something farther (the wall behind). The points of a large cluster that stand
//! where an earlier scan saw through, grouped in the ground plane, that make up a compact,
//! person-sized group, each become a cluster of their own, with the points beside and up to
//! a little above them (not the crown of a tree they walk under); the rest stays as it was.
//!
//! A static scene gives no such points (a point seen now is hit or hidden then, never seen
//! through); a moving vehicle's arrivals span its width, wider than a person, and a cluster
//! with such stray arrivals is left whole.

use std::ops::Range;

use nalgebra::{Point3, Vector3};

use super::ground::Ground;
use super::parts::PartWriter;
use super::raster::{MARKED, Raster, UNLABELLED};
use super::tracker::PredictedBox;
use super::views::View;
use super::visibility::Visibility;
use crate::Point;

/// Clusters shorter than this (m, longer side of their ground-plane bounds) are left alone:
/// people and riders, which the person split deals with. A walker under a tree's crown makes
/// a cluster of 2-3 m (with 3 m, and the crown peeled with the walker, the simulated drives'
/// mean MOTA was 0.1 point lower).
const MIN_EXTENT: f32 = 2.0;
/// Points lower than this (m) above the ground say nothing: kerbs, the ground's own edge.
const MIN_HEIGHT: f64 = 0.3;
/// Half-width (m) of the window a point must be seen through across, at its range.
const SEEN_THROUGH_HALF_WIDTH: f64 = 0.1;
/// Every this-many-th point of a cluster is tested first: a person of the fewest arrived
/// points peeled shows in one of them.
const PROBE_STRIDE: usize = 8;
/// Cell (m) of the ground-plane raster the arrivals are grouped on.
const CELL: f32 = 0.25;
/// Most cells of the raster (a very large cluster gets coarser cells).
const MAX_CELLS: usize = 1 << 16;
/// Fewest arrived points of a group peeled off...
const MIN_ARRIVED: usize = 8;
/// ...its longest ground-plane side (m): a person, arms swinging...
const MAX_SIDE: f32 = 1.3;
/// ...and its lowest top above the ground (m): an upper body, not a low clutter of returns.
const MIN_TOP: f64 = 1.0;
/// Most arrived points outside person-sized groups, as a share of the points tested: a
/// large cluster with more is moving itself, or seen from a pose too far off to compare.
const MAX_STRAY_SHARE: f64 = 0.02;
/// Points within this (m) of a peeled group's bounds go with it: the parts of the body
/// that stand where the person already stood a moment ago.
const GROW: f32 = 0.1;
/// Points up to this far (m) above a peeled group's highest arrival go with it: the top of
/// the head, seen where it already was a moment ago.
const GROW_UP: f64 = 0.3;

/// Groups farther than this (m) from the sensor are left in their cluster: the scans'
/// columns lie too far apart there to tell a newcomer from a pose a little off.
const MAX_RANGE: f64 = 30.0;
/// A moving vehicle's predicted box reaches a cluster when its centre lies within its half
/// diagonal and this margin (m) of the cluster's bounds.
const VEHICLE_MARGIN: f64 = 1.0;

/// What the peel needs to know of the scan besides the earlier view.
#[derive(Clone, Copy, Debug)]
pub struct Scene<'a> {
    /// The ground heights are measured from.
    pub ground: &'a Ground,
    /// The sensor's position (world x, y).
    pub sensor: [f64; 2],
    /// The confirmed tracks' predicted boxes.
    pub boxes: &'a [PredictedBox],
}

/// A group of arrived points: its ground-plane bounds, count and top.
#[derive(Clone, Copy, Debug)]
struct Group {
    min: [f32; 2],
    max: [f32; 2],
    arrived: usize,
    top: f64,
}

impl Group {
    fn new() -> Self {
        Self {
            min: [f32::MAX; 2],
            max: [f32::MIN; 2],
            arrived: 0,
            top: f64::MIN,
        }
    }

    fn add(&mut self, p: &Point, height: f64) {
        self.min = [self.min[0].min(p.x), self.min[1].min(p.y)];
        self.max = [self.max[0].max(p.x), self.max[1].max(p.y)];
        self.arrived += 1;
        self.top = self.top.max(height);
    }

    fn is_person_sized(&self) -> bool {
        let side = (self.max[0] - self.min[0]).max(self.max[1] - self.min[1]);
        self.arrived >= MIN_ARRIVED && side <= MAX_SIDE && self.top >= MIN_TOP
    }

    /// Whether `p`, `height` m above the ground, is part of the group: within [`GROW`] of its
    /// ground-plane bounds, and no higher than its top and [`GROW_UP`] (a tree's crown over a
    /// walker is not theirs).
    fn holds(&self, p: &Point, height: f64) -> bool {
        height <= self.top + GROW_UP
            && p.x >= self.min[0] - GROW
            && p.x <= self.max[0] + GROW
            && p.y >= self.min[1] - GROW
            && p.y <= self.max[1] + GROW
    }
}

/// A point that stands where the earlier scan saw through.
#[derive(Clone, Copy, Debug)]
struct Arrival {
    /// Its index in the cluster.
    point: u32,
    /// Its raster cell.
    cell: u32,
    /// Its height above the ground (m).
    height: f64,
}

/// Reusable buffers of the peel.
#[derive(Debug, Default)]
pub struct ArrivalPeeler {
    arrivals: Vec<Arrival>,
    /// Per raster cell: its group, [`UNLABELLED`] when no arrival lies in it.
    group_of_cell: Vec<u32>,
    stack: Vec<u32>,
    groups: Vec<Group>,
    owner: Vec<u32>,
    writer: PartWriter,
}

impl ArrivalPeeler {
    /// Splits the cluster `points` (world frame; reordered in place) by what `then`, an earlier
    /// scan, saw: appends the ranges of its parts to `parts` (relative to `points`), each
    /// person-sized group of newcomers first, then the rest, and returns how many (one, the
    /// whole cluster, when nothing is peeled).
    ///
    /// Clusters a moving vehicle's predicted box (among `boxes`) reaches are left whole, and
    /// so are groups farther than `MAX_RANGE` from the `sensor` (world x, y).
    pub fn split(
        &mut self,
        points: &mut [Point],
        then: &View,
        scene: &Scene<'_>,
        parts: &mut Vec<Range<usize>>,
    ) -> usize {
        let peeled = self.find_groups(points, then, scene);
        if peeled == 0 {
            parts.push(0..points.len());
            return 1;
        }
        // Owner of each point: the first peeled group holding it, else the rest (`peeled`).
        self.owner.clear();
        for p in points.iter() {
            let height = scene.ground.height(&Vector3::new(
                f64::from(p.x),
                f64::from(p.y),
                f64::from(p.z),
            ));
            let owner = self.groups[..peeled]
                .iter()
                .position(|g| g.holds(p, height))
                .unwrap_or(peeled);
            self.owner.push(owner as u32);
        }
        self.writer.write(points, &self.owner, peeled + 1, parts)
    }

    /// Finds the person-sized groups of arrived points of a large cluster; keeps them first
    /// in `self.groups` and returns how many.
    fn find_groups(&mut self, points: &[Point], then: &View, scene: &Scene<'_>) -> usize {
        self.groups.clear();
        let Some((min, max)) = bounds(points) else {
            return 0;
        };
        let extent = [max[0] - min[0], max[1] - min[1]];
        if extent[0].max(extent[1]) < MIN_EXTENT {
            return 0;
        }
        let reaches = |b: &&PredictedBox| {
            let reach = b.size.norm() / 2.0 + VEHICLE_MARGIN;
            b.center.x >= f64::from(min[0]) - reach
                && b.center.x <= f64::from(max[0]) + reach
                && b.center.y >= f64::from(min[1]) - reach
                && b.center.y <= f64::from(max[1]) + reach
        };
        if scene
            .boxes
            .iter()
            .filter(|b| b.moving_vehicle)
            .any(|b| reaches(&b))
        {
            return 0;
        }
        let ground = scene.ground;
        let mut cell = CELL;
        while Raster::over(min, max, cell).len() > MAX_CELLS {
            cell *= 2.0;
        }
        let raster = Raster::over(min, max, cell);
        // The arrived points; a cluster none of whose every PROBE_STRIDE-th point arrived is
        // left alone at once (walls and buildings, mostly).
        let to_then = then.pose.inverse();
        let arrival_height = |p: &Point| {
            let v = Vector3::new(f64::from(p.x), f64::from(p.y), f64::from(p.z));
            let height = ground.height(&v);
            let seen_through = height >= MIN_HEIGHT
                && then.image.visibility_across(
                    &(to_then * Point3::from(v)).coords,
                    SEEN_THROUGH_HALF_WIDTH,
                ) == Visibility::SeenThrough;
            (height >= MIN_HEIGHT, seen_through.then_some(height))
        };
        if !points
            .iter()
            .step_by(PROBE_STRIDE)
            .any(|p| arrival_height(p).1.is_some())
        {
            return 0;
        }
        self.arrivals.clear();
        let mut tested = 0;
        for (k, p) in points.iter().enumerate() {
            let (above, arrived) = arrival_height(p);
            tested += usize::from(above);
            if let Some(height) = arrived {
                let cell = raster.cell_of(p) as u32;
                self.arrivals.push(Arrival {
                    point: k as u32,
                    cell,
                    height,
                });
            }
        }
        if self.arrivals.len() < MIN_ARRIVED {
            return 0;
        }
        // Connected groups of the cells arrivals lie in.
        self.group_of_cell.clear();
        self.group_of_cell.resize(raster.len(), UNLABELLED);
        for a in &self.arrivals {
            self.group_of_cell[a.cell as usize] = MARKED;
        }
        let count = raster.label_groups(&mut self.group_of_cell, &mut self.stack);
        self.groups.resize(count as usize, Group::new());
        for a in &self.arrivals {
            let group = self.group_of_cell[a.cell as usize] as usize;
            self.groups[group].add(&points[a.point as usize], a.height);
        }
        // Grouped arrivals the size of no person: the cluster itself is on the move (a
        // vehicle), or the scene is not what it was; nothing is peeled then.
        let stray: usize = self
            .groups
            .iter()
            .filter(|g| !g.is_person_sized())
            .map(|g| g.arrived)
            .sum();
        if stray as f64 > MAX_STRAY_SHARE * tested as f64 {
            self.groups.clear();
            return 0;
        }
        let near = |g: &Group| {
            let centre = [(g.min[0] + g.max[0]) / 2.0, (g.min[1] + g.max[1]) / 2.0];
            (f64::from(centre[0]) - scene.sensor[0]).hypot(f64::from(centre[1]) - scene.sensor[1])
                <= MAX_RANGE
        };
        self.groups.retain(|g| g.is_person_sized() && near(g));
        self.groups.len()
    }
}

/// The ground-plane bounds of `points`; `None` when empty or not finite.
fn bounds(points: &[Point]) -> Option<([f32; 2], [f32; 2])> {
    let (mut min, mut max) = ([f32::MAX; 2], [f32::MIN; 2]);
    for p in points {
        min = [min[0].min(p.x), min[1].min(p.y)];
        max = [max[0].max(p.x), max[1].max(p.y)];
    }
    (min[0] <= max[0] && (max[0] - min[0]).is_finite() && (max[1] - min[1]).is_finite())
        .then_some((min, max))
}

#[cfg(test)]
mod tests {
    use nalgebra::{Isometry3, Vector2};

    use super::*;
    use crate::track::visibility::RangeImage;

    /// The road, 1.73 m below the sensor at the origin.
    const ROAD: f64 = -1.73;

    /// A wall across the x axis at `x`, 8 m wide, 2.5 m high, a point every 5 cm.
    fn wall(x: f32) -> Vec<Point> {
        let mut out = Vec::new();
        for i in 0..160 {
            for k in 0..50 {
                let z = ROAD as f32 + 0.05 + k as f32 * 0.05;
                out.push(Point::new(x, -4.0 + i as f32 * 0.05, z, 0.0));
            }
        }
        out
    }

    /// A person standing at (x, y): a 0.3 x 0.4 m column 1.75 m high, a point every 5 cm.
    fn person(x: f32, y: f32) -> Vec<Point> {
        let mut out = Vec::new();
        for i in 0..6 {
            for j in 0..8 {
                for k in 0..35 {
                    let z = ROAD as f32 + 0.05 + k as f32 * 0.05;
                    out.push(Point::new(
                        x - 0.15 + i as f32 * 0.05,
                        y - 0.2 + j as f32 * 0.05,
                        z,
                        0.0,
                    ));
                }
            }
        }
        out
    }

    /// What the sensor at the origin saw of `points`.
    fn view(points: &[Point]) -> View {
        let mut image = RangeImage::default();
        image.build(points);
        View {
            timestamp: 0.0,
            pose: Isometry3::identity(),
            image,
        }
    }

    fn peel(points: &mut [Point], then: &View, boxes: &[PredictedBox]) -> Vec<Range<usize>> {
        let ground = Ground::horizontal(ROAD);
        let scene = Scene {
            ground: &ground,
            sensor: [0.0, 0.0],
            boxes,
        };
        let mut parts = Vec::new();
        let count = ArrivalPeeler::default().split(points, then, &scene, &mut parts);
        assert_eq!(count, parts.len());
        parts
    }

    #[test]
    fn a_person_walking_up_to_a_wall_is_peeled_off_it() {
        let then = view(&wall(10.0));
        let mut points = wall(10.0);
        let person_points = person(9.0, 1.0).len();
        points.extend(person(9.0, 1.0));
        let parts = peel(&mut points, &then, &[]);
        assert_eq!(parts.len(), 2, "{parts:?}");
        assert_eq!(parts[0].len(), person_points);
        assert!(points[parts[0].clone()].iter().all(|p| p.x < 9.5));
        assert!(points[parts[1].clone()].iter().all(|p| p.x == 10.0));
    }

    #[test]
    fn a_person_walking_under_a_tree_leaves_its_crown_behind() {
        // A crown 2.2-2.9 m up over (8-10, 0-2), before a wall.
        let mut crown = Vec::new();
        for i in 0..20 {
            for j in 0..20 {
                for k in 0..5 {
                    let z = ROAD as f32 + 2.2 + k as f32 * 0.15;
                    crown.push(Point::new(8.0 + i as f32 * 0.1, j as f32 * 0.1, z, 0.0));
                }
            }
        }
        let mut scene = wall(10.0);
        scene.extend(&crown);
        let then = view(&scene);
        let mut points = scene.clone();
        points.extend(person(9.0, 1.0));
        let parts = peel(&mut points, &then, &[]);
        assert_eq!(parts.len(), 2, "{parts:?}");
        let peeled = &points[parts[0].clone()];
        assert_eq!(
            peeled.len(),
            person(9.0, 1.0).len(),
            "the crown went with the person"
        );
        assert!(peeled.iter().all(|p| p.z < ROAD as f32 + 1.9));
    }

    #[test]
    fn a_wall_as_it_was_stays_whole() {
        let mut with_person = wall(10.0);
        with_person.extend(person(9.0, 1.0));
        // The person already stood there a moment ago: no newcomer.
        let then = view(&with_person);
        let mut points = with_person.clone();
        assert_eq!(peel(&mut points, &then, &[]), vec![0..points.len()]);
        assert_eq!(points, with_person);
    }

    #[test]
    fn a_cluster_that_moved_as_a_whole_stays_whole() {
        // All of it stands where free space was: a vehicle, not a newcomer to a wall.
        let then = view(&wall(14.0));
        let mut points = wall(10.0);
        points.extend(person(9.0, 1.0));
        assert_eq!(peel(&mut points, &then, &[]).len(), 1);
    }

    #[test]
    fn no_peel_near_a_moving_vehicle_nor_far_away() {
        let then = view(&wall(10.0));
        let mut points = wall(10.0);
        points.extend(person(9.0, 1.0));
        let vehicle = PredictedBox {
            id: 1,
            center: Vector2::new(8.0, -6.0),
            heading: 0.0,
            size: Vector2::new(4.5, 1.8),
            moving_vehicle: true,
            moving_person: false,
        };
        assert_eq!(peel(&mut points, &then, &[vehicle]).len(), 1);
        let parked = PredictedBox {
            moving_vehicle: false,
            moving_person: false,
            ..vehicle
        };
        assert_eq!(peel(&mut points, &then, &[parked]).len(), 2);

        let then = view(&wall(40.0));
        let mut points = wall(40.0);
        points.extend(person(39.0, 1.0));
        assert_eq!(peel(&mut points, &then, &[]).len(), 1);
    }
}
