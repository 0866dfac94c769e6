//! DBSCAN's clusters made into what the tracker takes, before any track is consulted: stacked
//! fragments of one object joined, clusters larger than any object set aside for the map,
//! people a gap away peeled apart, people standing by a facade (or anything longer than a car)
//! peeled off it, cars peeled off what they touch, and each cluster described by its VFH.
//! (Clusters holding several confirmed tracks are split among them later, by the tracking
//! half, which also peels moving people and newcomers off the clusters set aside.)

use std::ops::Range;

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::Point;
use crate::cluster::Clustering;
use crate::config::Config;
use crate::track::Ground;
use crate::track::car_peel::{CarPeeler, CarShape};
use crate::track::fragments::{Bounds, stacked_groups};
use crate::track::person_split::{PersonShape, PersonSplitter};
use crate::track::standing_peel::StandingPeeler;
use crate::vfh::{BINS, Vfh, VfhConfig, VfhEstimator};

/// What VFH tells of one cluster: its histogram, the histogram's CDF and the cluster's surface
/// variation.
pub(super) type Signature = (Vfh, [f32; BINS], f32);

/// The clusters of one scan, gathered contiguously.
#[derive(Debug, Default)]
pub(super) struct Clusters {
    /// Points of every cluster, one after the other (world frame).
    pub(super) points: Vec<Point>,
    /// Each cluster's points.
    pub(super) ranges: Vec<Range<usize>>,
    /// Each cluster's VFH (`None`: too few points to describe).
    pub(super) signatures: Vec<Option<Signature>>,
    /// Clusters larger than any object (a facade, a fence): left to the map, but a person
    /// walking along one is peeled off it by the tracking half.
    pub(super) oversized: Vec<Range<usize>>,
}

/// The longest ground-plane side (m, along x or y) of an object's cluster: the longest object
/// seen diagonally.
pub(super) fn largest_object_side(config: &Config) -> f32 {
    config.track.classify.max_object_length as f32 * std::f32::consts::SQRT_2
}

/// Whether `points` reach farther than `largest` (m) along x or y.
pub(super) fn larger_than_any_object(points: &[Point], largest: f32) -> bool {
    longest_side(points) > largest
}

/// How far (m) `points` reach along x or y, whichever is farther.
fn longest_side(points: &[Point]) -> f32 {
    let bounds = Bounds::of(points);
    (bounds.max[0] - bounds.min[0]).max(bounds.max[1] - bounds.min[1])
}

/// The gathering's settings and reusable buffers.
#[derive(Debug)]
pub(super) struct Gatherer {
    /// Clusters longer than this on an axis (m) are structure.
    largest: f32,
    /// Clusters longer than this on an axis (m) are no one car: people standing by them are
    /// peeled off.
    longest_car: f32,
    person: PersonShape,
    standing: PersonShape,
    car: CarShape,
    /// Whether merged objects are split (people apart here, tracks apart later).
    split_merged: bool,
    vfh: VfhConfig,
    person_splitter: PersonSplitter,
    standing_peeler: StandingPeeler,
    car_peeler: CarPeeler,
    bounds: Vec<Bounds>,
    groups: Vec<usize>,
    group_ranges: Vec<Range<usize>>,
    sizes: Vec<usize>,
    people: Vec<Range<usize>>,
    cars: Vec<Range<usize>>,
}

impl Gatherer {
    /// A gatherer with the settings of `config`.
    pub(super) fn new(config: &Config) -> Self {
        Self {
            largest: largest_object_side(config),
            longest_car: config.track.classify.car_max_length as f32,
            person: PersonShape::of(&config.track.classify),
            standing: PersonShape::standing(&config.track.classify),
            car: CarShape::of(&config.track.classify),
            split_merged: config.track.split_merged_clusters,
            vfh: config.vfh.clone(),
            person_splitter: PersonSplitter::default(),
            standing_peeler: StandingPeeler::default(),
            car_peeler: CarPeeler::default(),
            bounds: Vec::new(),
            groups: Vec::new(),
            group_ranges: Vec::new(),
            sizes: Vec::new(),
            people: Vec::new(),
            cars: Vec::new(),
        }
    }

