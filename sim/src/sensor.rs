//! An HDL-64E-like LiDAR: 64 lasers, a full revolution per scan, range noise, dropouts and
//! reflectance-based intensities, returning points in the Velodyne frame with their labels.

use nalgebra::{Isometry3, Vector3};
use rayon::prelude::*;
use trackd_perception::Point;

use crate::label::PointLabel;
use crate::random::{RayRng, hash_seed};
use crate::raycast::Scene;

/// The sensor model's parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Lidar {
    /// Elevation of each laser (radians), top first.
    pub elevations: Vec<f64>,
    /// Azimuth steps per revolution.
    pub columns: usize,
    /// Farthest return (metres).
    pub max_range: f64,
    /// Nearest return (metres): closer hits are discarded, as the real sensor does.
    pub min_range: f64,
    /// Standard deviation of the range noise (metres).
    pub range_sigma: f64,
    /// Probability that any return is lost.
    pub dropout: f64,
    /// Extra loss probability of a black surface at maximum range (scaled by darkness and
    /// the square of the range fraction).
    pub far_dark_dropout: f64,
    /// Standard deviation of the intensity noise.
    pub intensity_sigma: f64,
}

impl Lidar {
    /// A Velodyne HDL-64E as KITTI used it: an upper block of 32 lasers from +2° to −8.33°
    /// (1/3° apart), a lower block of 32 from −8.83° to −24.8° (about 1/2° apart), 2000
    /// azimuth steps, 2 cm range noise, 120 m range.
    pub fn hdl64e() -> Self {
        let upper = (0..32).map(|i| 2.0 - i as f64 / 3.0);
        let lower = (0..32).map(|i| -8.83 - i as f64 * (24.8 - 8.83) / 31.0);
        Self {
            elevations: upper.chain(lower).map(f64::to_radians).collect(),
            columns: 2000,
            max_range: 120.0,
            min_range: 2.0,
            range_sigma: 0.02,
            dropout: 0.02,
            far_dark_dropout: 0.6,
            intensity_sigma: 0.03,
        }
    }

    /// Azimuth (radians, Velodyne frame) of column `j` of a scan whose first column is
    /// turned by `phase` steps: the head turns clockwise seen from above, from behind the
    /// vehicle, as in KITTI's scans.
    fn azimuth(&self, j: usize, phase: f64) -> f64 {
        std::f64::consts::PI - (j as f64 + phase) * std::f64::consts::TAU / self.columns as f64
    }

    /// One revolution from the Velodyne pose `pose` (Velodyne frame to world frame) in
    /// `scene`, which must be filed around the pose's origin. `seed` makes the noise.
    pub fn scan(&self, scene: &Scene, pose: &Isometry3<f64>, seed: u64) -> Scan {
        let phase = RayRng::new(hash_seed(&[seed, u64::MAX])).uniform();
        let azimuths: Vec<(f64, f64)> = (0..self.columns)
            .map(|j| self.azimuth(j, phase).sin_cos())
            .collect();
        let rings: Vec<Vec<(Point, PointLabel)>> = self
            .elevations
            .par_iter()
            .enumerate()
            .map(|(laser, &el)| {
                let (sin_el, cos_el) = el.sin_cos();
                let mut ring = Vec::with_capacity(self.columns);
                for (j, &(sin_az, cos_az)) in azimuths.iter().enumerate() {
                    let local = Vector3::new(cos_el * cos_az, cos_el * sin_az, sin_el);
                    let mut rng = RayRng::new(hash_seed(&[seed, laser as u64, j as u64]));
                    if let Some(p) = self.measure(scene, pose, &local, &mut rng) {
                        ring.push(p);
                    }
                }
                ring
            })
            .collect();
        let n = rings.iter().map(Vec::len).sum();
        let mut scan = Scan {
            points: Vec::with_capacity(n),
            labels: Vec::with_capacity(n),
        };
        for (point, label) in rings.into_iter().flatten() {
            scan.points.push(point);
            scan.labels.push(label);
        }
        scan
    }

    /// The return of one beam (unit direction `local` in the Velodyne frame), if any.
    fn measure(
        &self,
        scene: &Scene,
        pose: &Isometry3<f64>,
        local: &Vector3<f64>,
        rng: &mut RayRng,
    ) -> Option<(Point, PointLabel)> {
        let dir = pose.rotation * local;
        let hit = scene.first_hit(&dir, rng)?;
        let reflectance = f64::from(hit.material.reflectance);
        let fraction = hit.range / self.max_range;
        let loss = self.dropout + self.far_dark_dropout * (1.0 - reflectance) * fraction * fraction;
        if rng.uniform() < loss {
            return None;
        }
        let range = hit.range + self.range_sigma * rng.gauss();
        if range < self.min_range || range > self.max_range {
            return None;
        }
        let incidence = hit.normal.map_or(0.7, |n| n.dot(&dir).abs());
        let intensity = reflectance * (0.3 + 0.7 * incidence) * (1.0 - 0.3 * fraction)
            + self.intensity_sigma * rng.gauss();
        // KITTI's reflectances come in steps of 0.01.
        let intensity = (intensity.clamp(0.0, 1.0) * 100.0).round() / 100.0;
        let p = local * range;
        Some((
            Point::new(p.x as f32, p.y as f32, p.z as f32, intensity as f32),
            hit.label,
        ))
    }
}

/// One simulated revolution: points in the Velodyne frame and what each one hit.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scan {
    /// The returns, laser by laser (top laser first), each laser clockwise from behind.
    pub points: Vec<Point>,
    /// The ground truth of each point (same order).
    pub labels: Vec<PointLabel>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::terrain::Terrain;

    #[test]
    fn elevations_span_kitti_s_field_of_view() {
        let l = Lidar::hdl64e();
        assert_eq!(l.elevations.len(), 64);
        assert!((l.elevations[0].to_degrees() - 2.0).abs() < 1e-9);
        assert!((l.elevations[63].to_degrees() + 24.8).abs() < 1e-9);
        assert!(l.elevations.windows(2).all(|w| w[1] < w[0]));
    }

    #[test]
    fn flat_ground_scan_lies_on_the_ground_in_rings() {
        let terrain = Terrain::flat();
        let pose = Isometry3::translation(0.0, 0.0, 1.73);
        let scene = Scene::new(&terrain, &[], pose.translation.vector, 120.0);
        let lidar = Lidar::hdl64e();
        let scan = lidar.scan(&scene, &pose, 5);
        assert!(scan.labels.iter().all(PointLabel::is_ground));
        // Upward lasers see nothing; the lowest ring is 1.73 / tan(24.8°) away.
        assert!(
            scan.points.len() > 40 * 2000 * 9 / 10,
            "{}",
            scan.points.len()
        );
        for p in &scan.points {
            assert!((p.z + 1.73).abs() < 0.1, "{p:?}");
            let r = (p.x * p.x + p.y * p.y).sqrt();
            assert!(r > 3.6, "{p:?}");
        }
        assert_eq!(scan, lidar.scan(&scene, &pose, 5));
        assert_ne!(scan.points, lidar.scan(&scene, &pose, 6).points);
    }
}
