//! `trackd`: the per-vehicle tracking service and its offline tools.

mod cmd;

use clap::{Parser, Subcommand};

/// Training-free LiDAR object tracking, one service per vehicle.
#[derive(Parser)]
#[command(name = "trackd", version, about, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a fleet drive and run the whole service on it (the README's main command).
    Demo(cmd::demo::Args),
    /// Run the vehicle service: REST API, tracker, Zenoh fleet sharing.
    Serve(cmd::serve::Args),
    /// Run a Zenoh router for fleets that outgrow peer-to-peer.
    Router(cmd::router::Args),
    /// Track objects through a recorded drive offline.
    Run(cmd::run::Args),
    /// Score tracks against ground truth (CLEAR MOT, IDF1, HOTA).
    Eval(cmd::eval::Args),
    /// Draw a run's tracks over the drive, seen from above, as a PNG.
    Plot(cmd::plot::Args),
    /// Time each pipeline stage on one scan.
    Bench(cmd::bench::Args),
    /// Simulate drives with ground truth, written in KITTI raw layout.
    Sim(cmd::sim::Args),
    /// Tell what a path holds: kind, frames, points, poses, labels.
    Info(cmd::info::Args),
    /// Cluster one scan with DBSCAN and write its labels.
    Cluster(cmd::cluster::Args),
    /// Compute the VFH of each labelled cluster of one scan.
    Vfh(cmd::vfh::Args),
    /// Show or check the configuration.
    Config(cmd::config::Args),
    /// Probe a service's /healthz (or a TCP port): exit 0 when healthy (container HEALTHCHECK).
    Health(cmd::health::Args),
}

fn main() -> anyhow::Result<()> {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_env("TRACKD_LOG")
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info")),
        )
        .with_writer(std::io::stderr)
        .init();
    match Cli::parse().command {
        Command::Demo(a) => cmd::demo::run(a),
        Command::Serve(a) => cmd::serve::run(a),
        Command::Router(a) => cmd::router::run(a),
        Command::Run(a) => cmd::run::run(a),
        Command::Eval(a) => cmd::eval::run(a),
        Command::Plot(a) => cmd::plot::run(a),
        Command::Bench(a) => cmd::bench::run(a),
        Command::Sim(a) => cmd::sim::run(a),
        Command::Info(a) => cmd::info::run(a),
        Command::Cluster(a) => cmd::cluster::run(a),
        Command::Vfh(a) => cmd::vfh::run(a),
        Command::Config(a) => cmd::config::run(a),
        Command::Health(a) => cmd::health::run(a),
    }
}
