//! `trackd run INPUT --out DIR`: tracks objects through a recorded drive offline and writes
//! `tracks.csv` (Velodyne frame of each scan), KITTI tracking results (camera frame, when the
//! drive is calibrated), the super frames, the occupancy map, the ego poses and per-stage
//! timings. Three threads overlap: one reads and segments the scans ahead, the main one tracks
//! them, and one updates the occupancy map.

use std::collections::BTreeSet;
use std::fs::File;
use std::io::{BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use nalgebra::{Isometry3, Point3, Vector3};
use prost::Message;
use trackd_dataset::calib::RectifiedCamera;
use trackd_dataset::labels::{KittiLabel, write_tracking_results};
use trackd_dataset::poses::write_poses;
use trackd_dataset::{OpenOptions, Source, open};
use trackd_perception::StageTimings;
use trackd_perception::occupancy::OccupancyMap;
use trackd_perception::pipeline::TrackingFrame;
use trackd_perception::track::AssociationMode;
use trackd_perception::{FrameOutput, ObjectClass, Pipeline, PipelineError, TrackState, Vehicle};
use trackd_service::settings::Settings;

use crate::cmd::clusters_csv::ClustersCsv;
use crate::cmd::occupancy_thread::OccupancyThread;
use crate::cmd::segment_thread::{SegmentThread, SegmentedScan, scan_name};

/// Header of `tracks.csv` (eval-protocol.md).
pub const TRACKS_HEADER: &str = "frame,track_id,x,y,z,l,w,h,yaw,vx,vy,confidence,class";

/// Flags of `trackd run`.
#[derive(clap::Args)]
pub struct Args {
    /// A recorded drive: a KITTI raw drive, a KITTI tracking or odometry folder, a folder of
    /// .pcd or .bin scans, or one scan file (anything `trackd info` recognises).
    pub input: PathBuf,
    /// Sequence or drive, when the folder holds several (`0000`, `0001`).
    #[arg(long)]
    pub seq: Option<String>,
    /// Ego poses in KITTI odometry format, instead of what the drive holds.
    #[arg(long)]
    pub poses: Option<PathBuf>,
    /// Configuration file (`trackd.toml`; its `[perception]` and `[vehicle]` tables are used).
    #[arg(long, env = "TRACKD_CONFIG")]
    pub config: Option<PathBuf>,
    /// Output folder (created).
    #[arg(long)]
    pub out: PathBuf,
    /// Association steps, overriding the configuration (the ablation): chi2, chi2_mdt,
    /// chi2_mdt_motion, gated_assignment.
    #[arg(long, value_parser = parse_association)]
    pub association: Option<AssociationMode>,
    /// Process at most this many scans.
    #[arg(long)]
    pub frames: Option<usize>,
    /// Also write what the tracker measured of every cluster of every scan, and which track
    /// took it, to DIR/clusters.csv: why an object was or was not reported.
    #[arg(long)]
    pub debug_clusters: bool,
}

/// Parses an association mode by its configuration name.
fn parse_association(text: &str) -> Result<AssociationMode, String> {
    serde_json::from_value(serde_json::Value::String(text.to_string())).map_err(|_| {
        format!("{text:?}: expected chi2, chi2_mdt, chi2_mdt_motion or gated_assignment")
    })
}

/// Runs `trackd run`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let settings = match &args.config {
        Some(path) => Settings::read(path)?,
        None => Settings::default(),
    };
    let mut config = settings.perception.clone();
    if let Some(mode) = args.association {
        config.track.association.mode = mode;
    }
    let source = open(
        &args.input,
        &OpenOptions {
            seq: args.seq.clone(),
            poses: args.poses.clone(),
        },
    )
    .with_context(|| format!("opening {}", args.input.display()))?;
    let frames = args.frames.map_or(source.len(), |n| n.min(source.len()));
    if !source.has_oxts() && !source.has_poses() {
        tracing::warn!(
            "{}: no OXTS and no poses, tracking in the sensor frame of each scan",
            source.name()
        );
    }
    let vehicle = Vehicle {
        id: settings.vehicle.id.clone(),
        origin: settings.fleet.origin(),
        imu_to_velo: source
            .imu_to_velo()
            .unwrap_or_else(|| settings.vehicle.imu_to_velo()),
    };
    let (segmentation, mut tracking) = Pipeline::new(config, vehicle).into_halves();
    tracking.hand_out_occupancy();
    let occupancy = OccupancyThread::spawn(tracking.config().occupancy.clone())?;
    let mut out = Outputs::create(&args.out, source.calib().is_some(), args.debug_clusters)?;
    let progress = progress_bar(frames as u64);
    let started = Instant::now();
    let segmenter = SegmentThread::spawn(source.clone(), frames, segmentation)?;
    let (mut segmenting_ms, mut tracking_ms) = (Vec::new(), Vec::new());
    let mut ids = BTreeSet::new();
    let mut tracking_frame = TrackingFrame::World;
    for scan in segmenter.scans() {
        let SegmentedScan {
            index: i,
            result,
            ms,
        } = scan?;
        let mut segmented = match result {
            Ok(segmented) => segmented,
            // No GPS fix yet: the scan cannot be placed in the world; the next ones will.
            Err(PipelineError::Pose(e)) => {
                tracing::warn!("scan {i} ({}) skipped: {e}", scan_name(&source, i));
                progress.inc(1);
                continue;
            }
            Err(e) => {
                return Err(e).with_context(|| format!("scan {i} ({})", scan_name(&source, i)));
            }
        };
        let t0 = Instant::now();
        let mut result = tracking.track(&mut segmented);
        segmenter.recycle(segmented);
        if let Some(scan) = result.occupancy_scan.take() {
            occupancy.integrate(i, scan)?;
        }
        segmenting_ms.push(ms);
        tracking_ms.push(t0.elapsed().as_secs_f64() * 1e3);
        tracking_frame = result.tracking_frame;
        ids.extend(result.tracks.iter().map(|t| t.id));
        out.write_frame(i, source.frame_id(i)?, &result, source.calib())?;
        if let Some(clusters) = &mut out.clusters {
            clusters.write_frame(i, &result.odometry_pose, tracking.tracker())?;
        }
        progress.inc(1);
    }
    progress.finish_and_clear();
    let occupancy = occupancy.finish()?;
    out.finish(frames, &occupancy.map, &occupancy.timings, &source)?;
    let wall = started.elapsed().as_secs_f64();
    let mut occupancy_ms: Vec<f64> = occupancy.timings.iter().map(|(_, ms)| *ms).collect();
    println!(
        "{}: {frames} scans in {wall:.2} s ({:.1} Hz end to end; median ms a scan: \
         segmentation {:.1}, tracking {:.1}, occupancy {:.1}), {} object tracks, tracked in the \
         {} frame; wrote {}",
        source.name(),
        frames as f64 / wall.max(1e-9),
        median(&mut segmenting_ms),
        median(&mut tracking_ms),
        median(&mut occupancy_ms),
        ids.len(),
        match tracking_frame {
            TrackingFrame::World => "world",
            TrackingFrame::Sensor => "sensor (no pose)",
        },
        args.out.display()
    );
    Ok(())
}