    /// Gathers the clusters of `clustering` over `obstacles` (world frame), seen from `sensor`
    /// above `ground`, into `out`, in order of their first cluster.
    pub(super) fn gather(
        &mut self,
        clustering: &Clustering,
        obstacles: &[Point],
        sensor: Vector3<f64>,
        ground: &Ground,
        out: &mut Clusters,
    ) {
        let sensor_xy = [sensor.x, sensor.y];
        self.bounds.clear();
        for members in clustering.clusters() {
            let points = members.iter().map(|&i| &obstacles[i as usize]);
            self.bounds.push(Bounds::of(points));
        }
        stacked_groups(&self.bounds, &mut self.groups);
        // Order the members by group: a counting sort over the clusters' member lists.
        let group_count = self.groups.iter().max().map_or(0, |g| g + 1);
        self.sizes.clear();
        self.sizes.resize(group_count, 0);
        for (k, members) in clustering.clusters().enumerate() {
            self.sizes[self.groups[k]] += members.len();
        }
        self.group_ranges.clear();
        let mut start = 0;
        for size in &self.sizes {
            self.group_ranges.push(start..start);
            start += size;
        }
        out.points.clear();
        out.points.resize(start, Point::default());
        for (k, members) in clustering.clusters().enumerate() {
            let r = &mut self.group_ranges[self.groups[k]];
            for &i in members {
                out.points[r.end] = obstacles[i as usize];
                r.end += 1;
            }
        }
        out.ranges.clear();
        out.oversized.clear();
        for r in &self.group_ranges {
            let points = &mut out.points[r.clone()];
            let side = longest_side(points);
            let oversized = side > self.largest;
            if !self.split_merged {
                if oversized {
                    out.oversized.push(r.clone());
                } else {
                    out.ranges.push(r.clone());
                }
                continue;
            }
            let shifted = |p: &Range<usize>| r.start + p.start..r.start + p.end;
            self.people.clear();
            let split = !oversized
                && self.person_splitter.split(
                    points,
                    sensor_xy,
                    ground,
                    &self.person,
                    &mut self.people,
                ) > 1;
            if split {
                out.ranges.extend(self.people.iter().map(shifted));
                continue;
            }
            if side <= self.longest_car {
                self.cars.clear();
                self.car_peeler
                    .peel(points, sensor, ground, &self.car, &mut self.cars);
                out.ranges.extend(self.cars.iter().map(shifted));
                continue;
            }
            // Longer than any car and not all people: a facade, a hedge, a row of parked
            // cars, perhaps with people standing by it.
            self.people.clear();
            let rest = self.standing_peeler.peel(
                points,
                sensor_xy,
                ground,
                &self.standing,
                &mut self.people,
            );
            out.ranges.extend(self.people.iter().map(shifted));
            if rest.is_empty() {
                continue;
            }
            if oversized {
                out.oversized.push(shifted(&rest));
                continue;
            }
            // A row of parked cars, or a car by a hedge.
            self.cars.clear();
            self.car_peeler.peel(
                &mut points[rest.clone()],
                sensor,
                ground,
                &self.car,
                &mut self.cars,
            );
            let rest_start = r.start + rest.start;
            out.ranges.extend(
                self.cars
                    .iter()
                    .map(|c| rest_start + c.start..rest_start + c.end),
            );
        }
    }

    /// Computes the VFH of every gathered cluster in `clusters`, in parallel, seen from
    /// `viewpoint`.
    pub(super) fn describe(&self, clusters: &mut Clusters, viewpoint: [f64; 3]) {
        let points = &clusters.points;
        clusters
            .ranges
            .par_iter()
            .map_init(
                || VfhEstimator::new(self.vfh.clone()),
                |estimator, r| describe(estimator, &points[r.clone()], viewpoint),
            )
            .collect_into_vec(&mut clusters.signatures);
    }
}

/// The signature of one cluster's `points` seen from `viewpoint`, if it has enough points.
pub(super) fn describe(
    estimator: &mut VfhEstimator,
    points: &[Point],
    viewpoint: [f64; 3],
) -> Option<Signature> {
    estimator
        .compute(points, viewpoint)
        .map(|vfh| (vfh, vfh.cdf(), estimator.surface_variation()))
}
