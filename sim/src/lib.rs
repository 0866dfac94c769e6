//! Simulated drives with ground truth, written in KITTI's raw layout so the same readers read
//! them: for tests, demos and benchmarks.

#![warn(missing_docs)]
