//! The drives the simulator can make, each a world built from a seed.

pub mod builder;
pub mod crowd;
pub mod highway;
pub mod intersection;
pub mod paper;
pub mod props;
pub mod street;

use serde::{Deserialize, Serialize};

use crate::error::SimError;
use crate::scenario::builder::WorldBuilder;
use crate::terrain::{Terrain, TerrainKind};
use crate::trajectory::Trajectory;
use crate::world::World;

/// A kind of drive.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Scenario {
    /// The paper's drive: two cyclists side by side ahead, a car coming the other way.
    Paper,
    /// A crossroads: crossing and turning traffic, pedestrians at the crossings, parked cars;
    /// the first vehicle turns left.
    Intersection,
    /// Three lanes each way behind guard rails, traffic at up to 33 m/s; the first vehicle
    /// changes lanes.
    Highway,
    /// A street along a plaza full of pedestrians and cyclists; the first vehicle stops at a
    /// crossing.
    Crowd,
}

impl Scenario {
    /// Every scenario.
    pub const ALL: [Self; 4] = [Self::Paper, Self::Intersection, Self::Highway, Self::Crowd];

    /// The scenario's name on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Paper => "paper",
            Self::Intersection => "intersection",
            Self::Highway => "highway",
            Self::Crowd => "crowd",
        }
    }

    /// The ground the scenario runs on unless told otherwise.
    pub fn default_terrain(&self) -> TerrainKind {
        match self {
            Self::Paper => TerrainKind::Tilted,
            Self::Intersection | Self::Crowd => TerrainKind::Flat,
            Self::Highway => TerrainKind::Undulating,
        }
    }

    /// Builds the world of a drive of `duration` seconds with `vehicles` vehicles.
    pub fn build(
        &self,
        duration: f64,
        vehicles: usize,
        terrain: Option<TerrainKind>,
        seed: u64,
    ) -> Result<World, SimError> {
        let mut rng = <rand_chacha::ChaCha8Rng as rand::SeedableRng>::seed_from_u64(
            crate::random::hash_seed(&[seed, 0x7e44a1]),
        );
        let terrain = Terrain::random(terrain.unwrap_or(self.default_terrain()), &mut rng);
        let mut b = WorldBuilder::new(terrain, duration, seed);
        match self {
            Self::Paper => paper::build(&mut b, vehicles)?,
            Self::Intersection => intersection::build(&mut b, vehicles)?,
            Self::Highway => highway::build(&mut b, vehicles)?,
            Self::Crowd => crowd::build(&mut b, vehicles)?,
        }
        Ok(b.finish())
    }
}

impl std::fmt::Display for Scenario {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Scenario {
    type Err = SimError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|x| x.name() == s)
            .ok_or_else(|| {
                SimError::Config(format!(
                    "unknown scenario {s:?} (expected paper, intersection, highway or crowd)"
                ))
            })
    }
}

/// Trajectories to try, in order, for the fleet's vehicles.
pub type Candidates = Vec<Trajectory>;

/// Places `vehicles` vehicles on the first candidates that collide with nothing.
pub fn place_vehicles(
    b: &mut WorldBuilder,
    vehicles: usize,
    candidates: Candidates,
) -> Result<(), SimError> {
    let mut candidates = candidates.into_iter();
    while b.vehicle_count() < vehicles {
        let Some(trajectory) = candidates.next() else {
            return Err(SimError::Config(format!(
                "no room for vehicle {} of {vehicles} in this scenario",
                b.vehicle_count() + 1
            )));
        };
        b.add_vehicle(trajectory);
    }
    Ok(())
}
