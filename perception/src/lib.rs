//! trackd's perception core: the paper's pipeline as plain, synchronous stages.
//!
//! Each stage takes and returns plain data (`&[Point]`, clusters, histograms) so it can be
//! tested, benchmarked and replaced alone; nothing here does I/O, spawns threads of its own
//! or touches the network.

#![warn(missing_docs)]

mod angle;
pub mod cluster;
pub mod config;
pub mod filter;
pub mod fleet;
pub mod frame;
pub mod geo;
pub mod ground;
pub mod occupancy;
pub mod oxts;
mod pca;
pub mod pipeline;
pub mod point;
pub mod pose;
pub mod superframe;
pub mod track;
pub mod transform;
pub mod vfh;
mod voxel;
pub mod wire;

pub use frame::{Ego, Frame, ObjectClass, StageTimings, TrackState};
pub use pipeline::{FrameOutput, Pipeline, PipelineError, Vehicle};
pub use point::Point;
