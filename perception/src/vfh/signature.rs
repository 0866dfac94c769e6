//! PCL's `VFHEstimation` (1.13, default settings) for one cluster with given normals,
//! reproduced operation for operation in `f32` so that the bins agree with PCL's.
//!
//! - f1, f2, f3 (bins 0-44, 45-89, 90-134): `computePairFeatures` of the pair (centroid, mean
//!   normal) and (pᵢ, nᵢ) for every point, with PCL's source/target swap; each binned as
//!   `floor(45 · (f + π) / 2π)` and adding `100 / (n - 1)`. Pairs PCL rejects (a point on the
//!   centroid, or a zero Darboux `v`) add nothing.
//! - distance (bins 135-179): zero (PCL's default: no size component).
//! - viewpoint (bins 180-307): `floor(128 · (nᵢ · d + 1) / 2)` adding `100 / n`, where `d` is
//!   PCL's normalised `(viewpoint - centroid)`. PCL's centroid carries w = 1 and its viewpoint
//!   w = 0, so it normalises the 4-vector `(d_x, d_y, d_z, -1)`: the xyz part is shortened by
//!   `|d| / sqrt(|d|² + 1)`. That is kept, to stay comparable with PCL's histograms.
//! - the mean normal is the plain mean of the normals, not re-normalised (as in PCL).
//!
//! Dot products follow Eigen's SSE reduction order, `(x·x' + z·z') + (y·y' + w·w')`.

use super::{BINS, Vfh};

/// Bins of each of f1, f2, f3 and the distance block.
const FEATURE_BINS: usize = 45;
/// Bins of the viewpoint block.
const VIEWPOINT_BINS: usize = 128;
/// PCL's `d_pi_`: `1 / (2π)` as an `f32`.
const D_PI: f32 = 1.0 / (2.0 * std::f32::consts::PI);

/// A 4-vector as Eigen's `Vector4f`.
type V4 = [f32; 4];

/// The VFH of the points `points` with unit normals `normals` (same length, at least 2) seen
/// from `viewpoint`. Everything is `f32`, as in PCL.
pub fn vfh_signature(points: &[[f32; 3]], normals: &[[f32; 3]], viewpoint: [f32; 3]) -> Vfh {
    let n = points.len().min(normals.len());
    let mut bins = [0.0f32; BINS];
    if n < 2 {
        return Vfh { bins };
    }
    let (points, normals) = (&points[..n], &normals[..n]);

    // compute3DCentroid: float sums in index order, divided by the count; w = 1.
    let mut centroid: V4 = [0.0, 0.0, 0.0, 0.0];
    for p in points {
        centroid[0] += p[0];
        centroid[1] += p[1];
        centroid[2] += p[2];
    }
    let count = n as f32;
    centroid = [
        centroid[0] / count,
        centroid[1] / count,
        centroid[2] / count,
        0.0 / count,
    ];
    centroid[3] = 1.0;

    // The mean normal: 4-vector sums (w = 0), divided by the count.
    let mut mean_normal: V4 = [0.0; 4];
    for q in normals {
        for axis in 0..3 {
            mean_normal[axis] += q[axis];
        }
    }
    let mean_normal = mean_normal.map(|c| c / count);

    let vp: V4 = [viewpoint[0], viewpoint[1], viewpoint[2], 0.0];
    let d_vp_p = normalize(sub(vp, centroid));

    // f1, f2, f3.
    let increment = 100.0f32 / (n - 1) as f32;
    for (p, q) in points.iter().zip(normals) {
        let p4: V4 = [p[0], p[1], p[2], 1.0];
        let q4: V4 = [q[0], q[1], q[2], 0.0];
        let Some(features) = pair_features(centroid, mean_normal, p4, q4) else {
            continue;
        };
        for (block, f) in features.into_iter().enumerate() {
            let raw = FEATURE_BINS as f64 * ((f as f64 + std::f64::consts::PI) * D_PI as f64);
            let index = floor_clamped(raw, FEATURE_BINS);
            bins[block * FEATURE_BINS + index] += increment;
        }
    }

    // Viewpoint component.
    let increment = (100.0f64 / n as f64) as f32;
    let offset = 4 * FEATURE_BINS;
    for q in normals {
        let q4: V4 = [q[0], q[1], q[2], 0.0];
        let alpha = (dot(q4, d_vp_p) as f64 + 1.0) * 0.5;
        let index = floor_clamped(alpha * VIEWPOINT_BINS as f64, VIEWPOINT_BINS);
        bins[offset + index] += increment;
    }
    Vfh { bins }
}

