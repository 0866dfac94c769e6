//! Whether two objects ever overlap during a drive: scenarios use it to place traffic,
//! pedestrians and vehicles that never drive through each other.

use nalgebra::Vector2;

use crate::actor::Actor;

/// Time step of the overlap check (seconds).
const STEP: f64 = 0.1;

/// Whether `a` and `b` come closer than `margin` metres (between their boxes seen from
/// above) at any time in [−1 s, `duration` + 1 s].
pub fn conflict(a: &Actor, b: &Actor, duration: f64, margin: f64) -> bool {
    let ra = a.size[0].hypot(a.size[1]) / 2.0;
    let rb = b.size[0].hypot(b.size[1]) / 2.0;
    let steps = ((duration + 2.0) / STEP).ceil() as usize;
    (0..=steps).any(|i| {
        let t = -1.0 + i as f64 * STEP;
        let (sa, sb) = (a.planar(t), b.planar(t));
        let d = (sa.pose.position - sb.pose.position).norm();
        d < ra + rb + margin
            && boxes_overlap(
                sa.pose.position,
                sa.pose.heading,
                [a.size[0] / 2.0 + margin, a.size[1] / 2.0 + margin],
                sb.pose.position,
                sb.pose.heading,
                [b.size[0] / 2.0, b.size[1] / 2.0],
            )
    })
}

/// Separating-axis test of two rectangles (centre, heading, half extents).
pub fn boxes_overlap(
    ca: Vector2<f64>,
    ya: f64,
    ha: [f64; 2],
    cb: Vector2<f64>,
    yb: f64,
    hb: [f64; 2],
) -> bool {
    let axes = |y: f64| {
        [
            Vector2::new(y.cos(), y.sin()),
            Vector2::new(-y.sin(), y.cos()),
        ]
    };
    let (aa, ab) = (axes(ya), axes(yb));
    let d = cb - ca;
    let radius = |axes: &[Vector2<f64>; 2], h: [f64; 2], n: &Vector2<f64>| {
        h[0] * axes[0].dot(n).abs() + h[1] * axes[1].dot(n).abs()
    };
    aa.iter()
        .chain(ab.iter())
        .all(|n| d.dot(n).abs() <= radius(&aa, ha, n) + radius(&ab, hb, n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::class::Class;
    use crate::material::Material;
    use crate::path::{Path, Pose2};
    use crate::speed::SpeedProfile;
    use crate::trajectory::Trajectory;

    #[test]
    fn rectangles() {
        let o = Vector2::zeros();
        assert!(boxes_overlap(
            o,
            0.0,
            [2.0, 1.0],
            Vector2::new(3.5, 0.0),
            0.0,
            [2.0, 1.0]
        ));
        assert!(!boxes_overlap(
            o,
            0.0,
            [2.0, 1.0],
            Vector2::new(4.5, 0.0),
            0.0,
            [2.0, 1.0]
        ));
        assert!(!boxes_overlap(
            o,
            0.0,
            [2.0, 1.0],
            Vector2::new(0.0, 2.1),
            0.0,
            [2.0, 1.0]
        ));
        // Turned by 90°, its length now reaches across.
        assert!(boxes_overlap(
            o,
            0.0,
            [2.0, 1.0],
            Vector2::new(0.0, 2.9),
            std::f64::consts::FRAC_PI_2,
            [2.0, 1.0]
        ));
    }

    #[test]
    fn crossing_cars_conflict_only_when_timed_to_meet() {
        let car = |id, start: Pose2, delay: f64| {
            let speed = SpeedProfile::starting(0.0)
                .hold(delay)
                .to(10.0, 100.0)
                .build();
            Actor::new(
                id,
                Class::Car,
                [4.5, 1.8, 1.5],
                Material::PAINT,
                Trajectory::new(Path::line(start, 200.0), speed),
            )
        };
        let east = car(1, Pose2::new(-50.0, 0.0, 0.0), 0.0);
        let north_same_time = car(2, Pose2::new(0.0, -50.0, std::f64::consts::FRAC_PI_2), 0.0);
        let north_later = car(3, Pose2::new(0.0, -50.0, std::f64::consts::FRAC_PI_2), 3.0);
        assert!(conflict(&east, &north_same_time, 10.0, 0.3));
        assert!(!conflict(&east, &north_later, 10.0, 0.3));
    }
}
