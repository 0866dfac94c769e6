//! One recorded drive, whatever its layout: the abstraction every offline command reads scans
//! through. [`open`] tells the layout from the folder; [`Source::frame`] reads one scan with its
//! timestamp and what is known of the ego pose.
//!
//! Layouts recognised (a folder may be given at any of the levels shown):
//! - KITTI raw: `<date>/<date>_drive_<n>_sync/` with `velodyne_points/data/*.bin`,
//!   `velodyne_points/timestamps.txt`, `oxts/data/*.txt`, `tracklet_labels.xml`; calibration in
//!   `<date>/calib_*.txt`.
//! - KITTI tracking: `[<root>/]training|testing/` with `velodyne/<seq>/*.bin`, `calib/<seq>.txt`,
//!   `oxts/<seq>.txt`, `label_02/<seq>.txt`, `poses/<seq>.txt`.
//! - KITTI odometry: `[<root>/sequences/]<nn>/` with `velodyne/*.bin`, `calib.txt`, `times.txt`;
//!   poses in `<root>/poses/<nn>.txt`.
//! - A plain folder of `.pcd` or `.bin` scans (sorted by name; `timestamps.txt` in KITTI format
//!   or `times.txt` in seconds if present, else 10 Hz), or a single scan file.

use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, Matrix4};
use trackd_perception::{Ego, Frame, oxts::Oxts};

use crate::calib::{RectifiedCamera, read_raw_calib, read_tracking_calib};
use crate::clean::drop_invalid;
use crate::error::{DatasetError, parse_f64, read_text};
use crate::oxts::{read_oxts, read_oxts_lines};
use crate::poses::{read_pose_matrices, velodyne_poses};
use crate::scan::{ScanFormat, read_scan};
use crate::timestamps::read_timestamps;

/// Seconds between frames when a source gives no timestamps (KITTI's 10 Hz).
pub const DEFAULT_FRAME_PERIOD: f64 = 0.1;

/// Ground truth file names looked for beside the scans (besides KITTI's own).
pub const GT_TRACKS_FILE: &str = "gt_tracks.csv";
/// KITTI raw ground truth.
pub const TRACKLETS_FILE: &str = "tracklet_labels.xml";

/// What layout a source was read from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SourceKind {
    /// A KITTI raw drive (`<date>_drive_<n>_sync`).
    KittiRaw,
    /// A KITTI tracking sequence.
    KittiTracking,
    /// A KITTI odometry sequence.
    KittiOdometry,
    /// A plain folder of `.pcd` scans.
    PcdFolder,
    /// A plain folder of `.bin` scans.
    BinFolder,
    /// One scan file.
    SingleFile,
}

impl SourceKind {
    /// A lower-case name for output and JSON (`kitti_raw`, `pcd_folder`, …).
    pub fn as_str(&self) -> &'static str {
        match self {
            Self::KittiRaw => "kitti_raw",
            Self::KittiTracking => "kitti_tracking",
            Self::KittiOdometry => "kitti_odometry",
            Self::PcdFolder => "pcd_folder",
            Self::BinFolder => "bin_folder",
            Self::SingleFile => "single_file",
        }
    }
}

/// Choices [`open`] cannot make alone.
#[derive(Clone, Debug, Default)]
pub struct OpenOptions {
    /// Which sequence or drive, when the folder holds several: a tracking or odometry sequence
    /// (`0000`, or `0` for short) or a raw drive (`0001`, or its folder name).
    pub seq: Option<String>,
    /// A poses file in KITTI odometry format to use as ego poses instead of what the source
    /// holds. Camera poses are turned into Velodyne poses with the source's calibration when
    /// it has one; without calibration they are taken as Velodyne poses.
    pub poses: Option<PathBuf>,
}

/// Per-scan counts of [`Source::frame_with_stats`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ScanStats {
    /// Points stored in the file.
    pub points_in_file: usize,
    /// Of those, all-zero or non-finite points dropped.
    pub dropped: usize,
}

/// How the ego pose of one frame is had.
#[derive(Clone, Debug)]
enum EgoEntry {
    None,
    /// A raw drive's per-frame OXTS file, read with the scan.
    OxtsFile(PathBuf),
    Oxts(Oxts),
    Pose(Isometry3<f64>),
}

/// One frame: where its scan is and what goes with it.
#[derive(Clone, Debug)]
struct FrameEntry {
    scan: PathBuf,
    /// Frame number in the recording (from the file name when numeric).
    id: usize,
    timestamp: f64,
    ego: EgoEntry,
}

/// A recorded drive opened by [`open`].
#[derive(Clone, Debug)]
pub struct Source {
    kind: SourceKind,
    name: String,
    path: PathBuf,
    frames: Vec<FrameEntry>,
    imu_to_velo: Option<Isometry3<f64>>,
    camera: Option<RectifiedCamera>,
    labels_path: Option<PathBuf>,
    has_oxts: bool,
    has_poses: bool,
    notes: Vec<String>,
}

impl Source {
    /// The layout.
    pub fn kind(&self) -> SourceKind {
        self.kind
    }

    /// A short name: the sequence (`0000`), the drive folder, the folder or the file stem.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The folder (or file) the source was read from, after resolving `--seq`.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Number of frames (scans).
    pub fn len(&self) -> usize {
        self.frames.len()
    }

    /// Whether there is no scan (e.g. a raw drive shipped without its point clouds).
    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    /// Frame `i` with its points (Velodyne frame; zero and NaN points dropped), timestamp
    /// (seconds) and ego pose (OXTS packet, or Velodyne pose in the Velodyne frame of the first
    /// pose).
    pub fn frame(&self, i: usize) -> Result<Frame, DatasetError> {
        self.frame_with_stats(i).map(|(frame, _)| frame)
    }

    /// [`Self::frame`] and how many points the file held and how many were dropped.
    pub fn frame_with_stats(&self, i: usize) -> Result<(Frame, ScanStats), DatasetError> {
        let entry = self.entry(i)?;
        let mut points = read_scan(&entry.scan)?;
        let points_in_file = points.len();
        let dropped = drop_invalid(&mut points);
        let ego = match &entry.ego {
            EgoEntry::None => Ego::None,
            EgoEntry::OxtsFile(path) => Ego::Oxts(read_oxts(path)?),
            EgoEntry::Oxts(o) => Ego::Oxts(*o),
            EgoEntry::Pose(p) => Ego::Pose(*p),
        };
        let frame = Frame {
            timestamp: entry.timestamp,
            points,
            ego,
        };
        Ok((
            frame,
            ScanStats {
                points_in_file,
                dropped,
            },
        ))
    }

