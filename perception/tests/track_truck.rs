//! A truck driving away, seen from behind only: its length never shows, so its centre is
//! placed with a truck's length once it is seen moving and as tall as a truck, not with a
//! car's (which would put it 2.5 m short of its true centre).

mod track_support;
mod view_support;

use nalgebra::{Isometry3, Vector2};
use track_support::{FLAT, flat_clusters};
use trackd_perception::Point;
use trackd_perception::track::{Ground, RecentViews, ScanContext, TrackConfig, Tracker};
use view_support::{SENSOR_Z, record_view};

/// The truck: 9.5 m long, 2.5 m wide, 3.3 m tall.
const LENGTH: f64 = 9.5;
const WIDTH: f64 = 2.5;
const HEIGHT: f64 = 3.3;

/// The rear face of the truck whose centre is `x` metres ahead (world frame, ground at z = 0).
fn rear(x: f64) -> Vec<Point> {
    let face = x - LENGTH / 2.0;
    let mut out = Vec::new();
    let rows = ((HEIGHT - 0.2) / 0.1).round() as i32;
    for row in 0..=rows {
        let z = 0.2 + 0.1 * f64::from(row);
        for i in 0..=(WIDTH / 0.1).round() as i32 {
            let y = -WIDTH / 2.0 + 0.1 * f64::from(i);
            out.push(Point::new(face as f32, y as f32, z as f32, 0.0));
        }
    }
    out
}

#[test]
fn a_truck_seen_from_behind_is_centred_with_a_trucks_length() {
    let mut tracker = Tracker::new(TrackConfig::default());
    let mut views = RecentViews::new(2.0);
    let ground = Ground::horizontal(0.0);
    let cdf = FLAT.cdf();
    let pose = Isometry3::translation(0.0, 0.0, SENSOR_Z);
    let mut errors = Vec::new();
    for k in 0..30 {
        let t = f64::from(k) * 0.1;
        let center = 15.0 + 8.0 * t;
        let points = rear(center);
        record_view(&mut views, t, pose, &points);
        let clouds = vec![points];
        let scan = ScanContext {
            timestamp: t,
            pose,
            ground: &ground,
            range_limit: f64::INFINITY,
            views: Some(&views),
        };
        tracker.step(&scan, &flat_clusters(&clouds, &cdf));
        let truth = Vector2::new(center, 0.0);
        let error = tracker
            .reported()
            .map(|tr| (tr.state().center.xy() - truth).norm())
            .fold(f64::INFINITY, f64::min);
        errors.push(error);
    }
    // Seen moving within its first second; from then on within 1 m of its true centre.
    assert!(
        errors[15..].iter().all(|&e| e < 1.0),
        "centre errors (m) per scan: {errors:.2?}"
    );
}
