//! `trackd cluster`: DBSCAN on one scan as it is (no filtering), labels written as raw `i32`.

use std::{path::Path, path::PathBuf, time::Instant};

use anyhow::{Context, bail};
use trackd_perception::{
    Point,
    cluster::{ClusterConfig, Clustering, Dbscan, NOISE, NeighbourIndex},
};

/// Flags of `trackd cluster`.
#[derive(clap::Args)]
pub struct Args {
    /// The points: KITTI `.bin`, `.pcd`, or `.xyz` (N x 3 little-endian f32).
    pub points: PathBuf,
    /// Neighbourhood radius in metres.
    #[arg(long, default_value_t = ClusterConfig::default().eps)]
    pub eps: f64,
    /// Points within eps (itself counted) that make a point core.
    #[arg(long, default_value_t = ClusterConfig::default().min_points)]
    pub min_points: usize,
    /// Neighbour index (both give the same labels).
    #[arg(long, value_enum, default_value_t = Index::Grid)]
    pub index: Index,
    /// Where to write the labels: N little-endian i32, -1 for noise, clusters from 0.
    #[arg(long)]
    pub out: PathBuf,
    /// Also write the core flags: N bytes, 1 for a core point, 0 otherwise.
    #[arg(long)]
    pub core_out: Option<PathBuf>,
}

/// `--index` values.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Index {
    /// Clique cell grid.
    Grid,
    /// kiddo k-d tree.
    KdTree,
}

/// Runs `trackd cluster`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let points = read_points(&args.points)?;
    let config = ClusterConfig {
        eps: args.eps,
        min_points: args.min_points,
        index: match args.index {
            Index::Grid => NeighbourIndex::Grid,
            Index::KdTree => NeighbourIndex::KdTree,
        },
    };
    let mut clustering = Clustering::default();
    let started = Instant::now();
    Dbscan::new(config).run(&points, &mut clustering)?;
    let elapsed = started.elapsed();
    write_labels(&args.out, &clustering.labels)?;
    if let Some(path) = &args.core_out {
        let bytes: Vec<u8> = clustering.core.iter().map(|&c| u8::from(c)).collect();
        std::fs::write(path, bytes).with_context(|| format!("{}: cannot write", path.display()))?;
    }
    tracing::info!(
        points = points.len(),
        clusters = clustering.len(),
        noise = clustering.labels.iter().filter(|&&l| l == NOISE).count(),
        ms = elapsed.as_secs_f64() * 1e3,
        out = %args.out.display(),
        "clustered"
    );
    Ok(())
}

/// Reads a point file: `.xyz` (N x 3 little-endian f32, intensity 0) here, `.bin` and
/// `.pcd` through `trackd_dataset`.
pub fn read_points(path: &Path) -> anyhow::Result<Vec<Point>> {
    let is_xyz = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("xyz"));
    if !is_xyz {
        return Ok(trackd_dataset::scan::read_scan(path)?);
    }
    let bytes = std::fs::read(path).with_context(|| format!("{}: cannot read", path.display()))?;
    if bytes.len() % 12 != 0 {
        bail!(
            "{}: {} bytes is not a whole number of x, y, z f32 triples",
            path.display(),
            bytes.len()
        );
    }
    Ok(bytes
        .chunks_exact(12)
        .map(|c| {
            let f = |k: usize| f32::from_le_bytes([c[k], c[k + 1], c[k + 2], c[k + 3]]);
            Point::new(f(0), f(4), f(8), 0.0)
        })
        .collect())
}

/// Reads labels written by [`write_labels`] (N little-endian i32).
pub fn read_labels(path: &Path) -> anyhow::Result<Vec<i32>> {
    let bytes = std::fs::read(path).with_context(|| format!("{}: cannot read", path.display()))?;
    if bytes.len() % 4 != 0 {
        bail!(
            "{}: {} bytes is not a whole number of i32",
            path.display(),
            bytes.len()
        );
    }
    Ok(bytes
        .chunks_exact(4)
        .map(|c| i32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect())
}

/// Writes labels as N little-endian i32.
fn write_labels(path: &Path, labels: &[i32]) -> anyhow::Result<()> {
    let bytes: Vec<u8> = labels.iter().flat_map(|l| l.to_le_bytes()).collect();
    std::fs::write(path, bytes).with_context(|| format!("{}: cannot write", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn xyz_round_trip_and_labels_file() {
        let dir = tempfile::tempdir().unwrap();
        let xyz = dir.path().join("p.xyz");
        let coords: [f32; 9] = [0.0, 0.0, 0.0, 0.1, 0.0, 0.0, 5.0, 5.0, 5.0];
        let bytes: Vec<u8> = coords.iter().flat_map(|v| v.to_le_bytes()).collect();
        std::fs::write(&xyz, &bytes).unwrap();
        let points = read_points(&xyz).unwrap();
        assert_eq!(points[1], Point::new(0.1, 0.0, 0.0, 0.0));
        let out = dir.path().join("labels.i32");
        run(Args {
            points: xyz.clone(),
            eps: 0.5,
            min_points: 2,
            index: Index::Grid,
            out: out.clone(),
            core_out: Some(dir.path().join("core.u8")),
        })
        .unwrap();
        assert_eq!(read_labels(&out).unwrap(), vec![0, 0, -1]);
        assert_eq!(
            std::fs::read(dir.path().join("core.u8")).unwrap(),
            vec![1, 1, 0]
        );
        std::fs::write(&xyz, &bytes[..10]).unwrap();
        assert!(read_points(&xyz).is_err());
    }
}