    /// All frames in order.
    pub fn frames(&self) -> impl Iterator<Item = Result<Frame, DatasetError>> + '_ {
        (0..self.len()).map(|i| self.frame(i))
    }

    /// Frame number of frame `i` in the recording: the number in its file name
    /// (`000042.bin` -> 42), else `i`. Labels and KITTI results use these numbers.
    pub fn frame_id(&self, i: usize) -> Result<usize, DatasetError> {
        Ok(self.entry(i)?.id)
    }

    /// Timestamp of frame `i` (seconds) without reading its scan.
    pub fn timestamp(&self, i: usize) -> Result<f64, DatasetError> {
        Ok(self.entry(i)?.timestamp)
    }

    /// The scan file of frame `i`.
    pub fn scan_path(&self, i: usize) -> Result<&Path, DatasetError> {
        Ok(&self.entry(i)?.scan)
    }

    /// IMU -> Velodyne calibration (raw drives; tracking calib's `Tr_imu_to_velo`).
    pub fn imu_to_velo(&self) -> Option<Isometry3<f64>> {
        self.imu_to_velo
    }

    /// Velodyne -> rectified camera and `P2`, to write KITTI camera-frame results.
    pub fn calib(&self) -> Option<&RectifiedCamera> {
        self.camera.as_ref()
    }

    /// The ground truth beside the scans: `label_02/<seq>.txt`, `tracklet_labels.xml` or
    /// `gt_tracks.csv`.
    pub fn labels_path(&self) -> Option<&Path> {
        self.labels_path.as_deref()
    }

    /// Whether OXTS packets are present (raw drives' `oxts/data`, tracking `oxts/<seq>.txt`).
    pub fn has_oxts(&self) -> bool {
        self.has_oxts
    }

    /// Whether poses are present (odometry or tracking `poses/<seq>.txt`, or given).
    pub fn has_poses(&self) -> bool {
        self.has_poses
    }

    /// Things a user should know that are not errors (missing parts, choices made).
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    fn entry(&self, i: usize) -> Result<&FrameEntry, DatasetError> {
        self.frames.get(i).ok_or(DatasetError::FrameOutOfRange {
            index: i,
            len: self.frames.len(),
        })
    }
}

/// Opens `path` (a folder of any recognised layout, or one scan file) and lists its frames.
/// Only small text files (timestamps, poses, calibration, tracking OXTS) are read here; scans
/// are read by [`Source::frame`].
pub fn open(path: &Path, opts: &OpenOptions) -> Result<Source, DatasetError> {
    if path.is_file() {
        return open_single_file(path, opts);
    }
    if !path.is_dir() {
        return Err(DatasetError::io(
            path,
            std::io::Error::new(std::io::ErrorKind::NotFound, "no such file or folder"),
        ));
    }
    if path.join("velodyne_points").is_dir() || path.join("oxts").join("data").is_dir() {
        return open_raw_drive(path, opts);
    }
    let drives = raw_drives(path)?;
    if !drives.is_empty() {
        let names: Vec<String> = drives.iter().map(|d| file_name(d)).collect();
        let drive = pick(path, &names, opts.seq.as_deref(), "drive")?;
        let at = names.iter().position(|n| *n == drive).unwrap_or(0);
        return open_raw_drive(&drives[at], opts);
    }
    let velodyne = path.join("velodyne");
    if velodyne.is_dir() && subdirs(&velodyne)?.is_empty() {
        return open_odometry(path, opts);
    }
    if is_tracking_split(path) {
        return open_tracking(path, opts);
    }
    for split in ["training", "testing"] {
        if is_tracking_split(&path.join(split)) {
            return open_tracking(&path.join(split), opts);
        }
    }
    let sequences = if path.join("sequences").is_dir() {
        path.join("sequences")
    } else {
        path.to_path_buf()
    };
    let odometry: Vec<String> = subdirs(&sequences)?
        .into_iter()
        .filter(|s| {
            let velodyne = sequences.join(s).join("velodyne");
            velodyne.is_dir() && subdirs(&velodyne).is_ok_and(|d| d.is_empty())
        })
        .collect();
    if !odometry.is_empty() {
        let seq = pick(&sequences, &odometry, opts.seq.as_deref(), "sequence")?;
        return open_odometry(&sequences.join(seq), opts);
    }
    let scans = scan_files(path)?;
    let pcd = scans
        .iter()
        .filter(|p| ScanFormat::of(p) == Some(ScanFormat::Pcd))
        .count();
    match (pcd, scans.len() - pcd) {
        (0, 0) => Err(DatasetError::layout(
            path,
            "no scans found: expected a KITTI raw drive or date folder, a KITTI tracking or odometry \
             folder, or a folder of .pcd or .bin files",
        )),
        (_, 0) => open_folder(path, scans, SourceKind::PcdFolder, opts),
        (0, _) => open_folder(path, scans, SourceKind::BinFolder, opts),
        (p, b) => Err(DatasetError::layout(
            path,
            format!("holds both .pcd ({p}) and .bin ({b}) scans: give one file or split them"),
        )),
    }
}

fn open_single_file(path: &Path, opts: &OpenOptions) -> Result<Source, DatasetError> {
    if ScanFormat::of(path).is_none() {
        return Err(DatasetError::format(
            path,
            "not a scan file: expected a .bin or .pcd extension",
        ));
    }
    let mut source = Source::new(SourceKind::SingleFile, stem(path), path);
    source.frames.push(FrameEntry {
        scan: path.to_path_buf(),
        id: file_number(path).unwrap_or(0),
        timestamp: 0.0,
        ego: EgoEntry::None,
    });
    if let Some(poses) = &opts.poses {
        source.set_poses(poses, None)?;
    }
    Ok(source)
}

