//! `trackd bench`: wall time of each per-frame stage (filter → ground → world transform →
//! DBSCAN → VFH per cluster) on one scan, repeated; median and minimum per stage and in total.

use std::{path::PathBuf, time::Instant};

use anyhow::{Context, bail};
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};
use trackd_perception::{
    Point,
    cluster::{ClusterConfig, Clustering, Dbscan, NOISE},
    filter::{Filter, FilterConfig},
    ground::{GroundConfig, GroundRemoval},
    transform::{sensor_origin, to_world},
    vfh::{ClusterVfh, VfhConfig, VfhEstimator, compute_clusters_parallel},
};

use super::cluster::read_points;

/// Flags of `trackd bench`.
#[derive(clap::Args)]
pub struct Args {
    /// The scan: KITTI `.bin`, `.pcd`, or `.xyz` (N x 3 little-endian f32).
    pub frame: PathBuf,
    /// Timed runs (after one untimed warm-up run that sizes the buffers).
    #[arg(long, default_value_t = 21)]
    pub repeat: usize,
    /// Threads: 1 runs everything on this thread; more run the VFH of the clusters on a
    /// rayon pool of that size.
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
    /// Pose of the sensor in the world frame, 12 numbers (3 x 4 row-major, KITTI poses.txt
    /// style); identity when absent.
    #[arg(long, num_args = 12, allow_negative_numbers = true, value_name = "R|t")]
    pub pose: Option<Vec<f64>>,
    /// Voxel edge of the filter in metres (0: none); default: the filter's default.
    #[arg(long)]
    pub voxel: Option<f32>,
    /// DBSCAN radius in metres; default: the cluster stage's default.
    #[arg(long)]
    pub eps: Option<f64>,
    /// DBSCAN core threshold; default: the cluster stage's default.
    #[arg(long)]
    pub min_points: Option<usize>,
    /// Most points a cluster's VFH uses (0: all); default: the VFH stage's default.
    #[arg(long)]
    pub vfh_max_points: Option<usize>,
}

/// The stages' names, in order.
const STAGES: [&str; 5] = ["filter", "ground", "transform", "dbscan", "vfh"];

/// Runs `trackd bench`.
pub fn run(args: Args) -> anyhow::Result<()> {
    if args.repeat == 0 {
        bail!("--repeat must be at least 1");
    }
    let scan = read_points(&args.frame)?;
    let pose = match &args.pose {
        Some(m) => pose_from_rows(m)?,
        None => Isometry3::identity(),
    };
    let mut filter_config = FilterConfig::default();
    if let Some(v) = args.voxel {
        filter_config.voxel_size = (v > 0.0).then_some(v);
    }
    let mut cluster_config = ClusterConfig::default();
    cluster_config.eps = args.eps.unwrap_or(cluster_config.eps);
    cluster_config.min_points = args.min_points.unwrap_or(cluster_config.min_points);
    let mut vfh_config = VfhConfig::default();
    vfh_config.max_points = args.vfh_max_points.unwrap_or(vfh_config.max_points);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.max(1))
        .build()
        .context("cannot start the worker threads")?;

    let mut chain = Chain {
        filter: Filter::new(filter_config),
        ground: GroundRemoval::new(GroundConfig::default()),
        dbscan: Dbscan::new(cluster_config),
        vfh: VfhEstimator::new(vfh_config.clone()),
        vfh_config,
        threads: args.threads.max(1),
        pose,
        filtered: Vec::new(),
        non_ground: Vec::new(),
        world: Vec::new(),
        clustering: Clustering::default(),
        descriptors: Vec::new(),
    };
    let mut times = vec![Vec::with_capacity(args.repeat); STAGES.len() + 1];
    pool.install(|| -> anyhow::Result<()> {
        chain.run(&scan)?;
        for _ in 0..args.repeat {
            let stages = chain.run(&scan)?;
            for (k, ms) in stages.iter().enumerate() {
                times[k].push(*ms);
            }
            times[STAGES.len()].push(stages.iter().sum());
        }
        Ok(())
    })?;

    let clustered = chain
        .clustering
        .labels
        .iter()
        .filter(|&&l| l != NOISE)
        .count();
    let outputs = [
        format!("{} points", chain.filtered.len()),
        format!("{} points", chain.non_ground.len()),
        format!("{} points", chain.world.len()),
        format!("{} clusters ({clustered} points)", chain.clustering.len()),
        format!(
            "{} histograms ({} points)",
            chain.descriptors.len(),
            chain.descriptors.iter().map(|d| d.points).sum::<usize>()
        ),
        String::new(),
    ];
    println!(
        "trackd bench {}: {} points, {} runs, {} thread(s)",
        args.frame.display(),
        scan.len(),
        args.repeat,
        args.threads.max(1)
    );
    println!(
        "{:<10} {:>10} {:>10}  output",
        "stage", "median ms", "min ms"
    );
    for (k, name) in STAGES.iter().chain(["total"].iter()).enumerate() {
        let (median, min) = median_and_min(&mut times[k]);
        println!("{name:<10} {median:>10.3} {min:>10.3}  {}", outputs[k]);
    }
    Ok(())
}

