//! What can go wrong while reading ground truth or tracks.

use std::path::PathBuf;

/// An evaluation input that cannot be read or is invalid.
#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    /// A file could not be read.
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A CSV file lacks a column the format requires.
    #[error("{}: header lacks column `{column}`", path.display())]
    MissingColumn {
        /// The file.
        path: PathBuf,
        /// The missing column's name.
        column: String,
    },
    /// A row does not parse (wrong field count, not a number, …).
    #[error("{}:{line}: {message}", path.display())]
    BadRow {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A coordinate is NaN or infinite.
    #[error("{}:{line}: column `{column}` is not finite", path.display())]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// The column.
        column: String,
    },
    /// The same (frame, id) appears twice.
    #[error("{}:{line}: frame {frame} id {id} repeats line {first_line}", path.display())]
    Duplicate {
        /// The file.
        path: PathBuf,
        /// 1-based line number of the repeat.
        line: usize,
        /// 1-based line number of the first occurrence.
        first_line: usize,
        /// The frame.
        frame: u32,
        /// The repeated track or object id.
        id: u64,
    },
    /// A dataset file (KITTI labels, calibration, tracklets, scans) could not be read.
    #[error(transparent)]
    Dataset(#[from] trackd_dataset::DatasetError),
    /// Ground truth that reads but breaks a rule of its format (e.g. a repeated object).
    #[error("{}: {message}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}
