//! One module per subcommand: its flags (`Args`) and its entry point (`run`); `clusters_csv`
//! (`--debug-clusters`' file) and `occupancy_thread` (the map's thread) serve `trackd run`.

pub mod bench;
pub mod cluster;
pub mod clusters_csv;
pub mod config;
pub mod demo;
pub mod eval;
pub mod health;
pub mod info;
pub mod occupancy_thread;
pub mod plot;
pub mod router;
pub mod run;
pub mod segment_thread;
pub mod serve;
pub mod sim;
pub mod vfh;