fn open_raw_drive(drive: &Path, opts: &OpenOptions) -> Result<Source, DatasetError> {
    let mut source = Source::new(SourceKind::KittiRaw, file_name(drive), drive);
    let date_dir = drive.parent().unwrap_or(Path::new("."));
    if date_dir.join(crate::calib::IMU_TO_VELO_FILE).is_file() {
        let calib = read_raw_calib(date_dir)?;
        source.imu_to_velo = Some(calib.imu_to_velo);
        source.camera = Some(calib.rectified_camera());
    } else {
        source.notes.push(format!(
            "no calibration files ({}) in {}",
            crate::calib::IMU_TO_VELO_FILE,
            date_dir.display()
        ));
    }
    let data = drive.join("velodyne_points").join("data");
    let scans = if data.is_dir() {
        scan_files(&data)?
    } else {
        source.notes.push(format!(
            "no velodyne_points/data in {}: this drive has no point clouds here",
            drive.display()
        ));
        Vec::new()
    };
    let stamps_path = drive.join("velodyne_points").join("timestamps.txt");
    let stamps = if stamps_path.is_file() {
        Some(read_timestamps(&stamps_path)?)
    } else {
        None
    };
    let oxts_dir = drive.join("oxts").join("data");
    source.has_oxts = oxts_dir.is_dir()
        && std::fs::read_dir(&oxts_dir)
            .map_err(|e| DatasetError::io(&oxts_dir, e))?
            .next()
            .is_some();
    for (i, scan) in scans.into_iter().enumerate() {
        let id = file_number(&scan).unwrap_or(i);
        let timestamp = match &stamps {
            Some(s) => *s.get(id).ok_or_else(|| {
                DatasetError::layout(
                    &stamps_path,
                    format!("{} timestamps, but there is a scan numbered {id}", s.len()),
                )
            })?,
            None => id as f64 * DEFAULT_FRAME_PERIOD,
        };
        let ego = if source.has_oxts {
            EgoEntry::OxtsFile(oxts_dir.join(format!("{}.txt", stem(&scan))))
        } else {
            EgoEntry::None
        };
        source.frames.push(FrameEntry {
            scan,
            id,
            timestamp,
            ego,
        });
    }
    source.labels_path = [TRACKLETS_FILE, GT_TRACKS_FILE]
        .iter()
        .map(|f| drive.join(f))
        .find(|p| p.is_file());
    if let Some(poses) = &opts.poses {
        let v = source.camera.as_ref().map(|c| c.velo_to_rect_cam);
        source.set_poses(poses, v)?;
    }
    Ok(source)
}

/// Whether `dir` is a KITTI tracking split (`training` or `testing`): sequences in
/// `velodyne/<seq>/`, or (a labels-only sample) `label_02/` or `calib/` files.
fn is_tracking_split(dir: &Path) -> bool {
    let velodyne = dir.join("velodyne");
    if velodyne.is_dir() {
        return subdirs(&velodyne).is_ok_and(|s| !s.is_empty());
    }
    dir.join("label_02").is_dir() || dir.join("calib").is_dir()
}

/// The sequences of a tracking split: `velodyne/<seq>/` folders, else the stems of
/// `label_02/*.txt` and `calib/*.txt`.
fn tracking_sequences(split: &Path) -> Result<Vec<String>, DatasetError> {
    let velodyne = split.join("velodyne");
    if velodyne.is_dir() {
        return subdirs(&velodyne);
    }
    let mut seqs = Vec::new();
    for dir in [split.join("label_02"), split.join("calib")] {
        if dir.is_dir() {
            for entry in std::fs::read_dir(&dir).map_err(|e| DatasetError::io(&dir, e))? {
                let path = entry.map_err(|e| DatasetError::io(&dir, e))?.path();
                if path.extension().is_some_and(|e| e == "txt") {
                    seqs.push(stem(&path));
                }
            }
        }
    }
    seqs.sort();
    seqs.dedup();
    Ok(seqs)
}

/// Raw drive folders (`*_drive_*_sync`) in `dir` (a date folder) or in its date folders (the
/// raw download's root).
fn raw_drives(dir: &Path) -> Result<Vec<PathBuf>, DatasetError> {
    let is_drive = |n: &str| n.contains("_drive_") && n.ends_with("_sync");
    let mut drives: Vec<PathBuf> = subdirs(dir)?
        .into_iter()
        .filter(|n| is_drive(n))
        .map(|n| dir.join(n))
        .collect();
    if drives.is_empty() {
        for date in subdirs(dir)? {
            let date_dir = dir.join(&date);
            drives.extend(
                subdirs(&date_dir)?
                    .into_iter()
                    .filter(|n| is_drive(n))
                    .map(|n| date_dir.join(n)),
            );
        }
    }
    Ok(drives)
}

fn open_tracking(split: &Path, opts: &OpenOptions) -> Result<Source, DatasetError> {
    let velodyne = split.join("velodyne");
    let seq = pick(
        split,
        &tracking_sequences(split)?,
        opts.seq.as_deref(),
        "sequence",
    )?;
    let mut source = Source::new(SourceKind::KittiTracking, seq.clone(), split);
    let calib_path = split.join("calib").join(format!("{seq}.txt"));
    let calib = if calib_path.is_file() {
        Some(read_tracking_calib(&calib_path)?)
    } else {
        source.notes.push(format!("no {}", calib_path.display()));
        None
    };
    source.imu_to_velo = calib.as_ref().and_then(|c| c.imu_to_velo());
    source.camera = calib.as_ref().map(|c| c.rectified_camera());
    let scans = if velodyne.join(&seq).is_dir() {
        scan_files(&velodyne.join(&seq))?
    } else {
        source.notes.push(format!(
            "no velodyne/{seq} in {}: this sequence has no point clouds here",
            split.display()
        ));
        Vec::new()
    };
    for (i, scan) in scans.into_iter().enumerate() {
        let id = file_number(&scan).unwrap_or(i);
        source.frames.push(FrameEntry {
            scan,
            id,
            timestamp: id as f64 * DEFAULT_FRAME_PERIOD,
            ego: EgoEntry::None,
        });
    }
    let oxts_path = split.join("oxts").join(format!("{seq}.txt"));
    let poses_path = opts
        .poses
        .clone()
        .or_else(|| Some(split.join("poses").join(format!("{seq}.txt"))).filter(|p| p.is_file()));
    if oxts_path.is_file() {
        let packets = read_oxts_lines(&oxts_path)?;
        source.has_oxts = true;
        if opts.poses.is_none() {
            for f in &mut source.frames {
                let packet = packets.get(f.id).ok_or_else(|| {
                    DatasetError::layout(
                        &oxts_path,
                        format!(
                            "{} packets, but there is a scan numbered {}",
                            packets.len(),
                            f.id
                        ),
                    )
                })?;
                f.ego = EgoEntry::Oxts(*packet);
            }
            if poses_path.is_some() {
                source.notes.push(
                    "both OXTS and poses present: OXTS used (give --poses to use the poses)".into(),
                );
            }
        }
    }
    if let Some(poses) = poses_path {
        let v = source.camera.as_ref().map(|c| c.velo_to_rect_cam);
        if source.has_oxts && opts.poses.is_none() {
            source.has_poses = true;
        } else {
            source.set_poses(&poses, v)?;
        }
    }
    source.labels_path =
        Some(split.join("label_02").join(format!("{seq}.txt"))).filter(|p| p.is_file());
    Ok(source)
}