/// PCL's `computePairFeatures(p1, n1, p2, n2)`: (f1, f2, f3), or `None` where PCL returns
/// false (coincident points, or a zero Darboux `v`).
fn pair_features(p1: V4, n1: V4, p2: V4, n2: V4) -> Option<[f32; 3]> {
    let mut dp2p1 = sub(p2, p1);
    dp2p1[3] = 0.0;
    let f4 = norm(dp2p1);
    if f4 == 0.0 {
        return None;
    }
    let mut n1_copy = [n1[0], n1[1], n1[2], 0.0];
    let mut n2_copy = [n2[0], n2[1], n2[2], 0.0];
    let angle1 = dot(n1_copy, dp2p1) / f4;
    let angle2 = dot(n2_copy, dp2p1) / f4;
    let f3 = if farther_from_the_line(angle1, angle2) {
        std::mem::swap(&mut n1_copy, &mut n2_copy);
        dp2p1 = dp2p1.map(|c| -c);
        -angle2
    } else {
        angle1
    };
    let mut v = cross3(dp2p1, n1_copy);
    v[3] = 0.0;
    let v_norm = norm(v);
    if v_norm == 0.0 {
        return None;
    }
    let v = v.map(|c| c / v_norm);
    let mut w = cross3(n1_copy, v);
    let f2 = dot(v, n2_copy);
    w[3] = 0.0;
    let f1 = dot(w, n2_copy).atan2(dot(n1_copy, n2_copy));
    Some([f1, f2, f3])
}

/// PCL's swap test `acos(|angle1|) > acos(|angle2|)`, with the two `acos` calls only where
/// the cosines are too close for their order to tell (or one is out of acos's domain, NaN
/// there). acos falls with a slope of at least 1 in magnitude, so cosines more than
/// [`ACOS_ORDER_GAP`] apart have angles more than 8 ulp (of π/2) apart, and libm's acosf,
/// within an ulp or two, keeps their order.
#[inline]
fn farther_from_the_line(angle1: f32, angle2: f32) -> bool {
    let (a1, a2) = (angle1.abs(), angle2.abs());
    if a1 <= 1.0 && a2 <= 1.0 && (a1 - a2).abs() > ACOS_ORDER_GAP {
        a1 < a2
    } else {
        a1.acos() > a2.acos()
    }
}

/// See [`farther_from_the_line`]: 8 ulp of π/2 in `f32`.
const ACOS_ORDER_GAP: f32 = 1e-6;

/// `floor(x)` clamped to `0..bins` as an index. A truncating cast equals floor for x ≥ 0 and
/// lands on 0 or below for x < 0, where the clamp gives 0 either way (NaN gives 0 as well),
/// without the libm call `f64::floor` costs on baseline x86-64.
#[inline]
fn floor_clamped(x: f64, bins: usize) -> usize {
    (x as i32).clamp(0, bins as i32 - 1) as usize
}

/// `a - b`.
fn sub(a: V4, b: V4) -> V4 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3]]
}

/// Eigen's `Vector4f::dot` with SSE: lane sums (0 + 2) and (1 + 3), then added.
fn dot(a: V4, b: V4) -> f32 {
    (a[0] * b[0] + a[2] * b[2]) + (a[1] * b[1] + a[3] * b[3])
}

/// Eigen's `norm()`.
fn norm(a: V4) -> f32 {
    dot(a, a).sqrt()
}

/// Eigen's `normalize()`: divides by the norm unless it is zero.
fn normalize(a: V4) -> V4 {
    let n = norm(a);
    if n > 0.0 { a.map(|c| c / n) } else { a }
}