/// The stages and their buffers.
struct Chain {
    filter: Filter,
    ground: GroundRemoval,
    dbscan: Dbscan,
    vfh: VfhEstimator,
    vfh_config: VfhConfig,
    threads: usize,
    pose: Isometry3<f64>,
    filtered: Vec<Point>,
    non_ground: Vec<Point>,
    world: Vec<Point>,
    clustering: Clustering,
    descriptors: Vec<ClusterVfh>,
}

impl Chain {
    /// One pass over `scan`: milliseconds per stage.
    fn run(&mut self, scan: &[Point]) -> anyhow::Result<[f64; 5]> {
        let mut ms = [0.0; 5];
        let started = Instant::now();
        self.filter.run(scan, &mut self.filtered);
        ms[0] = lap(started);
        let started = Instant::now();
        self.ground.remove(&self.filtered, &mut self.non_ground);
        ms[1] = lap(started);
        let started = Instant::now();
        to_world(&self.non_ground, &self.pose, &mut self.world);
        ms[2] = lap(started);
        let started = Instant::now();
        self.dbscan.run(&self.world, &mut self.clustering)?;
        ms[3] = lap(started);
        let started = Instant::now();
        let viewpoint = sensor_origin(&self.pose).coords.into();
        if self.threads > 1 {
            compute_clusters_parallel(
                &self.vfh_config,
                &self.world,
                &self.clustering,
                viewpoint,
                &mut self.descriptors,
            );
        } else {
            self.vfh.compute_clusters(
                &self.world,
                &self.clustering,
                viewpoint,
                &mut self.descriptors,
            );
        }
        ms[4] = lap(started);
        Ok(ms)
    }
}

/// Milliseconds since `started`.
fn lap(started: Instant) -> f64 {
    started.elapsed().as_secs_f64() * 1e3
}

/// Median (upper median for an even count) and minimum; sorts `values`.
fn median_and_min(values: &mut [f64]) -> (f64, f64) {
    values.sort_by(f64::total_cmp);
    (values[values.len() / 2], values[0])
}

/// A pose from a 3 x 4 row-major matrix (rotation re-orthonormalised).
fn pose_from_rows(m: &[f64]) -> anyhow::Result<Isometry3<f64>> {
    if m.len() != 12 || m.iter().any(|v| !v.is_finite()) {
        bail!("--pose takes 12 finite numbers (3 x 4, row-major)");
    }
    let r = Matrix3::new(m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]);
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix(&r));
    Ok(Isometry3::from_parts(
        Translation3::from(Vector3::new(m[3], m[7], m[11])),
        rotation,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_min_and_pose() {
        let mut v = [3.0, 1.0, 2.0, 10.0];
        assert_eq!(median_and_min(&mut v), (3.0, 1.0));
        let pose = pose_from_rows(&[0., -1., 0., 5., 1., 0., 0., 6., 0., 0., 1., 7.]).unwrap();
        let p = pose * nalgebra::Point3::new(1.0, 0.0, 0.0);
        assert!((p - nalgebra::Point3::new(5.0, 7.0, 7.0)).norm() < 1e-12);
        assert!(pose_from_rows(&[1.0; 11]).is_err());
    }

    #[test]
    fn runs_the_chain_on_a_small_scan() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("scan.xyz");
        let mut coords = Vec::new();
        // Ground rings and a box.
        for ring in 0..20 {
            for step in 0..360 {
                let (r, a) = (4.0 + ring as f32, (step as f32).to_radians());
                coords.extend([r * a.cos(), r * a.sin(), -1.73]);
            }
        }
        for i in 0..400 {
            coords.extend([
                10.0 + (i % 20) as f32 * 0.05,
                2.0,
                -1.2 + (i / 20) as f32 * 0.05,
            ]);
        }
        let bytes: Vec<u8> = coords.iter().flat_map(|v| v.to_le_bytes()).collect();
        std::fs::write(&path, bytes).unwrap();
        run(Args {
            frame: path,
            repeat: 3,
            threads: 2,
            pose: None,
            voxel: None,
            eps: None,
            min_points: None,
            vfh_max_points: None,
        })
        .unwrap();
    }
}
