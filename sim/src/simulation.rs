//! Running a simulation: the configuration, the per-vehicle truth and OXTS computed up front,
//! and scans made frame by frame (or all at once for tests).

use nalgebra::Isometry3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use trackd_perception::Point;
use trackd_perception::oxts::Oxts;

use crate::ego::{EgoState, Mount, ego_state};
use crate::error::SimError;
use crate::gt::{GtObject, ground_truth};
use crate::label::PointLabel;
use crate::oxts_noise::OxtsNoise;
use crate::oxts_truth::Motion;
use crate::random::hash_seed;
use crate::raycast::Scene;
use crate::scenario::Scenario;
use crate::sensor::Lidar;
use crate::terrain::TerrainKind;
use crate::world::World;

/// Seconds between scans (10 Hz).
pub const FRAME_PERIOD: f64 = 0.1;

/// Unix time of a drive's time 0: 2011-09-26 13:02:25 UTC, the day of KITTI's calibration.
pub const START_UNIX_TIME: f64 = 1_317_042_145.0;

/// What to simulate.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SimConfig {
    /// The kind of drive.
    pub scenario: Scenario,
    /// Scans per vehicle.
    pub frames: usize,
    /// Seed: the same seed gives the same drive, bit for bit.
    pub seed: u64,
    /// Vehicles of the fleet, all in the one world.
    pub vehicles: usize,
    /// The ground; `None` takes the scenario's own (paper: tilted, highway: undulating,
    /// intersection and crowd: flat).
    pub terrain: Option<TerrainKind>,
}

impl SimConfig {
    /// A drive of `frames` scans of `scenario` for one vehicle.
    pub fn new(scenario: Scenario, frames: usize, seed: u64) -> Self {
        Self {
            scenario,
            frames,
            seed,
            vehicles: 1,
            terrain: None,
        }
    }

    /// The same with `vehicles` vehicles.
    pub fn with_vehicles(mut self, vehicles: usize) -> Self {
        self.vehicles = vehicles;
        self
    }

    /// The same on `terrain`.
    pub fn with_terrain(mut self, terrain: TerrainKind) -> Self {
        self.terrain = Some(terrain);
        self
    }

    /// Seconds the drive lasts.
    pub fn duration(&self) -> f64 {
        self.frames as f64 * FRAME_PERIOD
    }
}

/// One scan of one vehicle with everything known about it.
#[derive(Clone, Debug, PartialEq)]
pub struct SimFrame {
    /// Vehicle index (0-based; drive folder number − 1).
    pub vehicle: usize,
    /// Frame index.
    pub index: usize,
    /// Unix time of the scan (seconds).
    pub timestamp: f64,
    /// Points in the Velodyne frame (KITTI `.bin` content).
    pub points: Vec<Point>,
    /// What each point hit.
    pub labels: Vec<PointLabel>,
    /// The packet the (noisy) OXTS unit reported.
    pub oxts: Oxts,
    /// True pose of the Velodyne in the world (maps Velodyne coordinates to world ones).
    pub velodyne_pose: Isometry3<f64>,
    /// True pose of the IMU in the world.
    pub imu_pose: Isometry3<f64>,
    /// Ground truth: objects within 80 m.
    pub objects: Vec<GtObject>,
}

/// A vehicle's drive before its scans are made.
#[derive(Clone, Debug)]
struct Drive {
    /// Seconds since the world's time 0, per frame.
    times: Vec<f64>,
    states: Vec<EgoState>,
    oxts: Vec<Oxts>,
}

/// A simulation ready to make scans: the world, and each vehicle's true motion and OXTS.
#[derive(Debug)]
pub struct Simulation {
    config: SimConfig,
    world: World,
    lidar: Lidar,
    drives: Vec<Drive>,
}

