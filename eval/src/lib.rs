//! How trackd's tracks are judged (`../shared/eval-protocol.md`): ground truth from simulated
//! drives and KITTI labels, BEV centre matching, CLEAR MOT, IDF1 and HOTA.
//!
//! ```no_run
//! use std::path::Path;
//! use trackd_eval::{EvalConfig, evaluate, gt::sim, read_tracks_csv};
//!
//! let gt = sim::read_sim_ground_truth(Path::new("gt_tracks.csv"), &sim::SimRules::default())?;
//! let tracks = read_tracks_csv(Path::new("tracks.csv"))?;
//! let metrics = evaluate(&gt, &tracks, &EvalConfig::default());
//! println!("{}", metrics.table());
//! # Ok::<(), trackd_eval::EvalError>(())
//! ```

#![warn(missing_docs)]

pub mod assignment;
pub mod clear_mot;
pub mod config;
mod csv;
pub mod error;
pub mod evaluate;
pub mod events_csv;
pub mod gt;
pub mod hota;
pub mod idf1;
pub mod matching;
pub mod prepare;
pub mod report;
pub mod tracks_csv;
pub mod view;

pub use config::EvalConfig;
pub use error::EvalError;
pub use evaluate::{evaluate, evaluate_with_events};
pub use gt::{GroundTruth, GtFrame, GtObject};
pub use report::Metrics;
pub use tracks_csv::{TrackRow, read_tracks_csv};
