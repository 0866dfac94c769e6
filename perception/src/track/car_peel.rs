//! Peeling a car off what DBSCAN joined it to. The radius that keeps a distant car in one
//! piece (0.85 m) also joins a car to a sign post, a tree or another car parked less than a
//! metre from it: the whole is too wide, too tall or too long for a car, is taken for
//! structure, and the car with it. Clustered again with a smaller radius (`FINE_EPS`), the
//! car stands apart: each fine cluster shaped like a car (a car's footprint showing a corner, a
//! car's height under the field of view's upper edge, standing on the ground) becomes a
//! cluster of its own, and the rest stays one cluster, as it was. (Close by, the field of view
//! cuts a van's top: a row of vans bumper to bumper is split only when every part of it is a
//! van.) Only clusters that are no car themselves, no larger than two cars, and near enough
//! for the fine radius to keep a car whole (`MAX_RANGE`) are looked at.

use std::ops::Range;

use nalgebra::{Vector2, Vector3};

use super::box_fit::fit_rectangle;
use super::classify::ClassifyConfig;
use super::fragments::Bounds;
use super::ground::Ground;
use super::parts::PartWriter;
use crate::Point;
use crate::cluster::{ClusterConfig, Clustering, Dbscan};

/// The radius (m) of the second clustering: cars 40 m away keep their rings (a third of a
/// degree, 0.23 m apart there) together, a post or a car 0.6 m away falls apart from them.
const FINE_EPS: f64 = 0.6;
/// Clusters farther than this (m) are left whole: the fine radius breaks cars apart there.
/// (30 m left a van joined to the post behind it at 30-40 m unidentified: over 48 simulated
/// drives, 40 m gave 0.06-0.08 points more MOTA per set of drives.)
const MAX_RANGE: f64 = 40.0;
/// Clusters with a longer footprint (m) are left whole: two cars bumper to bumper reach 13 m.
const MAX_CLUSTER_LENGTH: f64 = 14.0;
/// Clusters with a wider footprint (m) are left whole: a car by a tree spans 6-7 m, a low
/// building's walls more.
const MAX_CLUSTER_WIDTH: f64 = 7.0;
/// Fewest points of a peeled car.
const MIN_CAR_POINTS: usize = 30;
/// Narrowest shorter side (m) of a peeled car: seen from the road, a car shows a corner, its
/// side and an end; a piece of a wall or a fence cut off by a gap is a line.
const MIN_CAR_WIDTH: f64 = 0.8;

/// What a part must look like to be peeled off as a car.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CarShape {
    /// Shortest and longest side of the footprint (m).
    pub length: [f64; 2],
    /// Widest shorter side of the footprint (m).
    pub max_width: f64,
    /// Lowest and highest top above the ground (m).
    pub top: [f64; 2],
    /// Highest lowest point above the ground (m): wheels stand on it.
    pub max_bottom: f64,
    /// Highest elevation (degrees, seen from the sensor) of a car's top: higher, the field of
    /// view may cut it (a truck's cab close behind).
    pub max_elevation_deg: f64,
}

impl CarShape {
    /// A car or van as `c` bounds it, seen whole.
    pub fn of(c: &ClassifyConfig) -> Self {
        Self {
            length: [c.static_car_min_length, c.car_max_length],
            max_width: c.car_max_width,
            top: [
                c.min_object_height,
                c.car_max_height.max(c.whole_van_max_height),
            ],
            max_bottom: c.person_max_bottom,
            max_elevation_deg: c.sensor_upper_fov_deg - c.truncation_tolerance_deg,
        }
    }

    /// The limits of a car of this shape anywhere.
    fn limits(&self) -> Limits {
        Limits {
            max_range: f64::INFINITY,
            length: self.length,
            max_width: self.max_width,
            min_top: self.top[0],
            max_bottom: self.max_bottom,
        }
    }

    /// Whether a cluster measuring `m` is a car, or may be one cut by the field of view.
    fn may_be_a_car(&self, m: &Measure) -> bool {
        (self.top[0]..=self.top[1]).contains(&m.top)
            && m.bottom <= self.max_bottom
            && (self.length[0]..=self.length[1]).contains(&m.length)
            && m.width <= self.max_width
    }

    /// Whether a part measuring `m` is a car: car-shaped, showing a corner, and whole unless
    /// `cut` allows its top to be cut by the field of view.
    fn is_a_car(&self, m: &Measure, cut: bool) -> bool {
        self.may_be_a_car(m)
            && m.width >= MIN_CAR_WIDTH
            && (cut || m.elevation_deg <= self.max_elevation_deg)
    }
}

