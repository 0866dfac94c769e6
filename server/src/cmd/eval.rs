//! `trackd eval`: scores a `tracks.csv` against ground truth (eval-protocol.md) and writes the
//! metrics as JSON.

use std::path::{Path, PathBuf};

use anyhow::Context;
use trackd_eval::{
    EvalConfig, GroundTruth, evaluate_with_events,
    gt::{
        kitti::{KittiRules, KittiTrackingFiles, read_kitti_tracking_ground_truth},
        sim::{SimRules, read_sim_ground_truth},
        tracklets::{KittiRawFiles, read_kitti_raw_ground_truth},
    },
    read_tracks_csv,
};

/// Flags of `trackd eval`.
#[derive(clap::Args)]
pub struct Args {
    /// Ground truth: a simulated drive's `gt_tracks.csv`, a KITTI tracking
    /// `label_02/<seq>.txt` or a KITTI raw `tracklet_labels.xml`.
    #[arg(long)]
    gt: PathBuf,
    /// The tracker's `tracks.csv`.
    #[arg(long)]
    tracks: PathBuf,
    /// BEV range of the scored region in metres [default: 40 for KITTI, 50 for simulated
    /// drives (where farther objects are don't care)].
    #[arg(long)]
    max_range: Option<f64>,
    /// Match threshold on the BEV centre distance (metres): pairs at this distance or more may
    /// not match.
    #[arg(long, default_value_t = 2.0)]
    threshold: f64,
    /// Match threshold for cyclists instead of --threshold (the protocol's cyclist test: 0.6).
    #[arg(long)]
    cyclist_threshold: Option<f64>,
    /// GT objects with fewer LiDAR points are dropped (KITTI) or don't care (simulated).
    #[arg(long, default_value_t = 10)]
    min_points: u32,
    /// KITTI calibration: a tracking sequence's `calib/<seq>.txt`, or a raw drive's date
    /// folder [default: where KITTI puts it beside the labels].
    #[arg(long)]
    calib: Option<PathBuf>,
    /// KITTI scans to count points in boxes: `velodyne/<seq>/` or a raw drive's
    /// `velodyne_points/data/` [default: where KITTI puts them beside the labels].
    #[arg(long)]
    scans: Option<PathBuf>,
    /// Score KITTI ground truth without its scans, keeping boxes whatever their point count.
    #[arg(long)]
    no_point_filter: bool,
    /// Where to write the metrics as JSON [default: metrics.json beside --tracks].
    #[arg(long)]
    out: Option<PathBuf>,
    /// Also write every frame's matches, misses and false positives, with positions, as CSV
    /// (`frame,event,gt_id,track_id,distance,gt_x,gt_y,track_x,track_y`).
    #[arg(long)]
    events: Option<PathBuf>,
}

/// The ground-truth formats `--gt` can name.
enum GtFormat {
    /// A simulated drive's `gt_tracks.csv`.
    Sim,
    /// A KITTI tracking `label_02/<seq>.txt`.
    KittiTracking,
    /// A KITTI raw `tracklet_labels.xml`.
    KittiRaw,
}

impl GtFormat {
    /// Tells the format from the file name.
    fn of(path: &Path) -> anyhow::Result<Self> {
        match path.extension().and_then(|e| e.to_str()) {
            Some("csv") => Ok(Self::Sim),
            Some("txt") => Ok(Self::KittiTracking),
            Some("xml") => Ok(Self::KittiRaw),
            _ => anyhow::bail!(
                "{}: not a ground-truth file trackd knows (gt_tracks.csv, label_02/<seq>.txt, \
                 tracklet_labels.xml)",
                path.display()
            ),
        }
    }
}

/// Runs `trackd eval`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let config = EvalConfig {
        threshold: args.threshold,
        cyclist_threshold: args.cyclist_threshold,
    };
    anyhow::ensure!(
        config.threshold > 0.0 && config.cyclist_threshold.is_none_or(|t| t > 0.0),
        "match thresholds must be positive"
    );
    let gt = load_gt(&args)?;
    let tracks = read_tracks_csv(&args.tracks)?;
    let (metrics, events) = evaluate_with_events(&gt, &tracks, &config);
    print!("{}", metrics.table());
    if let Some(path) = &args.events {
        std::fs::write(path, events).with_context(|| format!("writing {}", path.display()))?;
        tracing::info!("events written to {}", path.display());
    }
    let out = args
        .out
        .unwrap_or_else(|| args.tracks.with_file_name("metrics.json"));
    let json = serde_json::to_string_pretty(&metrics)?;
    std::fs::write(&out, json + "\n").with_context(|| format!("writing {}", out.display()))?;
    tracing::info!("metrics written to {}", out.display());
    Ok(())
}

/// Reads the ground truth in whichever format `--gt` is.
fn load_gt(args: &Args) -> anyhow::Result<GroundTruth> {
    match GtFormat::of(&args.gt)? {
        GtFormat::Sim => {
            let rules = SimRules {
                min_points: args.min_points,
                max_range: args.max_range.unwrap_or(SimRules::default().max_range),
            };
            Ok(read_sim_ground_truth(&args.gt, &rules)?)
        }
        GtFormat::KittiTracking => {
            let mut files = KittiTrackingFiles::beside(&args.gt);
            if let Some(calib) = &args.calib {
                files.calib = calib.clone();
            }
            files.scans = scans(args, files.scans)?;
            Ok(read_kitti_tracking_ground_truth(
                &files,
                &kitti_rules(args),
            )?)
        }
        GtFormat::KittiRaw => {
            let mut files = KittiRawFiles::beside(&args.gt);
            if args.calib.is_some() {
                files.calib_dir = args.calib.clone();
            }
            if files.calib_dir.is_none() {
                tracing::warn!(
                    "no raw calibration beside {} (--calib DATE_DIR): only the {} m range \
                     bounds the scored view, not the camera's field of view",
                    args.gt.display(),
                    kitti_rules(args).max_range
                );
            }
            files.scans = scans(args, files.scans)?;
            Ok(read_kitti_raw_ground_truth(&files, &kitti_rules(args))?)
        }
    }
}

/// The protocol's KITTI rules with the flags' range and point count.
fn kitti_rules(args: &Args) -> KittiRules {
    let default = KittiRules::default();
    KittiRules {
        min_points: args.min_points,
        max_range: args.max_range.unwrap_or(default.max_range),
        ..default
    }
}

/// The KITTI scan folder to count points in: `--scans`, else the one found beside the labels;
/// none only with --no-point-filter.
fn scans(args: &Args, found: Option<PathBuf>) -> anyhow::Result<Option<PathBuf>> {
    if args.no_point_filter {
        tracing::warn!("--no-point-filter: GT boxes are kept whatever their LiDAR point count");
        return Ok(None);
    }
    match args.scans.clone().or(found) {
        Some(dir) => Ok(Some(dir)),
        None => anyhow::bail!(
            "no scans found beside {} to count LiDAR points in GT boxes: pass --scans DIR, or \
             --no-point-filter to keep every box",
            args.gt.display()
        ),
    }
}
