//! One world view from this vehicle's tracks and the fleet's latest super frames.
//!
//! Observations are grouped vehicle by vehicle (own first, then remote vehicles by id): each
//! group is matched one-to-one, nearest pair first, to the objects fused so far within the
//! gate; what stays unmatched becomes a new object. So an object two vehicles see is one
//! object with two sources, and an object only a remote vehicle sees (occluded here, or out
//! of range) still appears, with that vehicle as its source.

use nalgebra::{Vector2, Vector3};

use crate::ObjectClass;

/// One observation of an object by one vehicle, in the fleet's world frame, brought to the
/// present.
#[derive(Clone, Debug, PartialEq)]
pub struct Observation {
    /// The observing vehicle.
    pub vehicle: String,
    /// Its track id there.
    pub track: u64,
    /// Class.
    pub class: ObjectClass,
    /// Box centre (m).
    pub center: Vector3<f64>,
    /// Length, width, height (m).
    pub size: Vector3<f64>,
    /// Heading (rad).
    pub yaw: f64,
    /// Ground velocity (m/s).
    pub velocity: Vector2<f64>,
    /// Confidence in [0, 1].
    pub confidence: f32,
    /// How long ago it was made (ms, service clock).
    pub age_ms: u64,
}

/// An object of the fused view.
#[derive(Clone, Debug, PartialEq)]
pub struct FusedObject {
    /// The vehicle and track id of its first observation (own track when this vehicle sees it).
    pub anchor: (String, u64),
    /// Class: that of the most confident observation that names one.
    pub class: ObjectClass,
    /// Confidence-weighted mean centre (m).
    pub center: Vector3<f64>,
    /// Extents of the most confident observation (m).
    pub size: Vector3<f64>,
    /// Heading of the most confident observation (rad).
    pub yaw: f64,
    /// Confidence-weighted mean velocity (m/s).
    pub velocity: Vector2<f64>,
    /// 1 − Π(1 − cᵢ): the chance at least one source is right, sources taken as independent.
    pub confidence: f32,
    /// Observing vehicles, in grouping order.
    pub sources: Vec<String>,
    /// Age of the freshest observation (ms).
    pub age_ms: u64,
}

/// Accumulates one fused object.
struct Accumulator {
    fused: FusedObject,
    weight: f64,
    best_confidence: f32,
    class_confidence: f32,
    miss_product: f64,
}

impl Accumulator {
    fn new(o: &Observation) -> Self {
        let weight = weight(o);
        Self {
            fused: FusedObject {
                anchor: (o.vehicle.clone(), o.track),
                class: o.class,
                center: o.center,
                size: o.size,
                yaw: o.yaw,
                velocity: o.velocity,
                confidence: o.confidence,
                sources: vec![o.vehicle.clone()],
                age_ms: o.age_ms,
            },
            weight,
            best_confidence: o.confidence,
            class_confidence: if o.class == ObjectClass::Unknown {
                -1.0
            } else {
                o.confidence
            },
            miss_product: 1.0 - f64::from(o.confidence),
        }
    }

    fn add(&mut self, o: &Observation) {
        let w = weight(o);
        let total = self.weight + w;
        let f = &mut self.fused;
        f.center = (f.center * self.weight + o.center * w) / total;
        f.velocity = (f.velocity * self.weight + o.velocity * w) / total;
        self.weight = total;
        if o.confidence > self.best_confidence {
            self.best_confidence = o.confidence;
            f.size = o.size;
            f.yaw = o.yaw;
        }
        if o.class != ObjectClass::Unknown && o.confidence > self.class_confidence {
            self.class_confidence = o.confidence;
            f.class = o.class;
        }
        self.miss_product *= 1.0 - f64::from(o.confidence);
        f.confidence = (1.0 - self.miss_product) as f32;
        f.sources.push(o.vehicle.clone());
        f.age_ms = f.age_ms.min(o.age_ms);
    }
}

/// Weight of an observation in the means: its confidence, floored so zero-confidence
/// observations still count a little.
fn weight(o: &Observation) -> f64 {
    f64::from(o.confidence).max(1e-3)
}

fn compatible(a: ObjectClass, b: ObjectClass) -> bool {
    a == b || a == ObjectClass::Unknown || b == ObjectClass::Unknown
}