/// What the peel looks at in a set of points.
#[derive(Clone, Copy, Debug)]
struct Measure {
    /// Lowest and highest point above the ground (m).
    bottom: f64,
    top: f64,
    /// Longer and shorter side of the footprint (m).
    length: f64,
    width: f64,
    /// Elevation of the highest point seen from the sensor (degrees).
    elevation_deg: f64,
}

/// Where a car may be found in a set of points: what its axis-aligned bounds and its heights,
/// cheap to find, must allow before its footprint is fitted.
#[derive(Clone, Copy, Debug)]
struct Limits {
    /// Farthest the bounds' centre may lie from the sensor (m).
    max_range: f64,
    /// Shortest and longest footprint (m).
    length: [f64; 2],
    /// Widest footprint (m).
    max_width: f64,
    /// Lowest top and highest bottom above the ground (m).
    min_top: f64,
    max_bottom: f64,
}

impl Measure {
    /// Measures `points` (world frame) seen from `sensor` above `ground`, unless their bounds
    /// or heights are out of `limits` (`None`); `xy` is scratch.
    fn of(
        points: &[Point],
        sensor: Vector3<f64>,
        ground: &Ground,
        limits: &Limits,
        xy: &mut Vec<Vector2<f64>>,
    ) -> Option<Self> {
        let Bounds { min, max } = Bounds::of(points);
        let side = [f64::from(max[0] - min[0]), f64::from(max[1] - min[1])];
        let centre = Vector2::new(
            f64::from(min[0] + max[0]) / 2.0,
            f64::from(min[1] + max[1]) / 2.0,
        );
        // A footprint of l x w spans at most its diagonal along x or y, and its long side at
        // most the bounds' diagonal.
        if (centre - sensor.xy()).norm() > limits.max_range
            || side[0].hypot(side[1]) < limits.length[0]
            || side[0].max(side[1]) > limits.length[1].hypot(limits.max_width)
        {
            return None;
        }
        let (mut bottom, mut top, mut highest) = (f64::MAX, f64::MIN, Vector3::zeros());
        for p in points {
            let q = Vector3::new(p.x.into(), p.y.into(), p.z.into());
            let height = ground.height(&q);
            bottom = bottom.min(height);
            if height > top {
                (top, highest) = (height, q);
            }
        }
        if top < limits.min_top || bottom > limits.max_bottom {
            return None;
        }
        xy.clear();
        xy.extend(points.iter().map(|p| Vector2::new(p.x.into(), p.y.into())));
        let extent = fit_rectangle(xy).extent;
        let to_top = highest - sensor;
        Some(Self {
            bottom,
            top,
            length: extent.max(),
            width: extent.min(),
            elevation_deg: to_top.z.atan2(to_top.xy().norm()).to_degrees(),
        })
    }
}

/// Reusable buffers of the peel.
#[derive(Debug)]
pub struct CarPeeler {
    dbscan: Dbscan,
    clustering: Clustering,
    fine: Vec<Point>,
    measures: Vec<Option<Measure>>,
    owner: Vec<u32>,
    xy: Vec<Vector2<f64>>,
    writer: PartWriter,
}

impl Default for CarPeeler {
    fn default() -> Self {
        Self {
            dbscan: Dbscan::new(ClusterConfig {
                eps: FINE_EPS,
                ..ClusterConfig::default()
            }),
            clustering: Clustering::default(),
            fine: Vec::new(),
            measures: Vec::new(),
            owner: Vec::new(),
            xy: Vec::new(),
            writer: PartWriter::default(),
        }
    }
}

impl CarPeeler {
    /// Peels the cars off the cluster `points` (world frame; reordered in place), seen from
    /// `sensor` (world frame), above `ground`: appends the ranges of its parts to `parts`
    /// (relative to `points`) — each car, then the rest; the whole cluster when nothing is
    /// peeled.
    pub fn peel(
        &mut self,
        points: &mut [Point],
        sensor: Vector3<f64>,
        ground: &Ground,
        shape: &CarShape,
        parts: &mut Vec<Range<usize>>,
    ) {
        let cars = match self.look(points, sensor, ground, shape) {
            Some(whole) => self.find_cars(points, sensor, ground, shape, &whole),
            None => 0,
        };
        if cars == 0 {
            parts.push(0..points.len());
        } else {
            self.writer
                .write(points, &self.owner, cars as usize + 1, parts);
        }
    }

