//! Reading and writing LiDAR data as it is published: KITTI raw drives, KITTI tracking and
//! odometry sequences, PCD files and plain folders of scans.

#![warn(missing_docs)]

pub mod shared_data;

pub use shared_data::shared_data_dir;
