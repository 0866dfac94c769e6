//! What can go wrong while reading ground truth or tracks.

use std::path::PathBuf;

/// An evaluation input that cannot be read or is invalid.
#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    /// A file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A CSV file lacks a column the format requires.
    #[error("{path}: header lacks column `{column}`")]
    MissingColumn {
        /// The file.
        path: PathBuf,
        /// The missing column's name.
        column: String,
    },
    /// A row does not parse (wrong field count, not a number, …).
    #[error("{path}:{line}: {message}")]
    BadRow {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A coordinate is NaN or infinite.
    #[error("{path}:{line}: column `{column}` is not finite")]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// The column.
        column: String,
    },
    /// The same (frame, id) appears twice.
    #[error("{path}:{line}: frame {frame} id {id} repeats line {first_line}")]
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
}
