//! `trackd info PATH`: tells what a path holds — its layout, frames, points per frame, dropped
//! points, whether OXTS, poses, calibration and ground truth are there (and how much).

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Context as _;
use serde::Serialize;
use trackd_dataset::{OpenOptions, Source, labels::read_label_02, tracklets::read_tracklets};

/// Flags of `trackd info`.
#[derive(clap::Args)]
pub struct Args {
    /// A KITTI raw drive (or its date folder), a KITTI tracking or odometry folder, a folder of
    /// .pcd or .bin scans, or one scan file.
    pub path: PathBuf,
    /// Sequence or drive to look at when the folder holds several (`0000`, `0001`).
    #[arg(long)]
    pub seq: Option<String>,
    /// Poses file (KITTI odometry format) to use instead of the source's own.
    #[arg(long)]
    pub poses: Option<PathBuf>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Runs `trackd info`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let opts = OpenOptions {
        seq: args.seq,
        poses: args.poses,
    };
    let info = inspect(&args.path, &opts)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&info)?);
    } else {
        print!("{}", render(&info));
    }
    Ok(())
}

/// What `trackd info` reports.
#[derive(Debug, Serialize)]
pub struct Info {
    /// The folder or file read (after choosing the sequence).
    pub path: PathBuf,
    /// Layout (`kitti_raw`, `kitti_tracking`, `kitti_odometry`, `pcd_folder`, `bin_folder`,
    /// `single_file`).
    pub kind: &'static str,
    /// Sequence, drive or folder name.
    pub name: String,
    /// Number of scans.
    pub frames: usize,
    /// Points stored per scan file (`None` without scans).
    pub points_per_frame: Option<PointStats>,
    /// All-zero or NaN points dropped, over all scans.
    pub dropped_points: usize,
    /// Scans with at least one dropped point.
    pub frames_with_dropped_points: usize,
    /// First and last timestamp (seconds) and the median frame rate (Hz).
    pub time: Option<TimeSpan>,
    /// OXTS packets present.
    pub oxts: bool,
    /// Poses present.
    pub poses: bool,
    /// IMU -> Velodyne calibration present.
    pub imu_to_velo: bool,
    /// Camera calibration present (to write KITTI camera-frame results).
    pub camera_calib: bool,
    /// Ground truth, when present.
    pub labels: Option<LabelSummary>,
    /// Remarks about missing parts or choices made.
    pub notes: Vec<String>,
}

/// Minimum, median and maximum of points per scan.
#[derive(Debug, Serialize, PartialEq, Eq)]
pub struct PointStats {
    /// Fewest points in a scan.
    pub min: usize,
    /// Median over scans.
    pub median: usize,
    /// Most points in a scan.
    pub max: usize,
}

/// The time a source spans.
#[derive(Debug, Serialize)]
pub struct TimeSpan {
    /// First timestamp (seconds).
    pub first: f64,
    /// Last timestamp (seconds).
    pub last: f64,
    /// 1 / median time between frames (Hz).
    pub rate_hz: Option<f64>,
}

/// How much ground truth a labels file holds.
#[derive(Debug, Serialize)]
pub struct LabelSummary {
    /// The file.
    pub path: PathBuf,
    /// `kitti_label_02`, `kitti_tracklets` or `gt_tracks_csv`.
    pub format: &'static str,
    /// Object boxes (one per object and frame; `DontCare` regions not counted).
    pub boxes: usize,
    /// Distinct objects (track ids or tracklets).
    pub tracks: usize,
    /// Distinct frames with at least one box.
    pub frames: usize,
    /// `DontCare` regions (label_02 only).
    pub dont_care: usize,
    /// Tracks per class.
    pub classes: BTreeMap<String, usize>,
}

