//! Static identity from many views: a distant standing person's upper body shows its width
//! only in some scans (the columns fall on the shoulders or between them), a post's never.
//! The tracker remembers the widest person-shaped view, so the person is reported in every
//! scan once confirmed and the post in none.

mod track_support;

use track_support::reported_per_scan;
use trackd_perception::Point;

/// A figure 30 m ahead, facing the sensor: a 0.3 m wide lower body up to 1.1 m and, from
/// 1.2 m to 1.7 m, an upper body seen in two columns `upper_width` apart (world frame, ground
/// at z = 0).
fn figure(upper_width: f64) -> Vec<Point> {
    let mut out = Vec::new();
    for row in 0..17 {
        let z = 0.1 + 0.1 * f64::from(row);
        let offsets: Vec<f64> = if z < 1.15 {
            vec![-0.15, -0.05, 0.05, 0.15]
        } else {
            vec![-upper_width / 2.0, upper_width / 2.0]
        };
        for y in offsets {
            out.push(Point::new(30.0, y as f32, z as f32, 0.0));
        }
    }
    out
}

/// Runs 30 scans at 10 Hz of one static figure whose upper width in scan k is
/// `upper_width(k)`; returns, per scan, whether a track is reported.
fn reported(upper_width: impl Fn(u32) -> f64) -> Vec<bool> {
    reported_per_scan(30, |k| figure(upper_width(k)))
}

#[test]
fn a_far_person_wide_in_some_views_is_reported_in_every_scan() {
    // 13 cm (one column's spacing at 40 m) in two scans of three, 26 cm in the third.
    let out = reported(|k| if k % 3 == 2 { 0.26 } else { 0.13 });
    assert!(out[5..].iter().all(|&r| r), "{out:?}");
}

#[test]
fn a_post_never_wider_than_a_column_is_never_reported() {
    let out = reported(|_| 0.13);
    assert!(out.iter().all(|&r| !r), "{out:?}");
}