/// The median of `values` (0 when empty).
fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(0.0)
}

/// A progress bar on a terminal, nothing otherwise.
fn progress_bar(len: u64) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    if let Ok(style) =
        ProgressStyle::with_template("{bar:40} {pos}/{len} scans, {per_sec}, eta {eta}")
    {
        bar.set_style(style);
    }
    bar
}

/// The output files of a run.
struct Outputs {
    dir: PathBuf,
    tracks: BufWriter<File>,
    timings: BufWriter<File>,
    /// Each processed scan's index and stage timings, written once the occupancy thread's
    /// timings are in.
    frame_timings: Vec<(usize, StageTimings)>,
    kitti: Option<Vec<KittiLabel>>,
    clusters: Option<ClustersCsv>,
    /// The Velodyne pose in the world frame of each scan, by index; `None` for a skipped one.
    ego_poses: Vec<Option<Isometry3<f64>>>,
}

impl Outputs {
    /// Creates the output folder and opens the per-frame files.
    fn create(dir: &Path, calibrated: bool, debug_clusters: bool) -> anyhow::Result<Self> {
        std::fs::create_dir_all(dir.join("superframes"))
            .with_context(|| format!("creating {}", dir.display()))?;
        let create = |name: &str| -> anyhow::Result<BufWriter<File>> {
            let path = dir.join(name);
            Ok(BufWriter::new(
                File::create(&path).with_context(|| format!("creating {}", path.display()))?,
            ))
        };
        let mut tracks = create("tracks.csv")?;
        writeln!(tracks, "{TRACKS_HEADER}")?;
        let clusters = if debug_clusters {
            Some(ClustersCsv::new(create("clusters.csv")?)?)
        } else {
            None
        };
        Ok(Self {
            dir: dir.to_path_buf(),
            tracks,
            timings: create("timings.csv")?,
            frame_timings: Vec::new(),
            kitti: calibrated.then(Vec::new),
            clusters,
            ego_poses: Vec::new(),
        })
    }

