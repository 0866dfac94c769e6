//! The one error type of every reader and writer: it names the file and, for text formats, the
//! line.

use std::path::{Path, PathBuf};

/// What went wrong reading or writing a dataset file or folder.
#[derive(Debug, thiserror::Error)]
pub enum DatasetError {
    /// The file or folder could not be opened, read or written.
    #[error("{}: {error}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What the operating system said.
        error: std::io::Error,
    },
    /// A text file holds something other than what its format allows.
    #[error("{}:{line}: {message}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong on that line.
        message: String,
    },
    /// A binary file (or a text file as a whole) is malformed: truncated, wrong size, unknown
    /// type.
    #[error("{}: {message}", path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A folder is not laid out as any dataset this crate reads, or lacks a part it needs.
    #[error("{}: {message}", path.display())]
    Layout {
        /// The folder (or file) looked at.
        path: PathBuf,
        /// What was expected and not found.
        message: String,
    },
    /// A frame index past the end of a source.
    #[error("frame {index} out of range: the source has {len} frames")]
    FrameOutOfRange {
        /// The index asked for.
        index: usize,
        /// How many frames there are.
        len: usize,
    },
}

impl DatasetError {
    /// An I/O error on `path`.
    pub fn io(path: &Path, error: std::io::Error) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            error,
        }
    }

    /// A parse error on line `line` (1-based) of `path`.
    pub fn parse(path: &Path, line: usize, message: impl Into<String>) -> Self {
        Self::Parse {
            path: path.to_path_buf(),
            line,
            message: message.into(),
        }
    }

    /// A malformed file.
    pub fn format(path: &Path, message: impl Into<String>) -> Self {
        Self::Format {
            path: path.to_path_buf(),
            message: message.into(),
        }
    }

    /// A folder that is not a known layout or lacks a part.
    pub fn layout(path: &Path, message: impl Into<String>) -> Self {
        Self::Layout {
            path: path.to_path_buf(),
            message: message.into(),
        }
    }
}

/// Reads a whole file, naming it in the error.
pub(crate) fn read_bytes(path: &Path) -> Result<Vec<u8>, DatasetError> {
    std::fs::read(path).map_err(|e| DatasetError::io(path, e))
}

/// Reads a whole text file, naming it in the error.
pub(crate) fn read_text(path: &Path) -> Result<String, DatasetError> {
    std::fs::read_to_string(path).map_err(|e| DatasetError::io(path, e))
}

/// Writes a whole file, naming it in the error.
pub(crate) fn write_bytes(path: &Path, bytes: &[u8]) -> Result<(), DatasetError> {
    std::fs::write(path, bytes).map_err(|e| DatasetError::io(path, e))
}

/// Parses one number of a text file, naming file, line and what the number is.
pub(crate) fn parse_f64(
    path: &Path,
    line: usize,
    what: &str,
    token: &str,
) -> Result<f64, DatasetError> {
    token
        .parse::<f64>()
        .map_err(|_| DatasetError::parse(path, line, format!("{what}: {token:?} is not a number")))
}
