//! DBSCAN (grid and k-d tree) against a brute-force O(n²) transcription of scikit-learn's
//! `DBSCAN.fit` (`radius_neighbors` + `_dbscan_inner`) on random clouds.

use proptest::prelude::*;
use trackd_perception::{
    Point,
    cluster::{ClusterConfig, NOISE, NeighbourIndex, dbscan},
};

/// scikit-learn's algorithm, literally: all neighbourhoods (f64 squared distances, `<=`),
/// core = neighbourhood size >= min_samples, then a depth-first expansion from every unlabelled
/// core point in index order.
fn sklearn_dbscan(points: &[Point], eps: f64, min_samples: usize) -> (Vec<i32>, Vec<bool>) {
    let xyz: Vec<[f64; 3]> = points.iter().map(|p| p.xyz().map(f64::from)).collect();
    let finite: Vec<bool> = points
        .iter()
        .map(|p| p.x.is_finite() && p.y.is_finite() && p.z.is_finite())
        .collect();
    let neighbours: Vec<Vec<usize>> = (0..points.len())
        .map(|i| {
            (0..points.len())
                .filter(|&j| {
                    if !finite[i] || !finite[j] {
                        return false;
                    }
                    let (a, b) = (xyz[i], xyz[j]);
                    let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
                    d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= eps * eps
                })
                .collect()
        })
        .collect();
    let core: Vec<bool> = neighbours
        .iter()
        .map(|n| !n.is_empty() && n.len() >= min_samples)
        .collect();
    let mut labels = vec![NOISE; points.len()];
    let mut next = 0;
    for start in 0..points.len() {
        if labels[start] != NOISE || !core[start] {
            continue;
        }
        let mut stack = vec![start];
        while let Some(i) = stack.pop() {
            if labels[i] == NOISE {
                labels[i] = next;
                if core[i] {
                    stack.extend(neighbours[i].iter().filter(|&&j| labels[j] == NOISE));
                }
            }
        }
        next += 1;
    }
    (labels, core)
}

/// A cloud of a few blobs and scattered points; coordinates on a 1/64 m lattice half of the
/// time, so that exact-eps distances and duplicates happen.
fn cloud() -> impl Strategy<Value = Vec<Point>> {
    let blob = (
        -6.0f32..6.0,
        -6.0f32..6.0,
        -1.0f32..2.0,
        0.05f32..0.8,
        1usize..40,
    );
    (
        prop::collection::vec(blob, 0..6),
        prop::collection::vec((-8.0f32..8.0, -8.0f32..8.0, -2.0f32..3.0), 0..40),
        any::<bool>(),
        any::<u64>(),
    )
        .prop_map(|(blobs, scattered, lattice, seed)| {
            let mut state = seed | 1;
            let mut unit = move || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f32 / (1u64 << 53) as f32 * 2.0 - 1.0
            };
            let snap = |v: f32| {
                if lattice {
                    (v * 64.0).round() / 64.0
                } else {
                    v
                }
            };
            let mut points = Vec::new();
            for (cx, cy, cz, spread, count) in blobs {
                for _ in 0..count {
                    points.push(Point::new(
                        snap(cx + spread * unit()),
                        snap(cy + spread * unit()),
                        snap(cz + spread * unit()),
                        0.0,
                    ));
                }
            }
            points.extend(
                scattered
                    .into_iter()
                    .map(|(x, y, z)| Point::new(snap(x), snap(y), snap(z), 0.0)),
            );
            // Interleave blobs and scatter so that cluster order is not point order.
            let len = points.len();
            if len > 1 {
                for i in 0..len {
                    let j = ((unit() + 1.0) * 0.5 * len as f32) as usize % len;
                    points.swap(i, j);
                }
            }
            points
        })
}

fn check(points: &[Point], eps: f64, min_points: usize) -> Result<(), TestCaseError> {
    let (labels, core) = sklearn_dbscan(points, eps, min_points);
    for index in [NeighbourIndex::Grid, NeighbourIndex::KdTree] {
        let got = dbscan(
            points,
            &ClusterConfig {
                eps,
                min_points,
                index,
            },
        )
        .map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(&got.core, &core, "{:?}: core points differ", index);
        prop_assert_eq!(&got.labels, &labels, "{:?}: labels differ", index);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn dbscan_equals_the_brute_force_reference(
        points in cloud(),
        eps in prop::sample::select(vec![0.1, 0.25, 0.3, 0.5, 0.7, 1.0, 1.5]),
        min_points in 1usize..9,
    ) {
        check(&points, eps, min_points)?;
    }

    /// A far-away point makes the cloud too wide for eps/√3 cells: the point-by-point path.
    #[test]
    fn dbscan_on_a_very_wide_cloud_equals_the_reference(
        mut points in cloud(),
        min_points in 1usize..6,
    ) {
        points.push(Point::new(9.0e5, -9.0e5, 0.0, 0.0));
        points.push(Point::new(f32::NAN, 0.0, 0.0, 0.0));
        check(&points, 0.5, min_points)?;
    }
}