/// Opens `path`, reads every scan and summarises it.
pub fn inspect(path: &Path, opts: &OpenOptions) -> anyhow::Result<Info> {
    let source = trackd_dataset::open(path, opts)?;
    let mut counts = Vec::with_capacity(source.len());
    let (mut dropped, mut frames_with_dropped) = (0, 0);
    for i in 0..source.len() {
        let (_, stats) = source.frame_with_stats(i)?;
        counts.push(stats.points_in_file);
        dropped += stats.dropped;
        frames_with_dropped += usize::from(stats.dropped > 0);
    }
    let labels = match source.labels_path() {
        Some(p) => {
            Some(summarize_labels(p).with_context(|| format!("reading labels {}", p.display()))?)
        }
        None => None,
    };
    Ok(Info {
        path: source.path().to_path_buf(),
        kind: source.kind().as_str(),
        name: source.name().to_string(),
        frames: source.len(),
        points_per_frame: point_stats(&mut counts),
        dropped_points: dropped,
        frames_with_dropped_points: frames_with_dropped,
        time: time_span(&source)?,
        oxts: source.has_oxts(),
        poses: source.has_poses(),
        imu_to_velo: source.imu_to_velo().is_some(),
        camera_calib: source.calib().is_some(),
        labels,
        notes: source.notes().to_vec(),
    })
}

fn point_stats(counts: &mut [usize]) -> Option<PointStats> {
    counts.sort_unstable();
    Some(PointStats {
        min: *counts.first()?,
        median: counts[counts.len() / 2],
        max: *counts.last()?,
    })
}

fn time_span(source: &Source) -> anyhow::Result<Option<TimeSpan>> {
    let times = (0..source.len())
        .map(|i| source.timestamp(i))
        .collect::<Result<Vec<f64>, _>>()?;
    let (Some(&first), Some(&last)) = (times.first(), times.last()) else {
        return Ok(None);
    };
    let mut steps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(f64::total_cmp);
    let rate_hz = steps
        .get(steps.len() / 2)
        .filter(|&&d| d > 0.0)
        .map(|d| 1.0 / d);
    Ok(Some(TimeSpan {
        first,
        last,
        rate_hz,
    }))
}

/// Counts what a labels file holds, by its format.
fn summarize_labels(path: &Path) -> anyhow::Result<LabelSummary> {
    let file = path
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or_default();
    let mut summary = LabelSummary {
        path: path.to_path_buf(),
        format: "",
        boxes: 0,
        tracks: 0,
        frames: 0,
        dont_care: 0,
        classes: BTreeMap::new(),
    };
    let mut frames = BTreeSet::new();
    let mut tracks = BTreeSet::new();
    if file == trackd_dataset::source::TRACKLETS_FILE {
        summary.format = "kitti_tracklets";
        for (id, t) in read_tracklets(path)?.iter().enumerate() {
            frames.extend(t.first_frame..t.end_frame());
            summary.boxes += t.poses.len();
            tracks.insert((t.object_type.clone(), id as i64));
        }
    } else if file == trackd_dataset::source::GT_TRACKS_FILE {
        summary.format = "gt_tracks_csv";
        let text = std::fs::read_to_string(path)?;
        for (n, line) in text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty())
        {
            let cols: Vec<&str> = line.split(',').map(str::trim).collect();
            if n == 0 && cols.first() == Some(&"frame") {
                continue;
            }
            let bad = || anyhow::anyhow!("{}:{}: expected frame,id,class,…", path.display(), n + 1);
            let (frame, id) = (cols.first().ok_or_else(bad)?, cols.get(1).ok_or_else(bad)?);
            let frame: usize = frame.parse().map_err(|_| bad())?;
            let id: i64 = id.parse().map_err(|_| bad())?;
            frames.insert(frame);
            summary.boxes += 1;
            tracks.insert((cols.get(2).unwrap_or(&"").to_string(), id));
        }
    } else {
        summary.format = "kitti_label_02";
        for l in read_label_02(path)? {
            if l.is_dont_care() {
                summary.dont_care += 1;
                continue;
            }
            frames.insert(l.frame);
            summary.boxes += 1;
            tracks.insert((l.object_type.clone(), l.track_id));
        }
    }
    summary.frames = frames.len();
    summary.tracks = tracks.len();
    for (class, _) in &tracks {
        *summary.classes.entry(class.clone()).or_default() += 1;
    }
    Ok(summary)
}