/// Eigen's `cross3`: the cross product of the xyz parts, w = 0.
fn cross3(a: V4, b: V4) -> V4 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
        0.0,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn approx(a: [f32; 3], b: [f32; 3]) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() < 1e-6)
    }

    #[test]
    fn pair_features_without_and_with_the_swap() {
        let origin = [0.0, 0.0, 0.0, 1.0];
        let x = [1.0, 0.0, 0.0, 1.0];
        let up = [0.0, 0.0, 1.0, 0.0];
        // Parallel normals across the pair: all three features 0.
        assert!(approx(
            pair_features(origin, up, x, up).unwrap(),
            [0.0, 0.0, 0.0]
        ));
        // The target's normal is closer to the line: source and target swap, f3 = -angle2.
        let tilted = [0.6, 0.0, 0.8, 0.0];
        let f = pair_features(origin, up, x, tilted).unwrap();
        assert!(approx(f, [0.6f32.atan2(0.8), 0.0, -0.6]), "{f:?}");
        // Without the swap: f3 = angle1.
        let f = pair_features(origin, tilted, x, up).unwrap();
        assert!(approx(f, [-(0.6f32.atan2(0.8)), 0.0, 0.6]), "{f:?}");
        // Coincident points and a normal along the line are rejected, as in PCL.
        assert!(pair_features(origin, up, origin, up).is_none());
        assert!(pair_features(origin, up, x, [1.0, 0.0, 0.0, 0.0]).is_none());
    }

    #[test]
    fn a_plane_gives_one_peak_per_angle_block() {
        // A 10 x 10 patch of road, 10 m ahead, normals up, seen from the sensor.
        let points: Vec<[f32; 3]> = (0..100)
            .map(|i| [10.0 + (i % 10) as f32 * 0.1, (i / 10) as f32 * 0.1, -1.7])
            .collect();
        let normals = vec![[0.0, 0.0, 1.0]; 100];
        let h = vfh_signature(&points, &normals, [0.0, 0.0, 0.0]);
        // (f + π) / 2π · 45 = 22.5 for f = 0: bin 22 of each block, every point counted
        // with 100 / (n - 1) (no point sits on the centroid).
        let expected = 100.0 * 100.0 / 99.0;
        for block in 0..3 {
            let b = &h.bins[block * 45..block * 45 + 45];
            assert!((b[22] - expected).abs() < 1e-3, "block {block}: {b:?}");
            assert_eq!(b.iter().filter(|&&v| v != 0.0).count(), 1);
        }
        assert!(h.bins[135..180].iter().all(|&v| v == 0.0));
        // Viewpoint block: one bin holds all 100.
        let vp = &h.bins[180..];
        assert_eq!(vp.iter().filter(|&&v| v != 0.0).count(), 1);
        assert!((vp.iter().sum::<f32>() - 100.0).abs() < 1e-3);
        // n · d with d towards the sensor (up and back): about 1.7 / 10.2 -> bin 74.
        let d = [-10.45f32, -0.45, 1.7];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 1.0).sqrt();
        let bin = (((d[2] / len) as f64 + 1.0) * 0.5 * 128.0).floor() as usize;
        assert!(vp[bin] > 99.0, "expected bin {bin}: {vp:?}");
    }

    #[test]
    fn the_swap_test_agrees_with_acos_everywhere() {
        let mut state = 3u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
        };
        for _ in 0..200_000 {
            let a = next() * 1.000_001;
            // Near pairs, one or a few ulp apart, and far pairs.
            let b = match (next() * 3.0) as i32 {
                -2 | -1 => f32::from_bits(a.to_bits().wrapping_add((next() * 9.0) as u32)),
                0 => -a,
                _ => next(),
            };
            for (x, y) in [(a, b), (b, a)] {
                assert_eq!(
                    farther_from_the_line(x, y),
                    x.abs().acos() > y.abs().acos(),
                    "{x} {y}"
                );
            }
        }
        assert!(!farther_from_the_line(f32::NAN, 0.5));
        assert!(!farther_from_the_line(0.2, 1.000_001));
    }

    #[test]
    fn floor_clamped_equals_floor_then_clamp() {
        for x in [
            -3.5,
            -1.0,
            -0.5,
            -0.0,
            0.0,
            0.3,
            1.0,
            44.9,
            45.0,
            1e12,
            f64::NAN,
        ] {
            let expected = (x.floor() as i32).clamp(0, 44) as usize;
            assert_eq!(floor_clamped(x, 45), expected, "{x}");
        }
    }

    #[test]
    fn too_few_points_give_an_empty_histogram() {
        let h = vfh_signature(&[[1.0, 0.0, 0.0]], &[[0.0, 0.0, 1.0]], [0.0; 3]);
        assert!(h.bins.iter().all(|&v| v == 0.0));
    }
}
