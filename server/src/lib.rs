//! The trackd vehicle service as a library: settings, the perception worker, the REST API
//! and the Zenoh fleet link. `trackd serve` and `trackd demo` run it; integration tests start
//! several in one process.

#![warn(missing_docs)]

pub mod local_fleet;
pub mod service;
pub mod settings;
