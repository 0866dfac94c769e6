//! Geodetic coordinates to the fleet's local metric world frame and back.
//!
//! KITTI's convention (its devkit's `latlonToMercator`): a Mercator projection scaled by the
//! cosine of a reference latitude. Every vehicle of a fleet uses the same [`GeoOrigin`], so
//! their world frames coincide: x east, y north, z up, metres from the origin.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Equatorial Earth radius used by KITTI's devkit, in metres.
pub const EARTH_RADIUS: f64 = 6_378_137.0;

/// The geodetic origin of a world frame (degrees, degrees, metres).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GeoOrigin {
    /// Latitude in degrees.
    pub lat: f64,
    /// Longitude in degrees.
    pub lon: f64,
    /// Altitude in metres.
    pub alt: f64,
}

impl GeoOrigin {
    /// An origin at the given latitude, longitude (degrees) and altitude (metres).
    pub const fn new(lat: f64, lon: f64, alt: f64) -> Self {
        Self { lat, lon, alt }
    }

    /// The Mercator scale of this origin: cos(latitude).
    pub fn scale(&self) -> f64 {
        self.lat.to_radians().cos()
    }

    /// Mercator metres of a latitude/longitude at this origin's scale.
    fn mercator(&self, lat: f64, lon: f64) -> (f64, f64) {
        let s = self.scale() * EARTH_RADIUS;
        let mx = s * lon.to_radians();
        let my = s * ((90.0 + lat).to_radians() / 2.0).tan().ln();
        (mx, my)
    }

    /// The world-frame position (east, north, up in metres) of a geodetic point.
    pub fn to_local(&self, lat: f64, lon: f64, alt: f64) -> Vector3<f64> {
        let (x0, y0) = self.mercator(self.lat, self.lon);
        let (x, y) = self.mercator(lat, lon);
        Vector3::new(x - x0, y - y0, alt - self.alt)
    }

    /// The geodetic point (lat, lon in degrees, alt in metres) of a world-frame position.
    pub fn to_geodetic(&self, p: &Vector3<f64>) -> (f64, f64, f64) {
        let s = self.scale() * EARTH_RADIUS;
        let (x0, y0) = self.mercator(self.lat, self.lon);
        let lon = ((p.x + x0) / s).to_degrees();
        let lat = 2.0 * ((p.y + y0) / s).exp().atan().to_degrees() - 90.0;
        (lat, lon, p.z + self.alt)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const KARLSRUHE: GeoOrigin = GeoOrigin::new(49.011_213_954_206, 8.422_885_922_889_3, 112.83);

    #[test]
    fn origin_maps_to_zero() {
        let p = KARLSRUHE.to_local(KARLSRUHE.lat, KARLSRUHE.lon, KARLSRUHE.alt);
        assert!(p.norm() < 1e-6, "{p}");
    }

    #[test]
    fn one_arc_second_north_is_about_31_metres_scaled() {
        // Mercator at scale cos(lat0): northward metres ≈ true metres near the origin.
        let p = KARLSRUHE.to_local(KARLSRUHE.lat + 1.0 / 3600.0, KARLSRUHE.lon, KARLSRUHE.alt);
        assert!((p.y - 30.92).abs() < 0.1, "{p}");
        assert!(p.x.abs() < 1e-6);
    }

    #[test]
    fn round_trip() {
        let q = Vector3::new(1234.5, -987.25, 3.5);
        let (lat, lon, alt) = KARLSRUHE.to_geodetic(&q);
        let back = KARLSRUHE.to_local(lat, lon, alt);
        assert!((back - q).norm() < 1e-6, "{back} vs {q}");
    }
}