    /// Writes what scan `index` (frame number `frame_id` in the recording) yielded.
    fn write_frame(
        &mut self,
        index: usize,
        frame_id: usize,
        result: &FrameOutput,
        camera: Option<&RectifiedCamera>,
    ) -> anyhow::Result<()> {
        let to_sensor = result.ego_pose.inverse();
        for track in &result.tracks {
            let row = SensorRow::new(track, &to_sensor);
            if !row.is_finite() {
                tracing::warn!(
                    "scan {index}: track {} has a non-finite value, skipped",
                    track.id
                );
                continue;
            }
            writeln!(
                self.tracks,
                "{index},{},{:.4},{:.4},{:.4},{:.3},{:.3},{:.3},{:.4},{:.3},{:.3},{:.4},{}",
                track.id,
                row.center.x,
                row.center.y,
                row.center.z,
                track.size.x,
                track.size.y,
                track.size.z,
                row.yaw,
                track.velocity.x,
                track.velocity.y,
                track.confidence,
                track.class.as_str()
            )?;
            if let (Some(labels), Some(camera)) = (&mut self.kitti, camera)
                && let Some(label) = kitti_label(frame_id, track, &row, camera)
            {
                labels.push(label);
            }
        }
        self.frame_timings.push((index, result.timings.clone()));
        if self.ego_poses.len() <= index {
            self.ego_poses.resize(index + 1, None);
        }
        self.ego_poses[index] = Some(result.ego_pose);
        if let Some(sf) = &result.superframe {
            let path = self
                .dir
                .join("superframes")
                .join(format!("{:06}.pb", sf.sequence));
            std::fs::write(&path, sf.encode_to_vec())
                .with_context(|| format!("writing {}", path.display()))?;
        }
        Ok(())
    }

    /// `timings.csv`: per scan, each stage's milliseconds, `occupancy_thread` (the map's update
    /// on its own thread, overlapping the next scans; `occupancy` is handing it over) and the
    /// total of all.
    fn write_timings(&mut self, occupancy: &[(usize, f64)]) -> anyhow::Result<()> {
        let Some((_, first)) = self.frame_timings.first() else {
            return Ok(());
        };
        let stages: Vec<&str> = first.stages.iter().map(|(name, _)| *name).collect();
        writeln!(
            self.timings,
            "frame,{},occupancy_thread,total",
            stages.join(",")
        )?;
        let mut occupancy = occupancy.iter().peekable();
        for (index, timings) in &self.frame_timings {
            let mut line = index.to_string();
            for name in &stages {
                let ms = timings
                    .stages
                    .iter()
                    .find(|(n, _)| n == name)
                    .map_or(0.0, |(_, ms)| *ms);
                line.push_str(&format!(",{ms:.3}"));
            }
            let thread_ms = occupancy
                .next_if(|(i, _)| i == index)
                .map_or(0.0, |(_, ms)| *ms);
            let total = timings.total_ms() + thread_ms;
            writeln!(self.timings, "{line},{thread_ms:.3},{total:.3}")?;
        }
        Ok(())
    }

    /// Flushes the per-frame files and writes the timings, the ego poses (one per scan of the
    /// `scans` read), the occupancy map and the KITTI results; `occupancy_timings` are the
    /// occupancy thread's per scan.
    fn finish(
        mut self,
        scans: usize,
        occupancy: &OccupancyMap,
        occupancy_timings: &[(usize, f64)],
        source: &Source,
    ) -> anyhow::Result<()> {
        self.tracks.flush()?;
        self.write_timings(occupancy_timings)?;
        self.timings.flush()?;
        if let Some(clusters) = &mut self.clusters {
            clusters.0.flush()?;
        }
        let poses = self.dir.join("ego_poses.txt");
        self.ego_poses.resize(scans, None);
        write_poses(&poses, &one_pose_per_scan(&self.ego_poses))
            .with_context(|| format!("writing {}", poses.display()))?;
        let bt = self.dir.join("occupancy.bt");
        std::fs::write(&bt, occupancy.to_bt())
            .with_context(|| format!("writing {}", bt.display()))?;
        if let Some(labels) = &self.kitti {
            let dir = self.dir.join("kitti");
            std::fs::create_dir_all(&dir)?;
            let path = dir.join(format!("{}.txt", source.name()));
            write_tracking_results(&path, labels)
                .with_context(|| format!("writing {}", path.display()))?;
        }
        Ok(())
    }
}

/// A track's box in the Velodyne frame of its scan.
struct SensorRow {
    center: Vector3<f64>,
    yaw: f64,
}

