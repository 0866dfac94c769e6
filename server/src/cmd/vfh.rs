//! `trackd vfh`: the VFH (PCL's `VFHSignature308`) of every labelled cluster of one scan.

use std::{fmt::Write as _, path::PathBuf};

use anyhow::{Context, bail};
use trackd_perception::{
    Point,
    vfh::{VfhConfig, VfhEstimator},
};

use super::cluster::{read_labels, read_points};

/// Flags of `trackd vfh`.
#[derive(clap::Args)]
pub struct Args {
    /// The points: KITTI `.bin`, `.pcd`, or `.xyz` (N x 3 little-endian f32).
    pub points: PathBuf,
    /// Their labels: N little-endian i32 (as `trackd cluster` writes them), < 0 for noise.
    pub labels: PathBuf,
    /// Neighbours (the point itself included) of each point's PCA normal.
    #[arg(long, default_value_t = VfhConfig::default().normal_k)]
    pub normal_k: usize,
    /// Clusters with fewer points are left out.
    #[arg(long, default_value_t = VfhConfig::default().min_points)]
    pub min_points: usize,
    /// Larger clusters are described by this many evenly spread points (0: all, as PCL).
    #[arg(long, default_value_t = VfhConfig::default().max_points)]
    pub max_points: usize,
    /// The sensor position in the points' frame, for the normals' orientation and the
    /// viewpoint component.
    #[arg(long, num_args = 3, value_names = ["X", "Y", "Z"], allow_negative_numbers = true,
          default_values_t = [0.0, 0.0, 0.0])]
    pub viewpoint: Vec<f64>,
    /// Where to write the CSV: `cluster,npoints,vfh_0,…,vfh_307`, one row per cluster.
    #[arg(long)]
    pub out: PathBuf,
    /// Also write the normals used: N x 3 little-endian f32, NaN for points not used (outside
    /// the clusters written, or left out by `--max-points`).
    #[arg(long)]
    pub normals_out: Option<PathBuf>,
}

/// Runs `trackd vfh`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let points = read_points(&args.points)?;
    let labels = read_labels(&args.labels)?;
    if labels.len() != points.len() {
        bail!(
            "{} holds {} labels for the {} points of {}",
            args.labels.display(),
            labels.len(),
            points.len(),
            args.points.display()
        );
    }
    let viewpoint = [args.viewpoint[0], args.viewpoint[1], args.viewpoint[2]];
    let clusters = group_by_label(&labels);
    let config = VfhConfig {
        normal_k: args.normal_k,
        min_points: args.min_points,
        max_points: args.max_points,
    };
    let mut estimator = VfhEstimator::new(config.clone());
    let mut normals = vec![[f32::NAN; 3]; points.len()];
    let mut csv = String::from("cluster,npoints");
    for k in 0..trackd_perception::vfh::BINS {
        write!(csv, ",vfh_{k}")?;
    }
    csv.push('\n');
    let mut written = 0;
    let mut members: Vec<Point> = Vec::new();
    for (label, indices) in clusters.iter().enumerate() {
        members.clear();
        members.extend(indices.iter().map(|&i| points[i]));
        let Some(vfh) = estimator.compute(&members, viewpoint) else {
            continue;
        };
        let used = indices.iter().step_by(config.sample_stride(indices.len()));
        for (&i, n) in used.zip(estimator.normals()) {
            normals[i] = *n;
        }
        write!(csv, "{label},{}", indices.len())?;
        for b in vfh.bins {
            write!(csv, ",{b}")?;
        }
        csv.push('\n');
        written += 1;
    }
    std::fs::write(&args.out, csv)
        .with_context(|| format!("{}: cannot write", args.out.display()))?;
    if let Some(path) = &args.normals_out {
        let bytes: Vec<u8> = normals
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        std::fs::write(path, bytes).with_context(|| format!("{}: cannot write", path.display()))?;
    }
    tracing::info!(
        points = points.len(),
        clusters = clusters.len(),
        described = written,
        out = %args.out.display(),
        "vfh"
    );
    Ok(())
}

/// Input indices of each label `0..=max` (noise left out), ascending.
fn group_by_label(labels: &[i32]) -> Vec<Vec<usize>> {
    let count = labels.iter().copied().max().map_or(0, |m| (m + 1).max(0)) as usize;
    let mut clusters = vec![Vec::new(); count];
    for (i, &label) in labels.iter().enumerate() {
        if label >= 0 {
            clusters[label as usize].push(i);
        }
    }
    clusters
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_one_row_per_cluster_with_enough_points() {
        let dir = tempfile::tempdir().unwrap();
        let xyz = dir.path().join("p.xyz");
        let labels = dir.path().join("l.i32");
        let mut coords = Vec::new();
        let mut label_bytes = Vec::new();
        for i in 0..40 {
            // Cluster 1: a 5 x 8 patch; cluster 0: 3 points; one noise point.
            let (x, y) = (10.0 + (i % 5) as f32 * 0.1, (i / 5) as f32 * 0.1);
            coords.extend([x, y, -1.5]);
            label_bytes.extend(1i32.to_le_bytes());
        }
        for i in 0..3 {
            coords.extend([20.0, i as f32 * 0.1, 0.0]);
            label_bytes.extend(0i32.to_le_bytes());
        }
        coords.extend([30.0, 0.0, 0.0]);
        label_bytes.extend((-1i32).to_le_bytes());
        let bytes: Vec<u8> = coords.iter().flat_map(|v| v.to_le_bytes()).collect();
        std::fs::write(&xyz, bytes).unwrap();
        std::fs::write(&labels, label_bytes).unwrap();
        let out = dir.path().join("vfh.csv");
        let normals_out = dir.path().join("n.f32");
        run(Args {
            points: xyz,
            labels,
            normal_k: 10,
            min_points: 10,
            max_points: 1024,
            viewpoint: vec![0.0, 0.0, 0.0],
            out: out.clone(),
            normals_out: Some(normals_out.clone()),
        })
        .unwrap();
        let csv = std::fs::read_to_string(&out).unwrap();
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 2);
        assert!(lines[0].starts_with("cluster,npoints,vfh_0,") && lines[0].ends_with(",vfh_307"));
        let row: Vec<f32> = lines[1].split(',').map(|v| v.parse().unwrap()).collect();
        assert_eq!(row.len(), 2 + 308);
        assert_eq!((row[0], row[1]), (1.0, 40.0));
        let viewpoint_sum: f32 = row[2 + 180..].iter().sum();
        assert!((viewpoint_sum - 100.0).abs() < 1e-3);
        let normals = std::fs::read(&normals_out).unwrap();
        assert_eq!(normals.len(), 44 * 12);
        let nz = f32::from_le_bytes(normals[8..12].try_into().unwrap());
        assert!((nz - 1.0).abs() < 1e-5);
        assert!(f32::from_le_bytes(normals[40 * 12..40 * 12 + 4].try_into().unwrap()).is_nan());
    }
}
