//! A street along a busy plaza: dozens of pedestrians walking and standing, cyclists crossing
//! the plaza and riding the street, trees, benches, a fountain. The first vehicle drives
//! slowly, stops at a zebra crossing full of people, and goes on round a bend.

use nalgebra::Vector2;

use crate::class::Class;
use crate::error::SimError;
use crate::path::{Path, Pose2};
use crate::random::{between, chance};
use crate::scenario::builder::WorldBuilder;
use crate::scenario::props;
use crate::scenario::street::{Roadside, dress};
use crate::scenario::{Candidates, place_vehicles};
use crate::speed::SpeedProfile;
use crate::trajectory::Trajectory;

/// Kerb offset of the street.
const KERB: f64 = 5.0;
/// The plaza: x range and y range (north of the street).
const PLAZA_X: (f64, f64) = (-30.0, 30.0);
const PLAZA_Y: (f64, f64) = (9.0, 55.0);
/// The fountain in the plaza's middle.
const FOUNTAIN: Vector2<f64> = Vector2::new(0.0, 32.0);
const FOUNTAIN_R: f64 = 3.0;
/// Where the street starts (west) and where the zebra crossing is.
const WEST: f64 = -70.0;
const ZEBRA_X: f64 = 0.0;
/// Where the first vehicle starts along the street.
const START_S: f64 = 30.0;

