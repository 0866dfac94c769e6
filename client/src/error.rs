//! What can go wrong talking to a trackd service.

use thiserror::Error;

/// An error of a [`crate::Client`] call.
#[derive(Debug, Error)]
pub enum ClientError {
    /// The service could not be reached or the connection broke.
    #[error("request to {url} failed: {source}")]
    Transport {
        /// The URL requested.
        url: String,
        /// The underlying error.
        source: reqwest::Error,
    },
    /// The service's queue is full; retry after the given seconds.
    #[error("service busy (queue full), retry after {retry_after_s} s")]
    Busy {
        /// Seconds the service asked to wait.
        retry_after_s: u64,
    },
    /// The service answered with an error status.
    #[error("{url}: HTTP {status}: {message}")]
    Status {
        /// The URL requested.
        url: String,
        /// The HTTP status code.
        status: u16,
        /// The service's explanation (its `error` field, or the raw body).
        message: String,
    },
    /// The answer's body was not what the API promises.
    #[error("{url}: unexpected answer: {message}")]
    Decode {
        /// The URL requested.
        url: String,
        /// What did not parse.
        message: String,
    },
}
