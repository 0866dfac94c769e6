//! One shared world: ground, static structure, objects, and the vehicles driving in it.

use trackd_perception::geo::GeoOrigin;

use crate::actor::Actor;
use crate::geometry::Primitive;
use crate::terrain::Terrain;

/// The geodetic origin of every simulated fleet: near Karlsruhe, where KITTI was recorded.
pub const FLEET_ORIGIN: GeoOrigin = GeoOrigin::new(49.0, 8.4, 115.0);

/// A world: everything every vehicle's sensor can see, over the whole drive.
#[derive(Clone, Debug)]
pub struct World {
    /// The ground.
    pub terrain: Terrain,
    /// Buildings, walls, poles, trees, guard rails, furniture (label `Static`).
    pub statics: Vec<Primitive>,
    /// Ground-truth objects, parked or moving, the vehicles themselves included.
    pub actors: Vec<Actor>,
    /// For each vehicle of the fleet, the index of its own actor in `actors`.
    pub vehicles: Vec<usize>,
    /// Geodetic origin of the world frame.
    pub origin: GeoOrigin,
}

impl World {
    /// The actor that is vehicle `k`.
    pub fn vehicle(&self, k: usize) -> &Actor {
        &self.actors[self.vehicles[k]]
    }

    /// The solids of every actor at time `t` except the one with id `exclude` (a vehicle
    /// does not see itself).
    pub fn dynamic_primitives(&self, t: f64, exclude: Option<u32>) -> Vec<Primitive> {
        let mut out = Vec::new();
        for actor in &self.actors {
            if Some(actor.id) != exclude {
                actor.primitives(&actor.pose_at(t, &self.terrain), &mut out);
            }
        }
        out
    }
}
