//! `trackd sim`: simulates a fleet's drive in one shared world and writes each vehicle's drive
//! in KITTI raw layout with its ground truth (`tracklet_labels.xml`, `gt_tracks.csv`).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::Context as _;
use trackd_sim::write::DriveWriter;
use trackd_sim::{Scenario, SimConfig, Simulation, TerrainKind};

/// Flags of `trackd sim`.
#[derive(clap::Args)]
pub struct Args {
    /// The drive: paper, intersection, highway or crowd.
    #[arg(long, default_value = "paper")]
    pub scenario: Scenario,
    /// Scans per vehicle (10 per second).
    #[arg(long, default_value_t = 100)]
    pub frames: usize,
    /// Seed: the same seed writes the same drive, bit for bit.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Vehicles of the fleet; vehicle k is written as drive k+1.
    #[arg(long, default_value_t = 1)]
    pub vehicles: usize,
    /// Ground: flat, tilted or undulating (default: the scenario's own).
    #[arg(long, value_parser = parse_terrain)]
    pub terrain: Option<TerrainKind>,
    /// Output folder (the date folder `2011_09_26` is made inside it).
    #[arg(long)]
    pub out: PathBuf,
}

fn parse_terrain(s: &str) -> Result<TerrainKind, String> {
    match s {
        "flat" => Ok(TerrainKind::Flat),
        "tilted" => Ok(TerrainKind::Tilted),
        "undulating" => Ok(TerrainKind::Undulating),
        _ => Err(format!(
            "unknown terrain {s:?} (expected flat, tilted or undulating)"
        )),
    }
}

/// Runs `trackd sim`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let config = SimConfig {
        scenario: args.scenario,
        frames: args.frames,
        seed: args.seed,
        vehicles: args.vehicles,
        terrain: args.terrain,
    };
    let started = Instant::now();
    let sim = Simulation::new(&config).context("building the simulation")?;
    let world = sim.world();
    tracing::info!(
        scenario = %config.scenario,
        objects = world.actors.len(),
        solids = world.statics.len(),
        elapsed_ms = started.elapsed().as_millis() as u64,
        "world built"
    );
    let mut simulating = Duration::ZERO;
    let mut writing = Duration::ZERO;
    for k in 0..config.vehicles {
        let mut writer = DriveWriter::create(&args.out, k)
            .with_context(|| format!("creating drive {} in {}", k + 1, args.out.display()))?;
        let (mut points, mut rows) = (0usize, 0usize);
        for i in 0..config.frames {
            let t = Instant::now();
            let frame = sim.frame(k, i);
            simulating += t.elapsed();
            points += frame.points.len();
            rows += frame.objects.len();
            let t = Instant::now();
            writer.push(&frame)?;
            writing += t.elapsed();
        }
        let dir = writer.finish()?;
        println!(
            "{}: {} frames, {:.0} points/frame, {} ground-truth rows",
            dir.display(),
            config.frames,
            points as f64 / config.frames as f64,
            rows
        );
    }
    let n = (config.frames * config.vehicles) as f64;
    println!(
        "simulation {:.1} ms/frame, writing {:.1} ms/frame, total {:.1} s",
        simulating.as_secs_f64() * 1e3 / n,
        writing.as_secs_f64() * 1e3 / n,
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
