//! The rays of a scan in order of azimuth around the sensor. A spinning LiDAR's points come
//! ring by ring, each ring a full turn, so rays in scan order sweep every block around the
//! vehicle once per ring; in azimuth order the rays through one block follow each other and
//! find its voxels in cache. The order of the rays does not change the map: each voxel takes
//! at most one miss a scan.

use nalgebra::Vector3;

/// Azimuth sectors the rays are sorted into (a counting sort: rays of one sector keep their
/// scan order).
const SECTORS: usize = 1024;

/// Writes `ends` into `ordered` sector by sector, counter-clockwise from +x around `sensor`;
/// `counts` is scratch space.
pub(super) fn by_azimuth(
    sensor: &Vector3<f64>,
    ends: &[Vector3<f64>],
    counts: &mut Vec<usize>,
    ordered: &mut Vec<Vector3<f64>>,
) {
    let sector = |end: &Vector3<f64>| {
        let angle = pseudo_angle(end.x - sensor.x, end.y - sensor.y);
        ((angle * (SECTORS / 4) as f64) as usize).min(SECTORS - 1)
    };
    counts.clear();
    counts.resize(SECTORS + 1, 0);
    for end in ends {
        counts[sector(end) + 1] += 1;
    }
    for s in 1..=SECTORS {
        counts[s] += counts[s - 1];
    }
    ordered.clear();
    ordered.resize(ends.len(), Vector3::zeros());
    for end in ends {
        let next = &mut counts[sector(end)];
        ordered[*next] = *end;
        *next += 1;
    }
}

/// A number in [0, 4) that grows with the angle of (`dx`, `dy`) counter-clockwise from +x
/// (one unit per quadrant), without a trigonometric call; 0 for the zero vector.
fn pseudo_angle(dx: f64, dy: f64) -> f64 {
    let sum = dx.abs() + dy.abs();
    if sum == 0.0 || !sum.is_finite() {
        return 0.0;
    }
    let (x, y) = (dx / sum, dy / sum);
    match (x >= 0.0, y >= 0.0) {
        (true, true) => y,
        (false, true) => 1.0 - x,
        (false, false) => 2.0 - y,
        (true, false) => 3.0 + x,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pseudo_angle_grows_with_the_angle() {
        let angles: Vec<f64> = (0..360)
            .map(|deg| {
                let a = f64::from(deg).to_radians();
                pseudo_angle(a.cos(), a.sin())
            })
            .collect();
        assert!(angles[0].abs() < 1e-12);
        assert!(angles.windows(2).all(|w| w[0] < w[1]), "{angles:?}");
        assert!(angles[359] < 4.0);
        assert_eq!(pseudo_angle(0.0, 0.0), 0.0);
    }

    #[test]
    fn orders_the_ends_by_azimuth_and_keeps_every_one() {
        let sensor = Vector3::new(10.0, -5.0, 1.7);
        let ends: Vec<Vector3<f64>> = (0..500)
            .map(|i| {
                let a = f64::from(i * 37 % 500) / 500.0 * std::f64::consts::TAU;
                sensor + Vector3::new(a.cos(), a.sin(), 0.0) * f64::from(5 + i % 30)
            })
            .collect();
        let (mut counts, mut ordered) = (Vec::new(), Vec::new());
        by_azimuth(&sensor, &ends, &mut counts, &mut ordered);
        assert_eq!(ordered.len(), ends.len());
        let angle = |e: &Vector3<f64>| pseudo_angle(e.x - sensor.x, e.y - sensor.y);
        assert!(
            ordered
                .windows(2)
                .all(|w| angle(&w[0]) <= angle(&w[1]) + 4.0 / 1024.0)
        );
        let key = |v: &Vector3<f64>| v.map(|c| c.to_bits());
        let mut a: Vec<_> = ends.iter().map(key).map(|v| [v.x, v.y, v.z]).collect();
        let mut b: Vec<_> = ordered.iter().map(key).map(|v| [v.x, v.y, v.z]).collect();
        a.sort_unstable();
        b.sort_unstable();
        assert_eq!(a, b);
    }
}
