//! Reading and writing LiDAR data as it is published: KITTI raw drives, KITTI tracking and
//! odometry sequences, PCD files and plain folders of scans.

#![warn(missing_docs)]

pub mod bin;
pub mod calib;
pub mod clean;
pub mod error;
pub mod labels;
mod numfmt;
pub mod oxts;
pub mod pcd;
pub mod poses;
pub mod scan;
pub mod shared_data;
pub mod source;
pub mod timestamps;
pub mod tracklets;

pub use error::DatasetError;
pub use shared_data::shared_data_dir;
pub use source::{OpenOptions, ScanStats, Source, SourceKind, open};