fn open_odometry(seq_dir: &Path, opts: &OpenOptions) -> Result<Source, DatasetError> {
    let name = file_name(seq_dir);
    let mut source = Source::new(SourceKind::KittiOdometry, name.clone(), seq_dir);
    let calib_path = seq_dir.join("calib.txt");
    if calib_path.is_file() {
        let calib = read_tracking_calib(&calib_path)?;
        source.camera = Some(calib.rectified_camera());
        source.imu_to_velo = calib.imu_to_velo();
    }
    let times_path = seq_dir.join("times.txt");
    let times = if times_path.is_file() {
        Some(read_seconds(&times_path)?)
    } else {
        None
    };
    for (i, scan) in scan_files(&seq_dir.join("velodyne"))?
        .into_iter()
        .enumerate()
    {
        let id = file_number(&scan).unwrap_or(i);
        let timestamp = match &times {
            Some(t) => *t.get(id).ok_or_else(|| {
                DatasetError::layout(
                    &times_path,
                    format!("{} times, but there is a scan numbered {id}", t.len()),
                )
            })?,
            None => id as f64 * DEFAULT_FRAME_PERIOD,
        };
        source.frames.push(FrameEntry {
            scan,
            id,
            timestamp,
            ego: EgoEntry::None,
        });
    }
    // KITTI odometry keeps poses beside `sequences/`: <root>/poses/<nn>.txt.
    let beside = seq_dir
        .parent()
        .and_then(Path::parent)
        .map(|root| root.join("poses").join(format!("{name}.txt")));
    let poses = opts
        .poses
        .clone()
        .or_else(|| beside.filter(|p| p.is_file()));
    if let Some(poses) = poses {
        let v = source.camera.as_ref().map(|c| c.velo_to_rect_cam);
        if v.is_none() {
            source
                .notes
                .push("no calib.txt: poses taken as Velodyne poses".into());
        }
        source.set_poses(&poses, v)?;
    }
    Ok(source)
}

fn open_folder(
    dir: &Path,
    scans: Vec<PathBuf>,
    kind: SourceKind,
    opts: &OpenOptions,
) -> Result<Source, DatasetError> {
    let mut source = Source::new(kind, file_name(dir), dir);
    let (kitti_stamps, plain_times) = (dir.join("timestamps.txt"), dir.join("times.txt"));
    let (times, times_path) = if kitti_stamps.is_file() {
        (Some(read_timestamps(&kitti_stamps)?), kitti_stamps)
    } else if plain_times.is_file() {
        (Some(read_seconds(&plain_times)?), plain_times)
    } else {
        (None, kitti_stamps)
    };
    if let Some(t) = &times
        && t.len() != scans.len()
    {
        return Err(DatasetError::layout(
            &times_path,
            format!("{} timestamps for {} scans", t.len(), scans.len()),
        ));
    }
    for (i, scan) in scans.into_iter().enumerate() {
        let timestamp = times
            .as_ref()
            .map_or(i as f64 * DEFAULT_FRAME_PERIOD, |t| t[i]);
        source.frames.push(FrameEntry {
            id: file_number(&scan).unwrap_or(i),
            scan,
            timestamp,
            ego: EgoEntry::None,
        });
    }
    let calib_path = dir.join("calib.txt");
    if calib_path.is_file() {
        let calib = read_tracking_calib(&calib_path)?;
        source.camera = Some(calib.rectified_camera());
        source.imu_to_velo = calib.imu_to_velo();
    }
    source.labels_path = [TRACKLETS_FILE, GT_TRACKS_FILE]
        .iter()
        .map(|f| dir.join(f))
        .find(|p| p.is_file());
    if let Some(poses) = &opts.poses {
        let v = source.camera.as_ref().map(|c| c.velo_to_rect_cam);
        source.set_poses(poses, v)?;
    }
    Ok(source)
}

impl Source {
    fn new(kind: SourceKind, name: String, path: &Path) -> Self {
        Self {
            kind,
            name,
            path: path.to_path_buf(),
            frames: Vec::new(),
            imu_to_velo: None,
            camera: None,
            labels_path: None,
            has_oxts: false,
            has_poses: false,
            notes: Vec::new(),
        }
    }

    /// Uses the poses of `path` (KITTI odometry format) as every frame's ego: camera poses
    /// turned into Velodyne poses with `velo_to_cam` when given. Pose line = frame number.
    fn set_poses(
        &mut self,
        path: &Path,
        velo_to_cam: Option<Matrix4<f64>>,
    ) -> Result<(), DatasetError> {
        let matrices = read_pose_matrices(path)?;
        let v = velo_to_cam.unwrap_or_else(Matrix4::identity);
        let poses = velodyne_poses(&matrices, &v)
            .ok_or_else(|| DatasetError::format(path, "singular first pose or calibration"))?;
        for f in &mut self.frames {
            let pose = poses.get(f.id).ok_or_else(|| {
                DatasetError::layout(
                    path,
                    format!(
                        "{} poses, but there is a scan numbered {}",
                        poses.len(),
                        f.id
                    ),
                )
            })?;
            f.ego = EgoEntry::Pose(*pose);
        }
        self.has_poses = true;
        Ok(())
    }
}