    /// The measure of `points` if they are worth a look: near enough, small enough and no car
    /// themselves.
    fn look(
        &mut self,
        points: &[Point],
        sensor: Vector3<f64>,
        ground: &Ground,
        shape: &CarShape,
    ) -> Option<Measure> {
        if points.len() < MIN_CAR_POINTS {
            return None;
        }
        let limits = Limits {
            max_range: MAX_RANGE,
            length: [shape.length[0], MAX_CLUSTER_LENGTH],
            max_width: MAX_CLUSTER_WIDTH,
            ..shape.limits()
        };
        Measure::of(points, sensor, ground, &limits, &mut self.xy).filter(|m| {
            m.length <= MAX_CLUSTER_LENGTH && m.width <= MAX_CLUSTER_WIDTH && !shape.may_be_a_car(m)
        })
    }

    /// Clusters `points` (measuring `whole`) again with the fine radius and marks the cars
    /// among the parts in `self.owner` (see [`Self::mark_cars`]); returns how many.
    fn find_cars(
        &mut self,
        points: &[Point],
        sensor: Vector3<f64>,
        ground: &Ground,
        shape: &CarShape,
        whole: &Measure,
    ) -> u32 {
        if self.dbscan.run(points, &mut self.clustering).is_err() {
            return 0;
        }
        self.measure_parts(points, sensor, ground, shape);
        let (cars, rest) = self.mark_cars(points.len(), shape, false);
        // A row as narrow as a car is cars only: a low building's wall, a container, a hedge
        // have car-shaped stretches too. Close by, the field of view cuts the top of vans
        // parked bumper to bumper: such a row is all vans when every part of it is one.
        let row = whole.width <= shape.max_width;
        if !row || rest < MIN_CAR_POINTS {
            return cars;
        }
        match self.mark_cars(points.len(), shape, true) {
            (cars, rest) if cars >= 2 && rest < MIN_CAR_POINTS => cars,
            _ => 0,
        }
    }

    /// Measures each cluster of `self.clustering` (`points` clustered again with the fine
    /// radius) into `self.measures`: `None` for one too small or out of a car's limits.
    fn measure_parts(
        &mut self,
        points: &[Point],
        sensor: Vector3<f64>,
        ground: &Ground,
        shape: &CarShape,
    ) {
        let limits = shape.limits();
        self.measures.clear();
        for members in self.clustering.clusters() {
            if members.len() < MIN_CAR_POINTS {
                self.measures.push(None);
                continue;
            }
            self.fine.clear();
            self.fine
                .extend(members.iter().map(|&i| points[i as usize]));
            let measure = Measure::of(&self.fine, sensor, ground, &limits, &mut self.xy);
            self.measures.push(measure);
        }
    }

