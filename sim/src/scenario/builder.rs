//! Assembling a world: static solids, objects placed without collisions, the fleet's
//! vehicles, global ids.

use nalgebra::{Vector2, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::actor::Actor;
use crate::class::Class;
use crate::clearance::conflict;
use crate::geometry::{Primitive, Shape};
use crate::label::PointLabel;
use crate::material::Material;
use crate::random::between;
use crate::terrain::Terrain;
use crate::trajectory::Trajectory;
use crate::world::{FLEET_ORIGIN, World};

/// Clearance kept between a new moving object and every other one (metres).
pub const VEHICLE_MARGIN: f64 = 0.5;
/// Clearance kept between pedestrians and cyclists and everything else (metres).
pub const PERSON_MARGIN: f64 = 0.15;

/// A world under construction.
#[derive(Debug)]
pub struct WorldBuilder {
    /// The ground.
    pub terrain: Terrain,
    /// Seconds the drive lasts (objects are checked for collisions over this span).
    pub duration: f64,
    /// The scenario's random source (deterministic per seed).
    pub rng: ChaCha8Rng,
    statics: Vec<Primitive>,
    actors: Vec<Actor>,
    vehicles: Vec<usize>,
    next_id: u32,
}

impl WorldBuilder {
    /// An empty world on `terrain` for a drive of `duration` seconds.
    pub fn new(terrain: Terrain, duration: f64, seed: u64) -> Self {
        Self {
            terrain,
            duration,
            rng: ChaCha8Rng::seed_from_u64(seed),
            statics: Vec::new(),
            actors: Vec::new(),
            vehicles: Vec::new(),
            next_id: 1,
        }
    }

    /// Ground height at `xy`.
    pub fn ground(&self, xy: Vector2<f64>) -> f64 {
        self.terrain.height(xy)
    }

    /// Adds a static solid of `shape` standing on the ground at `xy` (its base `lift` metres
    /// above the ground; the part below ground is hidden by it).
    pub fn add_static(
        &mut self,
        shape: Shape,
        xy: Vector2<f64>,
        lift: f64,
        yaw: f64,
        material: Material,
    ) {
        let hz = shape.half_extents().z;
        let center = Vector3::new(xy.x, xy.y, self.ground(xy) + lift + hz);
        self.statics.push(Primitive::new(
            shape,
            center,
            yaw,
            material,
            PointLabel::Static,
        ));
    }

    /// A random car paint.
    pub fn paint(&mut self) -> Material {
        Material {
            reflectance: between(&mut self.rng, 0.08, 0.55) as f32,
            ..Material::PAINT
        }
    }

    fn actor(&mut self, class: Class, size: Option<[f64; 3]>, trajectory: Trajectory) -> Actor {
        let size = size.unwrap_or_else(|| class.random_size(&mut self.rng));
        let paint = self.paint();
        let id = self.next_id;
        Actor::new(id, class, size, paint, trajectory)
    }

    fn margin(class: Class) -> f64 {
        match class {
            Class::Car | Class::Van | Class::Truck => VEHICLE_MARGIN,
            Class::Cyclist | Class::Pedestrian => PERSON_MARGIN,
        }
    }

    /// Adds an object of `class` (random size unless given) if it never comes too close to
    /// any object already placed; returns its id.
    pub fn place(
        &mut self,
        class: Class,
        size: Option<[f64; 3]>,
        trajectory: Trajectory,
    ) -> Option<u32> {
        let actor = self.actor(class, size, trajectory);
        let margin = Self::margin(class);
        let blocked = self.actors.iter().any(|other| {
            conflict(
                &actor,
                other,
                self.duration,
                margin.max(Self::margin(other.class)),
            )
        });
        (!blocked).then(|| self.push(actor))
    }

    /// Adds an object without the collision check (groups designed together, like two
    /// cyclists riding side by side); returns its id.
    pub fn place_unchecked(
        &mut self,
        class: Class,
        size: Option<[f64; 3]>,
        trajectory: Trajectory,
    ) -> u32 {
        let actor = self.actor(class, size, trajectory);
        self.push(actor)
    }

    /// Adds the next vehicle of the fleet (a car driving `trajectory`) if it never comes too
    /// close to anything placed; returns its object id.
    pub fn add_vehicle(&mut self, trajectory: Trajectory) -> Option<u32> {
        let id = self.place(Class::Car, None, trajectory)?;
        self.vehicles.push(self.actors.len() - 1);
        Some(id)
    }

    /// Number of vehicles added.
    pub fn vehicle_count(&self) -> usize {
        self.vehicles.len()
    }

    fn push(&mut self, actor: Actor) -> u32 {
        let id = actor.id;
        self.actors.push(actor);
        self.next_id += 1;
        id
    }

    /// The finished world.
    pub fn finish(self) -> World {
        World {
            terrain: self.terrain,
            statics: self.statics,
            actors: self.actors,
            vehicles: self.vehicles,
            origin: FLEET_ORIGIN,
        }
    }
}
