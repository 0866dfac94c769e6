//! Simulated drives with ground truth, written in KITTI's raw layout so the same readers read
//! them: for tests, demos and benchmarks.
//!
//! A [`Scenario`] builds one shared [`World`] (ground, static structure, objects, and the
//! fleet's vehicles as objects too) from a seed. Each vehicle drives its trajectory with an
//! HDL-64E-like [`Lidar`] on its roof and a noisy OXTS unit; [`Simulation::frame`] ray-casts
//! one scan and labels every point ([`PointLabel`]) and the objects near the vehicle
//! ([`GtObject`]). [`write_run`] and [`write_simulation`] write KITTI raw drive folders.
//!
//! ```no_run
//! use trackd_sim::{Scenario, SimConfig, simulate};
//! let run = simulate(&SimConfig::new(Scenario::Paper, 20, 7).with_vehicles(2))?;
//! let frame = &run.vehicles[0][10];
//! println!("{} points, {} objects", frame.points.len(), frame.objects.len());
//! # Ok::<(), trackd_sim::SimError>(())
//! ```

#![warn(missing_docs)]

pub mod actor;
pub mod body;
pub mod class;
pub mod clearance;
pub mod ego;
pub mod error;
pub mod geometry;
pub mod gt;
pub mod label;
pub mod material;
pub mod oxts_noise;
pub mod oxts_truth;
pub mod path;
pub mod random;
pub mod raycast;
pub mod scenario;
pub mod sensor;
pub mod simulation;
pub mod speed;
pub mod terrain;
pub mod tracklet;
pub mod trajectory;
pub mod world;
pub mod write;

pub use class::Class;
pub use error::SimError;
pub use gt::{GT_CSV_HEADER, GT_RANGE, GtObject, read_gt_csv};
pub use label::PointLabel;
pub use scenario::Scenario;
pub use sensor::Lidar;
pub use simulation::{FRAME_PERIOD, SimConfig, SimFrame, SimRun, Simulation, simulate};
pub use terrain::TerrainKind;
pub use world::{FLEET_ORIGIN, World};
pub use write::{drive_dir, write_run, write_simulation};
