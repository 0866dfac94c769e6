//! Expressing a remote vehicle's world-frame positions in this fleet's world frame.

use nalgebra::Vector3;

use crate::geo::{EARTH_RADIUS, GeoOrigin};

/// Whether an origin is a place on Earth a vehicle could be (finite, |lat| ≤ 85°, Mercator's
/// useful range; altitude within −1 km … 10 km).
pub fn is_plausible(origin: &GeoOrigin) -> bool {
    origin.lat.is_finite()
        && origin.lon.is_finite()
        && origin.alt.is_finite()
        && origin.lat.abs() <= 85.0
        && origin.lon.abs() <= 180.0
        && (-1_000.0..=10_000.0).contains(&origin.alt)
}

/// Great-circle distance between two origins on a sphere of KITTI's Earth radius (m).
pub fn distance_m(a: &GeoOrigin, b: &GeoOrigin) -> f64 {
    let (la, lb) = (a.lat.to_radians(), b.lat.to_radians());
    let dlat = lb - la;
    let dlon = (b.lon - a.lon).to_radians();
    let h = (dlat / 2.0).sin().powi(2) + la.cos() * lb.cos() * (dlon / 2.0).sin().powi(2);
    2.0 * EARTH_RADIUS * h.sqrt().asin()
}

/// Maps positions from the world frame of `from` to the world frame of `to`.
///
/// Both frames are east/north/up in (locally) true metres, and Mercator is conformal, so
/// sizes, headings and velocities carry over unchanged; only positions are re-expressed.
pub struct OriginShift {
    from: GeoOrigin,
    to: GeoOrigin,
    identical: bool,
}

impl OriginShift {
    /// The shift from `from`'s world frame to `to`'s.
    pub fn new(from: GeoOrigin, to: GeoOrigin) -> Self {
        Self {
            identical: from == to,
            from,
            to,
        }
    }

    /// `p` (in `from`'s frame) in `to`'s frame.
    pub fn apply(&self, p: &Vector3<f64>) -> Vector3<f64> {
        if self.identical {
            return *p;
        }
        let (lat, lon, alt) = self.from.to_geodetic(p);
        self.to.to_local(lat, lon, alt)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: GeoOrigin = GeoOrigin::new(49.011_213_954_206, 8.422_885_922_889_3, 112.83);

    #[test]
    fn shift_between_origins_preserves_the_geodetic_point() {
        let b = GeoOrigin::new(49.012, 8.425, 110.0);
        let p_in_b = Vector3::new(12.0, -30.0, 1.5);
        let p_in_a = OriginShift::new(b, A).apply(&p_in_b);
        let (lat, lon, alt) = b.to_geodetic(&p_in_b);
        let expected = A.to_local(lat, lon, alt);
        assert!((p_in_a - expected).norm() < 1e-6);
        // b's origin lies ~ 87 m north and ~ 155 m east of a's.
        let b_in_a = OriginShift::new(b, A).apply(&Vector3::zeros());
        assert!((b_in_a.y - 87.4).abs() < 1.0, "{b_in_a}");
        assert!((b_in_a.x - 154.6).abs() < 1.0, "{b_in_a}");
        assert!((b_in_a.x.hypot(b_in_a.y) - distance_m(&A, &b)).abs() < 0.5);
    }

    #[test]
    fn implausible_origins_are_told_apart() {
        assert!(is_plausible(&A));
        assert!(!is_plausible(&GeoOrigin::new(f64::NAN, 8.0, 0.0)));
        assert!(!is_plausible(&GeoOrigin::new(89.0, 8.0, 0.0)));
        assert!(!is_plausible(&GeoOrigin::new(49.0, 200.0, 0.0)));
        assert!(!is_plausible(&GeoOrigin::new(49.0, 8.0, 1e6)));
    }
}