fn yes(b: bool) -> &'static str {
    if b { "yes" } else { "no" }
}

/// The text report.
fn render(info: &Info) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "path:        {}", info.path.display());
    let _ = writeln!(s, "kind:        {}", info.kind);
    let _ = writeln!(s, "name:        {}", info.name);
    let _ = writeln!(s, "frames:      {}", info.frames);
    match &info.points_per_frame {
        Some(p) => {
            let _ = writeln!(
                s,
                "points:      min {} / median {} / max {} per frame",
                p.min, p.median, p.max
            );
        }
        None => {
            let _ = writeln!(s, "points:      no point clouds here");
        }
    }
    let _ = writeln!(
        s,
        "dropped:     {} zero/NaN points in {} frames",
        info.dropped_points, info.frames_with_dropped_points
    );
    if let Some(t) = &info.time {
        let rate = t.rate_hz.map_or_else(|| "?".into(), |r| format!("{r:.1}"));
        let _ = writeln!(
            s,
            "time:        {:.3} .. {:.3} s ({rate} Hz)",
            t.first, t.last
        );
    }
    let _ = writeln!(s, "oxts:        {}", yes(info.oxts));
    let _ = writeln!(s, "poses:       {}", yes(info.poses));
    let _ = writeln!(
        s,
        "calibration: imu_to_velo {}, camera {}",
        yes(info.imu_to_velo),
        yes(info.camera_calib)
    );
    match &info.labels {
        Some(l) => {
            let classes: Vec<String> = l.classes.iter().map(|(c, n)| format!("{c} {n}")).collect();
            let _ = writeln!(
                s,
                "labels:      {} ({}): {} boxes, {} tracks, {} frames{}",
                l.path.display(),
                l.format,
                l.boxes,
                l.tracks,
                l.frames,
                if l.dont_care > 0 {
                    format!(", {} DontCare", l.dont_care)
                } else {
                    String::new()
                }
            );
            let _ = writeln!(s, "             tracks by class: {}", classes.join(", "));
        }
        None => {
            let _ = writeln!(s, "labels:      none");
        }
    }
    for note in &info.notes {
        let _ = writeln!(s, "note:        {note}");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use trackd_dataset::shared_data_dir;

    fn info(path: &Path) -> Info {
        inspect(path, &OpenOptions::default()).unwrap()
    }

    #[test]
    fn kitti_raw_22_is_a_pcd_folder() {
        let Some(data) = shared_data_dir("info::kitti_raw_22_is_a_pcd_folder") else {
            return;
        };
        let i = info(&data.join("kitti-raw-22"));
        assert_eq!((i.kind, i.frames), ("pcd_folder", 22));
        let p = i.points_per_frame.as_ref().unwrap();
        assert!(
            p.min >= 114_000 && p.max <= 121_500 && p.min <= p.median && p.median <= p.max,
            "{p:?}"
        );
        assert!(
            i.dropped_points >= i.frames_with_dropped_points && i.frames_with_dropped_points > 0
        );
        assert!(!i.oxts && !i.poses && i.labels.is_none());
        assert!((i.time.as_ref().unwrap().rate_hz.unwrap() - 10.0).abs() < 1e-6);
        let text = render(&i);
        assert!(
            text.contains("kind:        pcd_folder") && text.contains("frames:      22"),
            "{text}"
        );
    }

    #[test]
    fn kitti_odometry_00_is_a_bin_folder() {
        let Some(data) = shared_data_dir("info::kitti_odometry_00_is_a_bin_folder") else {
            return;
        };
        let i = info(&data.join("kitti-odometry-00"));
        assert_eq!((i.kind, i.frames), ("bin_folder", 6));
        let p = i.points_per_frame.unwrap();
        assert!(p.min > 120_000 && p.max < 130_000, "{p:?}");
    }

    #[test]
    fn tracking_folder_at_both_levels_has_labels_and_poses() {
        let Some(data) = shared_data_dir("info::tracking_folder_at_both_levels") else {
            return;
        };
        let root = data.join("kitti-tracking-0000-first40");
        for path in [root.clone(), root.join("training")] {
            let i = info(&path);
            assert_eq!(
                (i.kind, i.name.as_str(), i.frames),
                ("kitti_tracking", "0000", 40)
            );
            assert!(i.poses && !i.oxts && i.imu_to_velo && i.camera_calib);
            let l = i.labels.unwrap();
            // Frames 0-39 of sequence 0000: vans 0 and 3, cyclist 1, pedestrian 2.
            assert_eq!(
                (l.format, l.boxes, l.dont_care, l.tracks, l.frames),
                ("kitti_label_02", 121, 64, 4, 40)
            );
            assert_eq!(l.classes.get("Van"), Some(&2));
            assert!(i.points_per_frame.unwrap().min > 100_000);
        }
        let json: serde_json::Value = serde_json::to_value(info(&root)).unwrap();
        assert_eq!(json["kind"], "kitti_tracking");
        assert_eq!(json["labels"]["tracks"], 4);
    }

    #[test]
    fn raw_drive_without_point_clouds_is_reported_not_failed() {
        let Some(data) = shared_data_dir("info::raw_drive_without_point_clouds") else {
            return;
        };
        let date = data.join("kitti-format-samples/raw/2011_09_26");
        for path in [date.join("2011_09_26_drive_0001_sync"), date.clone()] {
            let i = info(&path);
            assert_eq!((i.kind, i.frames), ("kitti_raw", 0));
            assert!(i.points_per_frame.is_none() && i.oxts && i.imu_to_velo && i.camera_calib);
            let l = i.labels.as_ref().unwrap();
            assert_eq!((l.format, l.tracks, l.frames), ("kitti_tracklets", 15, 108));
            let text = render(&i);
            assert!(
                text.contains("no point clouds here") && text.contains("note:"),
                "{text}"
            );
        }
    }

    #[test]
    fn tracking_labels_sample_and_ambiguous_roots() {
        let Some(data) = shared_data_dir("info::tracking_labels_sample") else {
            return;
        };
        let i = info(&data.join("kitti-format-samples/tracking"));
        assert_eq!(
            (i.kind, i.name.as_str(), i.frames),
            ("kitti_tracking", "0001", 0)
        );
        let l = i.labels.unwrap();
        // 447 frames have a line, 426 an object (not only DontCare regions).
        assert_eq!((l.frames, l.tracks), (426, 98));
        for path in [data.clone(), data.join("kitti-format-samples")] {
            let err = inspect(&path, &OpenOptions::default()).unwrap_err();
            assert!(err.to_string().contains("no scans found"), "{err}");
        }
    }

    #[test]
    fn gt_tracks_csv_is_counted() {
        let dir = tempfile::tempdir().unwrap();
        let scans = dir.path().join("drive");
        std::fs::create_dir(&scans).unwrap();
        let points = [trackd_perception::Point::new(1.0, 2.0, 3.0, 0.0)];
        trackd_dataset::bin::write_bin(&scans.join("000000.bin"), &points).unwrap();
        std::fs::write(
            scans.join("gt_tracks.csv"),
            "frame,id,class,x,y,z,l,w,h,yaw,vx,vy,npoints\n0,7,Car,1,2,0,4,2,1.5,0,0,0,40\n1,7,Car,1,2,0,4,2,1.5,0,0,0,38\n1,9,Pedestrian,5,1,0,1,1,2,0,1,0,12\n",
        )
        .unwrap();
        let l = info(&scans).labels.unwrap();
        assert_eq!(
            (l.format, l.boxes, l.tracks, l.frames),
            ("gt_tracks_csv", 3, 2, 2)
        );
        std::fs::write(scans.join("gt_tracks.csv"), "frame,id\n0,seven\n").unwrap();
        let err = inspect(&scans, &OpenOptions::default()).unwrap_err();
        assert!(format!("{err:#}").contains("gt_tracks.csv:2"), "{err:#}");
    }
}