impl SensorRow {
    fn new(track: &TrackState, to_sensor: &Isometry3<f64>) -> Self {
        let center = (to_sensor * Point3::from(track.center)).coords;
        let heading = to_sensor.rotation * Vector3::new(track.yaw.cos(), track.yaw.sin(), 0.0);
        Self {
            center,
            yaw: heading.y.atan2(heading.x),
        }
    }

    fn is_finite(&self) -> bool {
        self.center.iter().all(|v| v.is_finite()) && self.yaw.is_finite()
    }
}

/// A track as a KITTI tracking result in the rectified camera frame, `None` when its centre
/// is behind the camera.
fn kitti_label(
    frame: usize,
    track: &TrackState,
    row: &SensorRow,
    camera: &RectifiedCamera,
) -> Option<KittiLabel> {
    let (l, w, h) = (track.size.x, track.size.y, track.size.z);
    let object_type = match track.class {
        ObjectClass::Car => "Car",
        ObjectClass::Cyclist => "Cyclist",
        ObjectClass::Pedestrian => "Pedestrian",
        ObjectClass::OtherMovable | ObjectClass::Unknown => "Misc",
    };
    let bottom = camera.velo_to_cam(&(row.center - Vector3::new(0.0, 0.0, h / 2.0)));
    if bottom.z <= 0.0 {
        return None;
    }
    // Heading in the camera frame: KITTI's rotation_y turns the object's x axis about -y.
    let origin = camera.velo_to_cam(&Vector3::zeros());
    let ahead = camera.velo_to_cam(&Vector3::new(row.yaw.cos(), row.yaw.sin(), 0.0)) - origin;
    let rotation_y = (-ahead.z).atan2(ahead.x);
    let alpha = wrap(rotation_y - bottom.x.atan2(bottom.z));
    let (c, s) = (row.yaw.cos(), row.yaw.sin());
    let mut bbox = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
    for (a, b, z) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)]
        .into_iter()
        .flat_map(|(a, b)| [(a, b, -1.0), (a, b, 1.0)])
    {
        let corner = row.center
            + Vector3::new(
                c * a * l / 2.0 - s * b * w / 2.0,
                s * a * l / 2.0 + c * b * w / 2.0,
                z * h / 2.0,
            );
        if let Some([u, v]) = camera.project(&camera.velo_to_cam(&corner)) {
            bbox = [
                bbox[0].min(u),
                bbox[1].min(v),
                bbox[2].max(u),
                bbox[3].max(v),
            ];
        }
    }
    if bbox[0] > bbox[2] {
        return None;
    }
    let bbox = [
        bbox[0].clamp(0.0, 1241.0),
        bbox[1].clamp(0.0, 374.0),
        bbox[2].clamp(0.0, 1241.0),
        bbox[3].clamp(0.0, 374.0),
    ];
    Some(KittiLabel {
        frame,
        track_id: track.id as i64,
        object_type: object_type.to_string(),
        truncated: 0.0,
        occluded: 0,
        alpha,
        bbox,
        h,
        w,
        l,
        x: bottom.x,
        y: bottom.y,
        z: bottom.z,
        rotation_y: wrap(rotation_y),
        score: Some(f64::from(track.confidence)),
    })
}

/// An angle wrapped into (−π, π].
fn wrap(a: f64) -> f64 {
    trackd_perception::track::motion::wrap_angle(a)
}

/// One pose per scan for `ego_poses.txt`, so that line `i` is scan `i`: a scan skipped (no
/// GPS fix yet) takes the pose of the nearest processed scan before it, or after it for the
/// scans before the first fix. Empty when no scan was processed.
fn one_pose_per_scan(poses: &[Option<Isometry3<f64>>]) -> Vec<Isometry3<f64>> {
    let Some(first) = poses.iter().flatten().next() else {
        return Vec::new();
    };
    let mut last = *first;
    poses
        .iter()
        .map(|p| {
            if let Some(p) = p {
                last = *p;
            }
            last
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use nalgebra::Translation3;

    use super::*;

    #[test]
    fn skipped_scans_keep_one_pose_line_each() {
        let at = |x: f64| Isometry3::from_parts(Translation3::new(x, 0.0, 0.0), Default::default());
        let poses = [None, None, Some(at(2.0)), None, Some(at(4.0))];
        let xs: Vec<f64> = one_pose_per_scan(&poses)
            .iter()
            .map(|p| p.translation.x)
            .collect();
        assert_eq!(xs, [2.0, 2.0, 2.0, 2.0, 4.0]);
        assert!(one_pose_per_scan(&[None, None]).is_empty());
    }
}
