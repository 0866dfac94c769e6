//! Surface normals as PCL's `NormalEstimation` with `setKSearch(k)` gives them: the plane
//! normal (smallest principal axis) of each point's k nearest neighbours, the point itself
//! included, turned towards the viewpoint.

use super::knn::KnnTree;
use crate::pca::{Moments, smallest_eigenvector};

/// Writes one unit normal per point of `points` into `normals` (cleared first), from the
/// `k` nearest neighbours (all points when there are fewer), each turned so that it faces
/// `viewpoint`. Neighbourhoods on a line or a single point get some unit vector orthogonal
/// to it. `tree` is scratch. Returns the points' mean surface variation (PCL's curvature
/// `λ₀ / (λ₀ + λ₁ + λ₂)` of each neighbourhood): near 0 on smooth surfaces, up to 1/3 in
/// scattered returns such as foliage.
pub(crate) fn estimate_normals(
    points: &[[f32; 3]],
    k: usize,
    viewpoint: [f32; 3],
    tree: &mut KnnTree,
    normals: &mut Vec<[f32; 3]>,
) -> f32 {
    normals.clear();
    normals.resize(points.len(), [0.0, 0.0, 1.0]);
    tree.build(points);
    let mut variation = 0.0f64;
    tree.for_each_knn(k, |index, neighbours| {
        let mut moments = Moments::default();
        for q in neighbours {
            moments.add(q.map(f64::from));
        }
        let covariance = moments.covariance();
        let (smallest, normal) = smallest_eigenvector(covariance);
        let trace = covariance[0][0] + covariance[1][1] + covariance[2][2];
        if trace > 0.0 {
            variation += smallest / trace;
        }
        let mut normal = normal.map(|c| c as f32);
        // flipNormalTowardsViewpoint: (vp - p) · n < 0 -> flip.
        let p = points[index as usize];
        let to_viewpoint = [
            viewpoint[0] - p[0],
            viewpoint[1] - p[1],
            viewpoint[2] - p[2],
        ];
        let cos = (to_viewpoint[0] * normal[0] + to_viewpoint[2] * normal[2])
            + to_viewpoint[1] * normal[1];
        if cos < 0.0 {
            normal = normal.map(|c| -c);
        }
        normals[index as usize] = normal;
    });
    (variation / points.len().max(1) as f64) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plane_seen_from_above_has_up_normals() {
        let points: Vec<[f32; 3]> = (0..100)
            .map(|i| [(i % 10) as f32 * 0.1 + 5.0, (i / 10) as f32 * 0.1, -1.7])
            .collect();
        let mut normals = Vec::new();
        let mut tree = KnnTree::default();
        let variation = estimate_normals(&points, 10, [0.0, 0.0, 0.0], &mut tree, &mut normals);
        assert_eq!(normals.len(), 100);
        assert!(variation < 1e-6, "{variation}");
        for n in &normals {
            assert!((n[2] - 1.0).abs() < 1e-5, "{n:?}");
        }
        estimate_normals(&points, 10, [0.0, 0.0, -5.0], &mut tree, &mut normals);
        assert!(normals.iter().all(|n| (n[2] + 1.0).abs() < 1e-5));
    }

    #[test]
    fn a_sphere_gets_radial_normals() {
        let mut points = Vec::new();
        for i in 0..40 {
            for j in 0..80 {
                let (theta, phi) = (
                    0.1 + i as f32 * 0.075,
                    j as f32 * std::f32::consts::TAU / 80.0,
                );
                points.push([
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                ]);
            }
        }
        let (mut normals, mut tree) = (Vec::new(), KnnTree::default());
        // Seen from the centre: normals point inwards (near the pole the 10 neighbours lie on
        // one small circle, whose axis is the normal: 0.1 rad off the radius).
        estimate_normals(&points, 10, [0.0, 0.0, 0.0], &mut tree, &mut normals);
        for (p, n) in points.iter().zip(&normals) {
            let radial = p[0] * n[0] + p[1] * n[1] + p[2] * n[2];
            assert!(radial < -0.98, "{p:?} {n:?}");
        }
        estimate_normals(&[], 10, [0.0; 3], &mut tree, &mut normals);
        assert!(normals.is_empty());
    }
}