/// Builds the scenario with `vehicles` vehicles.
pub fn build(b: &mut WorldBuilder, vehicles: usize) -> Result<(), SimError> {
    let d = b.duration;
    let road = Path::from(Pose2::new(WEST, 0.0, 0.0))
        .line(110.0)
        .arc(
            between(&mut b.rng, 60.0, 90.0),
            between(&mut b.rng, 0.2, 0.4),
        )
        .line((6.0 * d).max(100.0))
        .build();
    let len = road.length();
    let east = road.offset(-1.75);
    let west = road.offset(1.75).reversed();

    // The first vehicle stops before the crossing for a few seconds.
    let v = between(&mut b.rng, 4.5, 6.0);
    // Stop with the front bumper ~4 m before the crossing.
    let stop_s = (ZEBRA_X - WEST) - 6.5 - START_S;
    let brake = v * v / 3.0;
    let wait = between(&mut b.rng, 2.5, 4.0);
    let first = SpeedProfile::starting(v)
        .hold(((stop_s - brake) / v).max(0.0))
        .to(0.0, 1.5)
        .hold(wait)
        .to(between(&mut b.rng, 5.0, 7.0), 1.0)
        .build();
    let mut candidates: Candidates =
        vec![Trajectory::new(east.clone(), first).starting_at(START_S)];
    for k in 0..10 {
        let k = k as f64;
        candidates.push(
            Trajectory::new(
                west.clone(),
                SpeedProfile::constant(between(&mut b.rng, 4.0, 6.0)),
            )
            .starting_at(len - 120.0 - 30.0 * k),
        );
        candidates.push(
            Trajectory::new(
                east.clone(),
                SpeedProfile::constant(between(&mut b.rng, 3.0, 5.0)),
            )
            .starting_at(-5.0 - 25.0 * k),
        );
    }
    place_vehicles(b, vehicles, candidates)?;

    // People crossing the street at the zebra, timed so nobody is run over.
    for _ in 0..(10.0 + 2.0 * d).min(60.0) as usize {
        let north = chance(&mut b.rng, 0.5);
        let x = ZEBRA_X + between(&mut b.rng, -1.5, 1.5);
        let (y0, y1) = if north {
            (-KERB - 2.0, PLAZA_Y.0 + 3.0)
        } else {
            (PLAZA_Y.0 + 3.0, -KERB - 2.0)
        };
        let lead = between(&mut b.rng, 2.0, 10.0);
        let side_x = x + between(&mut b.rng, -12.0, 12.0);
        let points = [
            Vector2::new(side_x, y0 + lead.copysign(y0)),
            Vector2::new(x, y0),
            Vector2::new(x, y1),
            Vector2::new(
                x + between(&mut b.rng, -8.0, 8.0),
                y1 + 15.0f64.copysign(y1),
            ),
        ];
        let v = between(&mut b.rng, 1.0, 1.5);
        let speed = SpeedProfile::starting(0.0)
            .hold(between(&mut b.rng, 0.0, d))
            .to(v, 1.5)
            .build();
        b.place(
            Class::Pedestrian,
            None,
            Trajectory::new(Path::through(&points, 1.0), speed),
        );
    }

    // The plaza's furniture, kept to its rim so walkers cross it freely.
    b.add_static(
        crate::geometry::Shape::cylinder(FOUNTAIN_R, 0.6),
        FOUNTAIN,
        0.0,
        0.0,
        crate::material::Material::CONCRETE,
    );
    b.add_static(
        crate::geometry::Shape::cylinder(0.4, 1.8),
        FOUNTAIN,
        0.0,
        0.0,
        crate::material::Material::CONCRETE,
    );
    let mut y = PLAZA_Y.0 + 4.0;
    while y < PLAZA_Y.1 {
        for x in [PLAZA_X.0 + 2.0, PLAZA_X.1 - 2.0] {
            props::tree(b, Vector2::new(x, y));
            props::bench(
                b,
                Vector2::new(x + 2.5f64.copysign(-x), y + 3.0),
                std::f64::consts::FRAC_PI_2,
            );
        }
        y += between(&mut b.rng, 7.0, 10.0);
    }
    let mut x = PLAZA_X.0 + 6.0;
    while x < PLAZA_X.1 - 4.0 {
        if chance(&mut b.rng, 0.5) {
            props::planter(b, Vector2::new(x, PLAZA_Y.1 - 2.0));
        } else {
            props::bin(b, Vector2::new(x, PLAZA_Y.1 - 2.0));
        }
        x += between(&mut b.rng, 5.0, 9.0);
    }
    for x in [-8.0, -4.0, 4.0, 8.0] {
        props::bollard(b, Vector2::new(ZEBRA_X + x, PLAZA_Y.0 - 1.0));
    }
    // Buildings close the plaza on three sides.
    for (xy, yaw, l) in [
        (
            Vector2::new(PLAZA_X.0 - 8.0, 32.0),
            std::f64::consts::FRAC_PI_2,
            50.0,
        ),
        (
            Vector2::new(PLAZA_X.1 + 8.0, 32.0),
            std::f64::consts::FRAC_PI_2,
            50.0,
        ),
        (Vector2::new(0.0, PLAZA_Y.1 + 8.0), 0.0, 76.0),
    ] {
        let h = between(&mut b.rng, 10.0, 22.0);
        props::building(b, xy, yaw, l, 12.0, h);
    }

    // Walkers and loiterers on the plaza.
    let people = 35 + crate::random::pick(&mut b.rng, 25);
    let mut placed = 0;
    for _ in 0..3 * people {
        let standing = chance(&mut b.rng, 0.3);
        let v = if standing {
            0.0
        } else {
            between(&mut b.rng, 0.8, 1.6)
        };
        let path = plaza_walk(b, v * d + 20.0, 1.0);
        let trajectory = Trajectory::new(path, SpeedProfile::constant(v));
        placed += usize::from(b.place(Class::Pedestrian, None, trajectory).is_some());
        if placed == people {
            break;
        }
    }
    for _ in 0..4 + crate::random::pick(&mut b.rng, 5) {
        let v = between(&mut b.rng, 3.0, 5.0);
        let path = plaza_walk(b, v * d + 30.0, 4.0);
        b.place(
            Class::Cyclist,
            None,
            Trajectory::new(path, SpeedProfile::constant(v)),
        );
    }
    // Cyclists on the street, both ways, at its edge.
    for k in 0..3 {
        let (lane, v) = if k % 2 == 0 {
            (road.offset(-KERB + 0.8), between(&mut b.rng, 4.0, 6.5))
        } else {
            (
                road.offset(KERB - 0.8).reversed(),
                between(&mut b.rng, 4.0, 6.5),
            )
        };
        let s = between(&mut b.rng, 0.0, 80.0);
        b.place(
            Class::Cyclist,
            None,
            Trajectory::new(lane, SpeedProfile::constant(v)).starting_at(s),
        );
    }

    // The street's south side is a city street; its north side only west and east of the
    // plaza.
    let mut south = Roadside::city(-1.0, KERB);
    south.walkers = 8;
    south.parking = None;
    dress(b, &road, 0.0, len, &south);
    let mut north = Roadside::city(1.0, KERB);
    north.walkers = 4;
    let plaza_start = PLAZA_X.0 - 16.0 - WEST;
    dress(b, &road, 0.0, plaza_start, &north);
    dress(b, &road, PLAZA_X.1 + 16.0 - WEST, len, &north);
    Ok(())
}

/// A random walk over the plaza at least `length` metres long, around the fountain, corners
/// rounded with `radius`.
fn plaza_walk(b: &mut WorldBuilder, length: f64, radius: f64) -> Path {
    let mut point = || loop {
        let p = Vector2::new(
            between(&mut b.rng, PLAZA_X.0 + 5.0, PLAZA_X.1 - 5.0),
            between(&mut b.rng, PLAZA_Y.0 + 2.0, PLAZA_Y.1 - 4.0),
        );
        if (p - FOUNTAIN).norm() > FOUNTAIN_R + 1.5 {
            return p;
        }
    };
    let mut points = vec![point()];
    let mut total = 0.0;
    while total < length || points.len() < 2 {
        let last = points[points.len() - 1];
        let next = point();
        // Legs may not cross the fountain.
        if segment_distance(FOUNTAIN, last, next) < FOUNTAIN_R + 1.0 || (next - last).norm() < 3.0 {
            continue;
        }
        total += (next - last).norm();
        points.push(next);
    }
    Path::through(&points, radius)
}

/// Distance from `p` to the segment `a`–`b`.
fn segment_distance(p: Vector2<f64>, a: Vector2<f64>, b: Vector2<f64>) -> f64 {
    let ab = b - a;
    let u = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
    (a + ab * u - p).norm()
}