/// Reads a file of one number (seconds) per line, like odometry's `times.txt`.
fn read_seconds(path: &Path) -> Result<Vec<f64>, DatasetError> {
    let text = read_text(path)?;
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| parse_f64(path, i + 1, "time", l.trim()))
        .collect()
}

/// Chooses one of `names` (sequences or drives in `dir`): the one `wanted` names (exactly, by
/// number, or as a drive number), or the only one.
fn pick(
    dir: &Path,
    names: &[String],
    wanted: Option<&str>,
    what: &str,
) -> Result<String, DatasetError> {
    let list = || names.join(", ");
    match wanted {
        Some(w) => {
            let number = |s: &str| s.parse::<u64>().ok();
            let drive_number = |s: &str| {
                s.split("_drive_")
                    .nth(1)
                    .and_then(|r| r.trim_end_matches("_sync").parse::<u64>().ok())
            };
            names
                .iter()
                .find(|n| n.as_str() == w)
                .or_else(|| {
                    names.iter().find(|n| {
                        number(w).is_some()
                            && (number(n) == number(w) || drive_number(n) == number(w))
                    })
                })
                .cloned()
                .ok_or_else(|| {
                    DatasetError::layout(dir, format!("no {what} {w:?}; there are: {}", list()))
                })
        }
        None => match names {
            [one] => Ok(one.clone()),
            [] => Err(DatasetError::layout(dir, format!("no {what} folder"))),
            _ => Err(DatasetError::layout(
                dir,
                format!(
                    "holds {} {what}s ({}): choose one with --seq",
                    names.len(),
                    list()
                ),
            )),
        },
    }
}

/// Names of the sub-folders of `dir`, sorted.
fn subdirs(dir: &Path) -> Result<Vec<String>, DatasetError> {
    let mut names = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| DatasetError::io(dir, e))? {
        let entry = entry.map_err(|e| DatasetError::io(dir, e))?;
        if entry.path().is_dir() {
            names.push(entry.file_name().to_string_lossy().into_owned());
        }
    }
    names.sort();
    Ok(names)
}

/// The `.bin` and `.pcd` files of `dir`, in frame order: by the number in their names when
/// numeric, then by name.
fn scan_files(dir: &Path) -> Result<Vec<PathBuf>, DatasetError> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| DatasetError::io(dir, e))? {
        let path = entry.map_err(|e| DatasetError::io(dir, e))?.path();
        if path.is_file() && ScanFormat::of(&path).is_some() {
            files.push(path);
        }
    }
    files.sort_by(|a, b| {
        (file_number(a).unwrap_or(usize::MAX), a).cmp(&(file_number(b).unwrap_or(usize::MAX), b))
    });
    Ok(files)
}

/// `000042.bin` -> 42.
fn file_number(path: &Path) -> Option<usize> {
    path.file_stem()?.to_str()?.parse().ok()
}

fn stem(path: &Path) -> String {
    path.file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned())
}

