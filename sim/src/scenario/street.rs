//! Roads and what lines them: lanes, buildings, lamps, trees, parked cars, walkers.

use nalgebra::Vector2;

use crate::class::Class;
use crate::path::{Path, Pose2};
use crate::random::{between, chance};
use crate::scenario::builder::WorldBuilder;
use crate::scenario::props::{self, beside};
use crate::speed::SpeedProfile;
use crate::trajectory::Trajectory;

/// A path following `road` from arc length `s0` to `s1` at a lateral offset that may vary
/// (`offset(s)`, metres to the left), through waypoints `spacing` metres apart joined by
/// arcs: lane changes, weaving cyclists.
pub fn lane_path(road: &Path, s0: f64, s1: f64, spacing: f64, offset: impl Fn(f64) -> f64) -> Path {
    let n = ((s1 - s0) / spacing).ceil().max(1.0) as usize;
    let points: Vec<Vector2<f64>> = (0..=n)
        .map(|i| {
            let s = s0 + (s1 - s0) * i as f64 / n as f64;
            beside(road, s, offset(s)).0
        })
        .collect();
    Path::through(&points, 1e4)
}

/// What lines one side of a road.
#[derive(Clone, Copy, Debug)]
pub struct Roadside {
    /// +1 for the left side of the road's direction, −1 for the right.
    pub side: f64,
    /// Distance from the centreline to the kerb (metres).
    pub kerb: f64,
    /// Distance from the centreline to the building fronts (range), if there are buildings.
    pub buildings: Option<(f64, f64)>,
    /// Spacing of street lamps, if any.
    pub lamps: Option<f64>,
    /// Mean spacing of trees, if any.
    pub trees: Option<f64>,
    /// Offset (from the centreline, unsigned) and probability per slot of parked cars.
    pub parking: Option<(f64, f64)>,
    /// Number of pedestrians walking along the sidewalk.
    pub walkers: usize,
}

impl Roadside {
    /// A city street side: buildings, lamps, trees, some parked cars, a few walkers.
    pub fn city(side: f64, kerb: f64) -> Self {
        Self {
            side,
            kerb,
            buildings: Some((kerb + 4.0, kerb + 8.0)),
            lamps: Some(30.0),
            trees: Some(14.0),
            parking: None,
            walkers: 3,
        }
    }
}

/// Dresses one side of `road` between arc lengths `s0` and `s1`.
pub fn dress(b: &mut WorldBuilder, road: &Path, s0: f64, s1: f64, r: &Roadside) {
    let side = r.side;
    if let Some(spacing) = r.lamps {
        let mut s = s0 + between(&mut b.rng, 0.0, spacing);
        while s < s1 {
            let (xy, heading) = beside(road, s, side * (r.kerb + 0.7));
            props::lamp_post(b, xy, heading - side * std::f64::consts::FRAC_PI_2);
            if chance(&mut b.rng, 0.25) {
                let (xy, heading) = beside(road, s + 3.0, side * (r.kerb + 0.5));
                props::sign(b, xy, heading + std::f64::consts::PI);
            }
            s += spacing;
        }
    }
    if let Some(spacing) = r.trees {
        let mut s = s0 + between(&mut b.rng, 0.0, spacing);
        while s < s1 {
            let (xy, _) = beside(road, s, side * (r.kerb + between(&mut b.rng, 1.8, 2.6)));
            if chance(&mut b.rng, 0.8) {
                props::tree(b, xy);
            } else {
                props::bush(b, xy);
            }
            s += spacing * between(&mut b.rng, 0.6, 1.4);
        }
    }
    if let Some((near, far)) = r.buildings {
        let mut s = s0 + between(&mut b.rng, 0.0, 8.0);
        while s < s1 {
            let l = between(&mut b.rng, 8.0, 25.0).min(s1 - s);
            if l < 5.0 {
                break;
            }
            let depth = between(&mut b.rng, 8.0, 14.0);
            let front = between(&mut b.rng, near, far);
            let h = between(&mut b.rng, 6.0, 20.0);
            let (xy, heading) = beside(road, s + l / 2.0, side * (front + depth / 2.0));
            props::building(b, xy, heading, l, depth, h);
            s += l + if chance(&mut b.rng, 0.2) {
                between(&mut b.rng, 6.0, 15.0)
            } else {
                between(&mut b.rng, 0.5, 3.0)
            };
        }
    }
    if let Some((offset, p)) = r.parking {
        let mut s = s0 + between(&mut b.rng, 0.0, 4.0);
        while s < s1 - 6.0 {
            if chance(&mut b.rng, p) {
                let (xy, heading) = beside(road, s, side * offset);
                // Parked with the traffic of their side of the road.
                let heading = if side > 0.0 {
                    heading + std::f64::consts::PI
                } else {
                    heading
                };
                let class = if chance(&mut b.rng, 0.15) {
                    Class::Van
                } else {
                    Class::Car
                };
                let pose = Pose2 {
                    position: xy,
                    heading: heading + between(&mut b.rng, -0.03, 0.03),
                };
                b.place(class, None, Trajectory::parked(pose));
            }
            s += between(&mut b.rng, 6.0, 7.5);
        }
    }
    for _ in 0..r.walkers {
        let lane = road.offset(side * (r.kerb + between(&mut b.rng, 1.0, 2.5)));
        let forward = chance(&mut b.rng, 0.5);
        let lane = if forward { lane } else { lane.reversed() };
        let span = lane.length() * (s1 - s0) / road.length().max(1e-9);
        let start = if forward { s0 } else { road.length() - s1 };
        let s = start * lane.length() / road.length().max(1e-9) + between(&mut b.rng, 0.0, span);
        let speed = if chance(&mut b.rng, 0.15) {
            0.0
        } else {
            between(&mut b.rng, 1.0, 1.6)
        };
        b.place(
            Class::Pedestrian,
            None,
            Trajectory::new(lane, SpeedProfile::constant(speed)).starting_at(s),
        );
    }
}
