//! Errors of the simulator.

use std::path::PathBuf;

use trackd_dataset::error::DatasetError;

/// Why a simulation could not be made, written or read back.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// The configuration asks for something impossible.
    #[error("invalid simulation config: {0}")]
    Config(String),
    /// Writing the KITTI layout failed.
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        source: std::io::Error,
    },
    /// A ground-truth file is malformed.
    #[error("{}:{line}: {message}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
}