impl Simulation {
    /// Builds the world and computes every vehicle's motion and OXTS packets.
    pub fn new(config: &SimConfig) -> Result<Self, SimError> {
        if config.frames == 0 {
            return Err(SimError::Config("frames must be at least 1".into()));
        }
        if config.vehicles == 0 {
            return Err(SimError::Config("vehicles must be at least 1".into()));
        }
        let world = config.scenario.build(
            config.duration(),
            config.vehicles,
            config.terrain,
            config.seed,
        )?;
        let mount = Mount::kitti();
        let noise = OxtsNoise::default();
        let drives = (0..config.vehicles)
            .map(|k| {
                let mut rng =
                    ChaCha8Rng::seed_from_u64(hash_seed(&[config.seed, k as u64, 0x0475]));
                // Vehicles' scanners are not in step: each has its own phase, and jitter.
                let phase = if k == 0 {
                    0.0
                } else {
                    crate::random::between(&mut rng, 0.0, FRAME_PERIOD)
                };
                let times: Vec<f64> = (0..config.frames)
                    .map(|i| {
                        phase
                            + i as f64 * FRAME_PERIOD
                            + crate::random::between(&mut rng, -0.002, 0.002)
                    })
                    .collect();
                let trajectory = &world.vehicle(k).trajectory;
                let states: Vec<EgoState> = times
                    .iter()
                    .map(|&t| ego_state(&world.terrain, trajectory, &mount, t))
                    .collect();
                let motions: Vec<Motion> = states.iter().map(Motion::of).collect();
                let oxts = noise.packets(&motions, &times, &world.origin, &mut rng);
                Drive {
                    times,
                    states,
                    oxts,
                }
            })
            .collect();
        Ok(Self {
            config: config.clone(),
            world,
            lidar: Lidar::hdl64e(),
            drives,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    /// The world.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The sensor model.
    pub fn lidar(&self) -> &Lidar {
        &self.lidar
    }

    /// Unix timestamp of a vehicle's frame.
    pub fn timestamp(&self, vehicle: usize, frame: usize) -> f64 {
        START_UNIX_TIME + self.drives[vehicle].times[frame]
    }

    /// Makes frame `frame` of vehicle `vehicle` (both in range).
    pub fn frame(&self, vehicle: usize, frame: usize) -> SimFrame {
        let drive = &self.drives[vehicle];
        let t = drive.times[frame];
        let state = &drive.states[frame];
        let own = self.world.vehicle(vehicle).id;
        let dynamic = self.world.dynamic_primitives(t, Some(own));
        let origin = state.velodyne_pose.translation.vector;
        let scene = Scene::new(
            &self.world.terrain,
            &[&self.world.statics, &dynamic],
            origin,
            self.lidar.max_range,
        );
        let seed = hash_seed(&[self.config.seed, vehicle as u64, frame as u64]);
        let scan = self.lidar.scan(&scene, &state.velodyne_pose, seed);
        let objects = ground_truth(
            &self.world,
            vehicle,
            frame,
            t,
            &state.velodyne_pose,
            &scan.labels,
        );
        SimFrame {
            vehicle,
            index: frame,
            timestamp: self.timestamp(vehicle, frame),
            points: scan.points,
            labels: scan.labels,
            oxts: drive.oxts[frame],
            velodyne_pose: state.velodyne_pose,
            imu_pose: state.imu_pose,
            objects,
        }
    }

    /// All frames of a vehicle, in order.
    pub fn frames(&self, vehicle: usize) -> impl Iterator<Item = SimFrame> + '_ {
        (0..self.config.frames).map(move |i| self.frame(vehicle, i))
    }

    /// The noisy OXTS packets of a vehicle (no scans needed).
    pub fn oxts(&self, vehicle: usize) -> &[Oxts] {
        &self.drives[vehicle].oxts
    }

    /// The true Velodyne poses of a vehicle (no scans needed).
    pub fn velodyne_poses(&self, vehicle: usize) -> Vec<Isometry3<f64>> {
        self.drives[vehicle]
            .states
            .iter()
            .map(|s| s.velodyne_pose)
            .collect()
    }
}

/// A whole simulation in memory: every frame of every vehicle.
#[derive(Clone, Debug)]
pub struct SimRun {
    /// What was simulated.
    pub config: SimConfig,
    /// The world it happened in.
    pub world: World,
    /// `vehicles[k][i]`: frame `i` of vehicle `k`.
    pub vehicles: Vec<Vec<SimFrame>>,
}

/// Simulates every frame of every vehicle (about 2 MB per frame: keep runs short, or use
/// [`Simulation::frame`] to make frames one at a time).
pub fn simulate(config: &SimConfig) -> Result<SimRun, SimError> {
    let sim = Simulation::new(config)?;
    let vehicles = (0..config.vehicles)
        .map(|k| sim.frames(k).collect())
        .collect();
    Ok(SimRun {
        config: config.clone(),
        world: sim.world,
        vehicles,
    })
}