/// Fuses groups of observations (one group per vehicle, in the given order) into one view.
pub fn fuse(groups: &[Vec<Observation>], gate_m: f64) -> Vec<FusedObject> {
    let mut fused: Vec<Accumulator> = Vec::new();
    for group in groups {
        let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
        for (fi, acc) in fused.iter().enumerate() {
            for (oi, o) in group.iter().enumerate() {
                let d = (acc.fused.center.xy() - o.center.xy()).norm();
                if d <= gate_m
                    && compatible(acc.fused.class, o.class)
                    && !acc.fused.sources.contains(&o.vehicle)
                {
                    pairs.push((d, fi, oi));
                }
            }
        }
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut fused_taken = vec![false; fused.len()];
        let mut obs_taken = vec![false; group.len()];
        for (_, fi, oi) in pairs {
            if fused_taken[fi] || obs_taken[oi] {
                continue;
            }
            fused_taken[fi] = true;
            obs_taken[oi] = true;
            fused[fi].add(&group[oi]);
        }
        for (o, taken) in group.iter().zip(obs_taken) {
            if !taken {
                fused.push(Accumulator::new(o));
            }
        }
    }
    fused.into_iter().map(|a| a.fused).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn obs(vehicle: &str, track: u64, x: f64, y: f64, confidence: f32) -> Observation {
        Observation {
            vehicle: vehicle.into(),
            track,
            class: ObjectClass::Car,
            center: Vector3::new(x, y, 0.8),
            size: Vector3::new(4.0, 1.8, 1.5),
            yaw: 0.0,
            velocity: Vector2::zeros(),
            confidence,
            age_ms: 10,
        }
    }

    #[test]
    fn same_object_seen_twice_is_one_object_with_two_sources() {
        let view = fuse(
            &[
                vec![obs("a", 1, 10.0, 0.0, 0.9)],
                vec![obs("b", 7, 10.6, 0.0, 0.3)],
            ],
            2.0,
        );
        assert_eq!(view.len(), 1);
        let o = &view[0];
        assert_eq!(o.anchor, ("a".to_string(), 1));
        assert_eq!(o.sources, ["a", "b"]);
        // Weighted mean: (10 * 0.9 + 10.6 * 0.3) / 1.2 = 10.15.
        assert!((o.center.x - 10.15).abs() < 1e-6, "{}", o.center.x);
        assert!((o.confidence - 0.93).abs() < 1e-6, "{}", o.confidence);
    }

    #[test]
    fn object_only_a_remote_vehicle_sees_keeps_its_source() {
        let view = fuse(
            &[
                vec![obs("a", 1, 10.0, 0.0, 0.9)],
                vec![obs("b", 3, 10.2, 0.1, 0.8), obs("b", 4, 40.0, 5.0, 0.8)],
            ],
            2.0,
        );
        assert_eq!(view.len(), 2);
        let hidden = view.iter().find(|o| o.anchor.0 == "b").expect("b's object");
        assert_eq!(hidden.anchor.1, 4);
        assert_eq!(hidden.sources, ["b"]);
        assert_eq!(hidden.center.x, 40.0);
    }

    #[test]
    fn matching_is_one_to_one_nearest_first() {
        // Two own cars 1.5 m apart; one remote observation between them, nearer the second.
        let view = fuse(
            &[
                vec![obs("a", 1, 0.0, 0.0, 0.9), obs("a", 2, 1.5, 0.0, 0.9)],
                vec![obs("b", 9, 1.0, 0.0, 0.9)],
            ],
            2.0,
        );
        assert_eq!(view.len(), 2);
        assert_eq!(view[0].sources, ["a"]);
        assert_eq!(view[1].sources, ["a", "b"]);
    }

    #[test]
    fn incompatible_classes_and_far_objects_stay_apart() {
        let mut pedestrian = obs("b", 5, 10.0, 0.5, 0.9);
        pedestrian.class = ObjectClass::Pedestrian;
        let view = fuse(
            &[
                vec![obs("a", 1, 10.0, 0.0, 0.9)],
                vec![pedestrian, obs("b", 6, 13.0, 0.0, 0.9)],
            ],
            2.0,
        );
        assert_eq!(view.len(), 3);
    }

    #[test]
    fn an_unknown_class_takes_the_remote_class() {
        let mut own = obs("a", 1, 0.0, 0.0, 0.5);
        own.class = ObjectClass::Unknown;
        let view = fuse(&[vec![own], vec![obs("b", 2, 0.5, 0.0, 0.4)]], 2.0);
        assert_eq!(view.len(), 1);
        assert_eq!(view[0].class, ObjectClass::Car);
    }
}
