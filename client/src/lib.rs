//! A client for trackd's REST API.

#![warn(missing_docs)]