fn file_name(path: &Path) -> String {
    path.canonicalize()
        .ok()
        .as_deref()
        .unwrap_or(path)
        .file_name()
        .map_or_else(
            || path.display().to_string(),
            |s| s.to_string_lossy().into_owned(),
        )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calib::{RawCalib, write_raw_calib};
    use crate::poses::write_poses;
    use crate::shared_data_dir;
    use crate::timestamps::write_timestamps;
    use crate::tracklets::write_tracklets;
    use crate::{bin::write_bin, oxts, pcd::write_pcd_binary};
    use nalgebra::{Translation3, UnitQuaternion};
    use trackd_perception::Point;

    /// A scan of `n` points plus one all-zero and one NaN point.
    fn scan(n: usize, shift: f32) -> Vec<Point> {
        let mut points: Vec<Point> = (0..n)
            .map(|i| Point::new(5.0 + shift + i as f32, 1.0, -1.5, 0.5))
            .collect();
        points.insert(1, Point::new(0.0, 0.0, 0.0, 0.0));
        points.push(Point::new(f32::NAN, 2.0, 3.0, 0.1));
        points
    }

    fn packet(i: usize) -> Oxts {
        Oxts {
            lat: 49.0 + 1e-5 * i as f64,
            lon: 8.4,
            alt: 110.0,
            yaw: 0.5,
            vf: 5.0,
            numsats: 9,
            ..Default::default()
        }
    }

    /// `<root>/2011_09_26/2011_09_26_drive_000<k>_sync` with three frames.
    fn raw_drive(root: &Path, k: usize) -> PathBuf {
        let date = root.join("2011_09_26");
        let drive = date.join(format!("2011_09_26_drive_000{k}_sync"));
        std::fs::create_dir_all(drive.join("velodyne_points/data")).unwrap();
        std::fs::create_dir_all(drive.join("oxts/data")).unwrap();
        write_raw_calib(&date, &RawCalib::kitti_2011_09_26()).unwrap();
        for i in 0..3 {
            write_bin(
                &drive.join(format!("velodyne_points/data/{i:010}.bin")),
                &scan(10 + i, i as f32),
            )
            .unwrap();
            oxts::write_oxts(&drive.join(format!("oxts/data/{i:010}.txt")), &packet(i)).unwrap();
        }
        write_timestamps(
            &drive.join("velodyne_points/timestamps.txt"),
            &[1e9, 1e9 + 0.1, 1e9 + 0.2],
        )
        .unwrap();
        oxts::write_dataformat(&drive.join("oxts/dataformat.txt")).unwrap();
        write_tracklets(&drive.join(TRACKLETS_FILE), &[]).unwrap();
        drive
    }

    fn pose(x: f64) -> Isometry3<f64> {
        Isometry3::from_parts(Translation3::new(0.0, 0.0, x), UnitQuaternion::identity())
    }

    #[test]
    fn raw_drive_frames_have_points_timestamps_and_oxts() {
        let dir = tempfile::tempdir().unwrap();
        let drive = raw_drive(dir.path(), 1);
        for path in [
            drive.clone(),
            dir.path().join("2011_09_26"),
            dir.path().to_path_buf(),
        ] {
            let source = open(&path, &OpenOptions::default()).unwrap();
            assert_eq!(source.kind(), SourceKind::KittiRaw);
            assert_eq!(source.name(), "2011_09_26_drive_0001_sync");
            assert_eq!(source.len(), 3);
        }
        let source = open(&drive, &OpenOptions::default()).unwrap();
        assert!(source.has_oxts() && !source.has_poses());
        assert_eq!(
            source.labels_path(),
            Some(drive.join(TRACKLETS_FILE).as_path())
        );
        assert_eq!(
            source.imu_to_velo(),
            Some(RawCalib::kitti_2011_09_26().imu_to_velo)
        );
        assert!(source.calib().is_some());
        let (frame, stats) = source.frame_with_stats(2).unwrap();
        assert_eq!(
            stats,
            ScanStats {
                points_in_file: 14,
                dropped: 2
            }
        );
        assert_eq!(
            frame.points,
            scan(12, 2.0)
                .into_iter()
                .filter(crate::clean::is_valid)
                .collect::<Vec<_>>()
        );
        assert!((frame.timestamp - (1e9 + 0.2)).abs() < 1e-6);
        match frame.ego {
            Ego::Oxts(o) => assert!((o.lat - packet(2).lat).abs() < 1e-12 && o.numsats == 9),
            other => panic!("{other:?}"),
        }
        assert_eq!(source.frame_id(2).unwrap(), 2);
        assert_eq!(source.frames().count(), 3);
        assert!(matches!(
            source.frame(3),
            Err(DatasetError::FrameOutOfRange { index: 3, len: 3 })
        ));
    }

    #[test]
    fn several_drives_need_a_choice() {
        let dir = tempfile::tempdir().unwrap();
        raw_drive(dir.path(), 1);
        raw_drive(dir.path(), 2);
        let date = dir.path().join("2011_09_26");
        let err = open(&date, &OpenOptions::default()).unwrap_err();
        assert!(
            err.to_string().contains("--seq") && err.to_string().contains("drive_0002"),
            "{err}"
        );
        for seq in ["2", "0002", "2011_09_26_drive_0002_sync"] {
            let source = open(
                &date,
                &OpenOptions {
                    seq: Some(seq.into()),
                    ..Default::default()
                },
            )
            .unwrap();
            assert_eq!(source.name(), "2011_09_26_drive_0002_sync", "{seq}");
        }
        let err = open(
            &date,
            &OpenOptions {
                seq: Some("7".into()),
                ..Default::default()
            },
        )
        .unwrap_err();
        assert!(matches!(err, DatasetError::Layout { .. }), "{err}");
    }

    #[test]
    fn raw_drive_with_a_missing_oxts_file_fails_on_that_frame() {
        let dir = tempfile::tempdir().unwrap();
        let drive = raw_drive(dir.path(), 1);
        std::fs::remove_file(drive.join("oxts/data/0000000001.txt")).unwrap();
        let source = open(&drive, &OpenOptions::default()).unwrap();
        assert!(source.frame(0).is_ok());
        let err = source.frame(1).unwrap_err();
        assert!(
            matches!(err, DatasetError::Io { .. }) && err.to_string().contains("0000000001.txt"),
            "{err}"
        );
    }

    #[test]
    fn raw_timestamps_must_cover_every_scan() {
        let dir = tempfile::tempdir().unwrap();
        let drive = raw_drive(dir.path(), 1);
        write_timestamps(
            &drive.join("velodyne_points/timestamps.txt"),
            &[1e9, 1e9 + 0.1],
        )
        .unwrap();
        let err = open(&drive, &OpenOptions::default()).unwrap_err();
        assert!(
            err.to_string()
                .contains("2 timestamps, but there is a scan numbered 2"),
            "{err}"
        );
    }

    /// `<root>/training` with sequence 0003 of `n` frames, calib, labels, and optionally oxts.
    fn tracking(root: &Path, n: usize, with_oxts: bool) -> PathBuf {
        let split = root.join("training");
        for sub in ["velodyne/0003", "calib", "label_02", "poses", "oxts"] {
            std::fs::create_dir_all(split.join(sub)).unwrap();
        }
        for i in 0..n {
            write_bin(
                &split.join(format!("velodyne/0003/{i:06}.bin")),
                &scan(5, 0.0),
            )
            .unwrap();
        }
        let twelve = "7.215377e+02 0 6.095593e+02 4.485728e+01 0 7.215377e+02 1.728540e+02 2.163791e-01 0 0 1 2.745884e-03";
        let tr = "0 -1 0 0 0 0 -1 -0.08 1 0 0 -0.27";
        let imu = "1 0 0 -0.8 0 1 0 0.3 0 0 1 -0.8";
        std::fs::write(
            split.join("calib/0003.txt"),
            format!("P0: {twelve}\nP1: {twelve}\nP2: {twelve}\nP3: {twelve}\nR0_rect: 1 0 0 0 1 0 0 0 1\nTr_velo_to_cam: {tr}\nTr_imu_to_velo: {imu}\n"),
        )
        .unwrap();
        std::fs::write(split.join("label_02/0003.txt"), "").unwrap();
        write_poses(
            &split.join("poses/0003.txt"),
            &(0..n).map(|i| pose(i as f64)).collect::<Vec<_>>(),
        )
        .unwrap();
        if with_oxts {
            oxts::write_oxts_lines(
                &split.join("oxts/0003.txt"),
                &(0..n).map(packet).collect::<Vec<_>>(),
            )
            .unwrap();
        }
        split
    }

    #[test]
    fn tracking_sequence_uses_poses_as_velodyne_poses() {
        let dir = tempfile::tempdir().unwrap();
        let split = tracking(dir.path(), 4, false);
        for path in [split.clone(), dir.path().to_path_buf()] {
            let source = open(&path, &OpenOptions::default()).unwrap();
            assert_eq!(
                (source.kind(), source.name(), source.len()),
                (SourceKind::KittiTracking, "0003", 4)
            );
        }
        let source = open(
            &split,
            &OpenOptions {
                seq: Some("3".into()),
                ..Default::default()
            },
        )
        .unwrap();
        assert!(source.has_poses() && !source.has_oxts());
        assert_eq!(source.imu_to_velo().unwrap().translation.x, -0.8);
        assert_eq!(
            source.labels_path(),
            Some(split.join("label_02/0003.txt").as_path())
        );
        let frame = source.frame(3).unwrap();
        assert!((frame.timestamp - 0.3).abs() < 1e-12);
        // The camera moves 3 m along its z (forward): the Velodyne 3 m along its x.
        match frame.ego {
            Ego::Pose(p) => assert!(
                (p.translation.vector - nalgebra::Vector3::new(3.0, 0.0, 0.0)).norm() < 1e-6,
                "{p}"
            ),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn tracking_oxts_wins_unless_poses_are_asked_for() {
        let dir = tempfile::tempdir().unwrap();
        let split = tracking(dir.path(), 3, true);
        let source = open(&split, &OpenOptions::default()).unwrap();
        assert!(source.has_oxts() && source.has_poses());
        assert!(!source.notes().is_empty());
        assert!(matches!(source.frame(1).unwrap().ego, Ego::Oxts(o) if o.lat == packet(1).lat));
        let opts = OpenOptions {
            poses: Some(split.join("poses/0003.txt")),
            ..Default::default()
        };
        let source = open(&split, &opts).unwrap();
        assert!(matches!(source.frame(1).unwrap().ego, Ego::Pose(_)));
        // Too few packets or poses for the scans is a layout error naming the file.
        oxts::write_oxts_lines(&split.join("oxts/0003.txt"), &[packet(0)]).unwrap();
        let err = open(&split, &OpenOptions::default()).unwrap_err();
        assert!(
            err.to_string().contains("oxts/0003.txt") && err.to_string().contains("1 packets"),
            "{err}"
        );
        write_poses(&split.join("poses/0003.txt"), &[pose(0.0)]).unwrap();
        assert!(
            open(&split, &opts)
                .unwrap_err()
                .to_string()
                .contains("1 poses")
        );
    }

    #[test]
    fn odometry_sequence_reads_times_calib_and_poses_beside_sequences() {
        let dir = tempfile::tempdir().unwrap();
        let seq = dir.path().join("sequences/07");
        std::fs::create_dir_all(seq.join("velodyne")).unwrap();
        std::fs::create_dir_all(dir.path().join("poses")).unwrap();
        for i in 0..3 {
            write_bin(&seq.join(format!("velodyne/{i:06}.bin")), &scan(3, 0.0)).unwrap();
        }
        let twelve = "1 0 0 0 0 1 0 0 0 0 1 0";
        std::fs::write(seq.join("calib.txt"), format!("P0: {twelve}\nP1: {twelve}\nP2: {twelve}\nP3: {twelve}\nTr: 0 -1 0 0 0 0 -1 0 1 0 0 0\n")).unwrap();
        std::fs::write(seq.join("times.txt"), "0.000000e+00\n1.036e-01\n2.07e-01\n").unwrap();
        write_poses(
            &dir.path().join("poses/07.txt"),
            &[pose(0.0), pose(1.0), pose(2.5)],
        )
        .unwrap();
        for (path, seq_opt) in [
            (seq.clone(), None),
            (dir.path().to_path_buf(), Some("7")),
            (dir.path().join("sequences"), Some("07")),
        ] {
            let source = open(
                &path,
                &OpenOptions {
                    seq: seq_opt.map(String::from),
                    ..Default::default()
                },
            )
            .unwrap();
            assert_eq!(
                (source.kind(), source.name(), source.len()),
                (SourceKind::KittiOdometry, "07", 3)
            );
            assert!(source.has_poses());
        }
        let source = open(&seq, &OpenOptions::default()).unwrap();
        let frame = source.frame(2).unwrap();
        assert_eq!(frame.timestamp, 0.207);
        match frame.ego {
            Ego::Pose(p) => assert!((p.translation.x - 2.5).abs() < 1e-6, "{p}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn plain_folders_and_single_files() {
        let dir = tempfile::tempdir().unwrap();
        let folder = dir.path().join("scans");
        std::fs::create_dir(&folder).unwrap();
        for name in ["b.pcd", "a.pcd", "c.pcd"] {
            write_pcd_binary(&folder.join(name), &scan(4, 0.0)).unwrap();
        }
        std::fs::write(folder.join("notes.txt"), "not a scan").unwrap();
        let source = open(&folder, &OpenOptions::default()).unwrap();
        assert_eq!(
            (source.kind(), source.name(), source.len()),
            (SourceKind::PcdFolder, "scans", 3)
        );
        assert!(
            source.scan_path(0).unwrap().ends_with("a.pcd")
                && source.scan_path(2).unwrap().ends_with("c.pcd")
        );
        assert!((source.timestamp(2).unwrap() - 0.2).abs() < 1e-12);
        assert!(matches!(source.frame(0).unwrap().ego, Ego::None));
        assert!(source.labels_path().is_none() && !source.has_oxts() && !source.has_poses());

        std::fs::write(folder.join("times.txt"), "5\n5.5\n6\n").unwrap();
        let source = open(&folder, &OpenOptions::default()).unwrap();
        assert_eq!(source.timestamp(1).unwrap(), 5.5);
        std::fs::write(folder.join("times.txt"), "5\n5.5\n").unwrap();
        assert!(
            open(&folder, &OpenOptions::default())
                .unwrap_err()
                .to_string()
                .contains("2 timestamps for 3 scans")
        );
        std::fs::remove_file(folder.join("times.txt")).unwrap();

        let poses = dir.path().join("poses.txt");
        write_poses(&poses, &[pose(1.0), pose(2.0), pose(4.0)]).unwrap();
        let source = open(
            &folder,
            &OpenOptions {
                poses: Some(poses),
                ..Default::default()
            },
        )
        .unwrap();
        // Without calibration the poses are Velodyne poses, relative to the first.
        assert!(
            matches!(source.frame(2).unwrap().ego, Ego::Pose(p) if (p.translation.z - 3.0).abs() < 1e-9)
        );

        let single = open(&folder.join("b.pcd"), &OpenOptions::default()).unwrap();
        assert_eq!(
            (single.kind(), single.name(), single.len()),
            (SourceKind::SingleFile, "b", 1)
        );
        assert_eq!(single.frame(0).unwrap().points.len(), 4);

        write_bin(&folder.join("d.bin"), &scan(2, 0.0)).unwrap();
        let err = open(&folder, &OpenOptions::default()).unwrap_err();
        assert!(
            err.to_string().contains("both .pcd (3) and .bin (1)"),
            "{err}"
        );
        std::fs::remove_file(folder.join("a.pcd")).unwrap();
        std::fs::remove_file(folder.join("b.pcd")).unwrap();
        std::fs::remove_file(folder.join("c.pcd")).unwrap();
        let source = open(&folder, &OpenOptions::default()).unwrap();
        assert_eq!((source.kind(), source.len()), (SourceKind::BinFolder, 1));
    }

    #[test]
    fn bad_paths_and_scans_are_typed_errors() {
        let dir = tempfile::tempdir().unwrap();
        assert!(matches!(
            open(&dir.path().join("missing"), &OpenOptions::default()),
            Err(DatasetError::Io { .. })
        ));
        assert!(matches!(
            open(dir.path(), &OpenOptions::default()),
            Err(DatasetError::Layout { .. })
        ));
        let text = dir.path().join("readme.txt");
        std::fs::write(&text, "hello").unwrap();
        assert!(matches!(
            open(&text, &OpenOptions::default()),
            Err(DatasetError::Format { .. })
        ));
        let cut = dir.path().join("cut.bin");
        std::fs::write(&cut, [0u8; 17]).unwrap();
        let source = open(dir.path(), &OpenOptions::default()).unwrap();
        assert_eq!(source.kind(), SourceKind::BinFolder);
        let err = source.frame(0).unwrap_err();
        assert!(
            matches!(err, DatasetError::Format { .. }) && err.to_string().contains("cut.bin"),
            "{err}"
        );
    }

    fn shared(what: &str) -> Option<PathBuf> {
        shared_data_dir(what)
    }

    #[test]
    fn real_pcd_folder() {
        let Some(data) = shared("source::real_pcd_folder") else {
            return;
        };
        let source = open(&data.join("kitti-raw-22"), &OpenOptions::default()).unwrap();
        assert_eq!(
            (source.kind(), source.name(), source.len()),
            (SourceKind::PcdFolder, "kitti-raw-22", 22)
        );
        let mut dropped = 0;
        for i in 0..source.len() {
            let (frame, stats) = source.frame_with_stats(i).unwrap();
            assert!(
                (114_000..=121_500).contains(&stats.points_in_file),
                "{stats:?}"
            );
            assert_eq!(frame.points.len(), stats.points_in_file - stats.dropped);
            assert!(frame.points.iter().all(crate::clean::is_valid));
            assert!((frame.timestamp - 0.1 * i as f64).abs() < 1e-9);
            dropped += stats.dropped;
        }
        assert!(dropped > 0, "some frames hold an all-zero point");
    }

    #[test]
    fn real_odometry_folder_is_a_bin_folder() {
        let Some(data) = shared("source::real_odometry_folder_is_a_bin_folder") else {
            return;
        };
        let source = open(&data.join("kitti-odometry-00"), &OpenOptions::default()).unwrap();
        assert_eq!((source.kind(), source.len()), (SourceKind::BinFolder, 6));
        let frame = source.frame(5).unwrap();
        assert!(
            (120_000..130_000).contains(&frame.points.len()),
            "{}",
            frame.points.len()
        );
    }

    #[test]
    fn real_tracking_sequence_at_both_levels() {
        let Some(data) = shared("source::real_tracking_sequence_at_both_levels") else {
            return;
        };
        let root = data.join("kitti-tracking-0000-first40");
        for path in [root.clone(), root.join("training")] {
            let source = open(&path, &OpenOptions::default()).unwrap();
            assert_eq!(
                (source.kind(), source.name(), source.len()),
                (SourceKind::KittiTracking, "0000", 40)
            );
            assert!(source.has_poses() && !source.has_oxts());
            assert!(source.labels_path().unwrap().ends_with("label_02/0000.txt"));
            assert!(source.imu_to_velo().is_some() && source.calib().is_some());
        }
        let source = open(&root, &OpenOptions::default()).unwrap();
        let (first, last) = (source.frame(0).unwrap(), source.frame(39).unwrap());
        assert!(matches!(first.ego, Ego::Pose(p) if p.translation.vector.norm() < 1e-9));
        assert!(matches!(last.ego, Ego::Pose(p) if p.translation.x > 5.0));
        assert!((last.timestamp - 3.9).abs() < 1e-9);
        assert!(last.points.len() > 100_000);
    }

    #[test]
    fn real_raw_drive_without_point_clouds_opens_empty() {
        let Some(data) = shared("source::real_raw_drive_without_point_clouds_opens_empty") else {
            return;
        };
        let raw = data.join("kitti-format-samples/raw");
        for path in [
            raw.join("2011_09_26/2011_09_26_drive_0001_sync"),
            raw.join("2011_09_26"),
            raw.clone(),
        ] {
            let source = open(&path, &OpenOptions::default()).unwrap();
            assert_eq!(
                (source.kind(), source.name()),
                (SourceKind::KittiRaw, "2011_09_26_drive_0001_sync")
            );
            assert!(source.is_empty());
            assert!(source.has_oxts());
            assert!(source.labels_path().unwrap().ends_with(TRACKLETS_FILE));
            assert_eq!(
                source.imu_to_velo(),
                Some(RawCalib::kitti_2011_09_26().imu_to_velo)
            );
            assert!(
                source
                    .notes()
                    .iter()
                    .any(|n| n.contains("no velodyne_points")),
                "{:?}",
                source.notes()
            );
        }
    }

    #[test]
    fn real_tracking_labels_sample_opens_empty() {
        let Some(data) = shared("source::real_tracking_labels_sample_opens_empty") else {
            return;
        };
        let source = open(
            &data.join("kitti-format-samples/tracking"),
            &OpenOptions::default(),
        )
        .unwrap();
        assert_eq!(
            (source.kind(), source.name(), source.len()),
            (SourceKind::KittiTracking, "0001", 0)
        );
        assert!(source.labels_path().is_some() && source.calib().is_some());
        assert!(
            source
                .notes()
                .iter()
                .any(|n| n.contains("no velodyne/0001")),
            "{:?}",
            source.notes()
        );
        // The data root itself and the samples folder hold several layouts: not one source.
        for path in [data.clone(), data.join("kitti-format-samples")] {
            assert!(
                matches!(
                    open(&path, &OpenOptions::default()),
                    Err(DatasetError::Layout { .. })
                ),
                "{}",
                path.display()
            );
        }
    }
}