    /// Marks, in `self.owner` (one entry for each of the `len` points), each measured cluster
    /// that is a car (its top perhaps `cut` by the field of view) with its number and every
    /// other point with the number after the last car's. Returns how many cars it found and
    /// how many points are left.
    fn mark_cars(&mut self, len: usize, shape: &CarShape, cut: bool) -> (u32, usize) {
        self.owner.clear();
        self.owner.resize(len, u32::MAX);
        let mut cars = 0;
        for (members, measure) in self.clustering.clusters().zip(&self.measures) {
            if measure.is_some_and(|m| shape.is_a_car(&m, cut)) {
                for &i in members {
                    self.owner[i as usize] = cars;
                }
                cars += 1;
            }
        }
        let mut rest = 0;
        for o in &mut self.owner {
            if *o == u32::MAX {
                *o = cars;
                rest += 1;
            }
        }
        (cars, rest)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The surface points of a box on the ground (z = 0): its four sides and its top, every
    /// `step` metres.
    fn solid(min: [f32; 2], max: [f32; 2], height: f32, step: f32) -> Vec<Point> {
        let mut points = Vec::new();
        let count = |a: f32, b: f32| ((b - a) / step).round() as usize + 1;
        let (nx, ny, nz) = (
            count(min[0], max[0]),
            count(min[1], max[1]),
            count(0.0, height),
        );
        for i in 0..nx {
            for j in 0..ny {
                for k in 0..nz {
                    let (x, y, z) = (
                        min[0] + i as f32 * step,
                        min[1] + j as f32 * step,
                        k as f32 * step,
                    );
                    let on_side = i == 0 || j == 0 || i == nx - 1 || j == ny - 1;
                    if on_side || k == nz - 1 {
                        points.push(Point::new(x, y, z, 0.0));
                    }
                }
            }
        }
        points
    }

    fn peel(points: &mut [Point]) -> Vec<usize> {
        let shape = CarShape::of(&ClassifyConfig::default());
        let mut parts = Vec::new();
        CarPeeler::default().peel(
            points,
            Vector3::new(0.0, 0.0, 1.73),
            &Ground::horizontal(0.0),
            &shape,
            &mut parts,
        );
        parts.iter().map(|r| r.len()).collect()
    }

    #[test]
    fn a_van_beside_a_sign_is_peeled_off_it() {
        // A van 2 x 5.5 m, 2 m high, 15 m away, and a sign 0.7 m beside it: a post with a
        // board at 2-2.6 m. Together 3 m wide and 2.6 m high: no car.
        let van = solid([15.0, -1.0], [17.0, 4.5], 2.0, 0.2);
        let mut sign = solid([17.7, 1.0], [17.8, 1.1], 2.0, 0.2);
        sign.extend(
            solid([17.7, 0.4], [17.8, 1.7], 0.6, 0.2)
                .iter()
                .map(|p| Point::new(p.x, p.y, p.z + 2.0, 0.0)),
        );
        let mut points = [van.clone(), sign.clone()].concat();
        assert_eq!(peel(&mut points), vec![van.len(), sign.len()]);
        // The van came first: its points are the van's.
        assert!(points[..van.len()].iter().all(|p| p.x <= 17.0));
    }

    #[test]
    fn two_cars_bumper_to_bumper_are_two_cars() {
        let first = solid([20.0, 2.0], [24.4, 3.8], 1.5, 0.2);
        let second = solid([25.2, 2.0], [29.6, 3.8], 1.5, 0.2);
        let mut points = [first.clone(), second.clone()].concat();
        assert_eq!(peel(&mut points), vec![first.len(), second.len()]);
    }

    #[test]
    fn two_vans_bumper_to_bumper_close_by_are_two_vans_though_cut() {
        // 8 m away the field of view cuts the vans' tops: each part is a car only because the
        // whole row is cars.
        let first = solid([8.0, 2.0], [13.4, 4.0], 2.2, 0.2);
        let second = solid([14.2, 2.0], [19.6, 4.0], 2.3, 0.2);
        let mut points = [first.clone(), second.clone()].concat();
        assert_eq!(peel(&mut points), vec![first.len(), second.len()]);
        // A van cut so, by a stretch of wall: left whole.
        let wall = solid([14.2, 3.8], [19.6, 4.0], 2.3, 0.2);
        let mut points = [first.clone(), wall.clone()].concat();
        assert_eq!(peel(&mut points), vec![first.len() + wall.len()]);
    }

    #[test]
    fn a_car_a_wall_and_what_is_too_far_are_left_whole() {
        // One car: already a car.
        let mut car = solid([10.0, 2.0], [14.4, 3.8], 1.5, 0.2);
        assert_eq!(peel(&mut car), vec![car.len()]);
        // A wall 10 m long with a gap of 0.7 m: no car-shaped part, left whole.
        let mut wall = solid([10.0, 5.0], [14.0, 5.2], 2.8, 0.2);
        wall.extend(solid([14.8, 5.0], [20.0, 5.2], 2.8, 0.2));
        assert_eq!(peel(&mut wall), vec![wall.len()]);
        // A car and a sign 45 m away: the fine radius would break a car apart there.
        let mut far = solid([45.0, -1.0], [47.0, 4.5], 2.0, 0.2);
        far.extend(solid([47.7, 0.4], [47.8, 1.7], 2.6, 0.2));
        assert_eq!(peel(&mut far), vec![far.len()]);
    }

    #[test]
    fn a_van_beside_a_post_35_m_away_is_peeled_off_it() {
        // A van 2 x 5.5 m, 2 m high, and a post 2.6 m tall 0.7 m behind it: together 2.8 m
        // wide and 2.6 m high, no car.
        let van = solid([35.0, -1.0], [37.0, 4.5], 2.0, 0.2);
        let post = solid([37.7, 1.0], [37.8, 1.1], 2.6, 0.2);
        let mut points = [van.clone(), post.clone()].concat();
        assert_eq!(peel(&mut points), vec![van.len(), post.len()]);
    }
}
