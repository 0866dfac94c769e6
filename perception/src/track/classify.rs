//! Training-free identification: objects (car, cyclist, pedestrian, other movable) versus
//! static structure (walls, buildings, poles, vegetation, guard rails, kerbs).
//!
//! Each observation of a cluster gets a [`ShapeVerdict`] from its size, its height profile
//! above the ground and the width of its upper part; a track accumulates the verdicts of its
//! observations as decaying votes and adds what one scan cannot show: whether it moves.
//! Structure is what is too tall, too long, floating, thin and tall (poles), top-heavy
//! (trees) or too low (kerbs); a static cluster that fits no object class is not reported,
//! and a moving one that fits none is "other movable".

use serde::{Deserialize, Serialize};

use crate::ObjectClass;

/// Size of a class: the prior a partial view is completed with.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClassSize {
    /// Length, m.
    pub length: f64,
    /// Width, m.
    pub width: f64,
    /// Height, m.
    pub height: f64,
}

/// Thresholds of the identification.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ClassifyConfig {
    /// Typical car. Default 4.5 × 1.8 × 1.6 m.
    pub car_size: ClassSize,
    /// Typical cyclist. Default 1.8 × 0.6 × 1.75 m.
    pub cyclist_size: ClassSize,
    /// Typical pedestrian. Default 0.8 × 0.6 × 1.75 m.
    pub pedestrian_size: ClassSize,
    /// Taller (top above ground, m) is structure: buildings, trees. Default 4.5.
    pub max_object_height: f64,
    /// Longer (m) is structure: walls, guard rails, hedges. Default 16.
    pub max_object_length: f64,
    /// Wider (shorter BEV side, m) is structure. Default 3.5.
    pub max_object_width: f64,
    /// A lowest point higher than this above the ground (m) floats: canopies, signs.
    /// Default 1.0.
    pub max_bottom_gap: f64,
    /// A top lower than this (m) is a kerb, a bollard, a low wall: cars are taller than
    /// 1.3 m, people than 1.2 m. Default 1.15.
    pub min_object_height: f64,
    /// Poles: a footprint narrower than this (m)... Default 0.45.
    pub pole_max_footprint: f64,
    /// ...and taller than this (m). Default 2.3.
    pub pole_min_height: f64,
    /// Trees: the upper third is this many times wider than the lower third... Default 2.0.
    pub tree_spread_ratio: f64,
    /// ...and the top is above this (m). Default 2.2.
    pub tree_min_height: f64,
    /// A person's upper body (top third of the cluster) is at most this wide (m); a car's
    /// roof and rear window are wider. Default 1.0.
    pub person_max_upper_width: f64,
    /// Longest BEV side (m) of a pedestrian. Default 1.3.
    pub pedestrian_max_length: f64,
    /// Longest BEV side (m) of a cyclist. Default 2.6.
    pub cyclist_max_length: f64,
    /// Shorter BEV side (m) of a person. Default 1.2.
    pub person_max_width: f64,
    /// Highest top (m) of a person. Default 2.1.
    pub person_max_height: f64,
    /// Highest lowest point (m) of a person: feet are on the ground. Default 0.6.
    pub person_max_bottom: f64,
    /// Shortest longer BEV side (m) of a person: thinner is a post. Default 0.25.
    pub person_min_length: f64,
    /// Highest lowest point (m) of a car: wheels are on the ground. Default 0.8.
    pub car_max_bottom: f64,
    /// Highest top (m) of a car or van; taller needs a truck's length. Default 2.6.
    pub car_max_height: f64,
    /// Highest top (m) of a car whose top is cut by the field of view: the cut passes below a
    /// van's roof only within about 10 m of the sensor; a taller cut object is a tree or a
    /// building. Default 2.1.
    pub car_max_truncated_top: f64,
    /// Shortest visible length (m) of something taller than a car: a truck. Default 6.5.
    pub truck_min_length: f64,
    /// A car's upper third (roof, windows) is at least this fraction of its lower third's
    /// extent; less is a hedge, a bicycle stand, a fence with a post. Default 0.4.
    pub car_min_upper_ratio: f64,
    /// Upper edge of the LiDAR's vertical field of view (degrees above horizontal): a cluster
    /// whose top reaches it may be taller than it looks. Default 2.0 (HDL-64E).
    pub sensor_upper_fov_deg: f64,
    /// A top within this (degrees) of the upper edge is cut by it. Default 0.4.
    pub truncation_tolerance_deg: f64,
    /// A track whose box moved farther than this from where it was born (m)... Default 2.0.
    pub moving_min_displacement: f64,
    /// ...at a speed above this (m/s) moves. Default 1.0.
    pub moving_min_speed: f64,
    /// Weight of the past in the class votes, per observation. Default 0.9.
    pub vote_memory: f32,
}

impl Default for ClassifyConfig {
    fn default() -> Self {
        Self {
            car_size: ClassSize {
                length: 4.5,
                width: 1.8,
                height: 1.6,
            },
            cyclist_size: ClassSize {
                length: 1.8,
                width: 0.6,
                height: 1.75,
            },
            pedestrian_size: ClassSize {
                length: 0.8,
                width: 0.6,
                height: 1.75,
            },
            max_object_height: 4.5,
            max_object_length: 16.0,
            max_object_width: 3.5,
            max_bottom_gap: 1.0,
            min_object_height: 1.15,
            pole_max_footprint: 0.45,
            pole_min_height: 2.3,
            tree_spread_ratio: 2.0,
            tree_min_height: 2.2,
            person_max_upper_width: 1.0,
            pedestrian_max_length: 1.3,
            cyclist_max_length: 2.6,
            person_max_width: 1.2,
            person_max_height: 2.1,
            person_max_bottom: 0.6,
            person_min_length: 0.25,
            car_max_bottom: 0.8,
            car_max_height: 2.6,
            car_max_truncated_top: 2.1,
            truck_min_length: 6.5,
            car_min_upper_ratio: 0.4,
            sensor_upper_fov_deg: 2.0,
            truncation_tolerance_deg: 0.4,
            moving_min_displacement: 2.0,
            moving_min_speed: 1.0,
            vote_memory: 0.9,
        }
    }
}

impl ClassifyConfig {
    /// The size prior of `class` (`None` for classes without one).
    pub fn size_of(&self, class: ObjectClass) -> Option<ClassSize> {
        match class {
            ObjectClass::Car => Some(self.car_size),
            ObjectClass::Cyclist => Some(self.cyclist_size),
            ObjectClass::Pedestrian => Some(self.pedestrian_size),
            ObjectClass::Unknown | ObjectClass::OtherMovable => None,
        }
    }
}

/// What one view of a cluster shows of its shape.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShapeFeatures {
    /// Longer visible BEV side (m).
    pub length: f64,
    /// Shorter visible BEV side (m).
    pub width: f64,
    /// Highest point above the ground (m).
    pub top: f64,
    /// Lowest point above the ground (m).
    pub bottom: f64,
    /// Widest BEV extent of the points in the upper third of the cluster's height (m).
    pub upper_width: f64,
    /// Widest BEV extent of the points in the lower third (m).
    pub lower_width: f64,
    /// Whether the top reaches the upper edge of the sensor's field of view (the object may
    /// be taller than seen).
    pub truncated: bool,
}

/// Why a view is static structure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StructureKind {
    /// Taller than any object: a building, a tree.
    TooTall,
    /// Longer or wider than any object: a wall, a guard rail, a hedge.
    TooLarge,
    /// Its lowest point is far above the ground: a canopy, a sign.
    Floating,
    /// Lower than any object: a kerb, a bollard.
    TooLow,
    /// Thin and tall.
    Pole,
    /// Much wider at the top than at the bottom.
    Tree,
}

/// The verdict on one view of a cluster.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeVerdict {
    /// Static structure.
    Structure(StructureKind),
    /// Shaped like an object of this class.
    Object(ObjectClass),
    /// Neither clearly structure nor shaped like a known object class.
    Unknown,
}

/// The verdict on one view.
pub fn classify_shape(f: &ShapeFeatures, c: &ClassifyConfig) -> ShapeVerdict {
    use ShapeVerdict::{Object, Structure};
    use StructureKind::*;
    if f.top > c.max_object_height {
        return Structure(TooTall);
    }
    if f.length > c.max_object_length || f.width > c.max_object_width {
        return Structure(TooLarge);
    }
    if f.bottom > c.max_bottom_gap {
        return Structure(Floating);
    }
    if f.top < c.min_object_height {
        return Structure(TooLow);
    }
    if f.length < c.pole_max_footprint && f.top > c.pole_min_height {
        return Structure(Pole);
    }
    if f.top > c.tree_min_height && f.upper_width > c.tree_spread_ratio * f.lower_width.max(0.2) {
        return Structure(Tree);
    }
    let person_shaped = f.upper_width <= c.person_max_upper_width
        && f.width <= c.person_max_width
        && f.length >= c.person_min_length
        && f.top <= c.person_max_height
        && f.bottom <= c.person_max_bottom;
    // A person-sized top cut by the field of view: a trunk or a post as likely as a person.
    if person_shaped && !f.truncated {
        if f.length <= c.pedestrian_max_length {
            return Object(ObjectClass::Pedestrian);
        }
        if f.length <= c.cyclist_max_length {
            return Object(ObjectClass::Cyclist);
        }
    }
    let car_shaped = !person_shaped
        && (f.length > c.pedestrian_max_length || f.width > c.person_max_width)
        && f.bottom <= c.car_max_bottom
        && f.upper_width >= c.car_min_upper_ratio * f.lower_width
        && (f.length >= c.truck_min_length
            || f.top
                <= if f.truncated {
                    c.car_max_truncated_top
                } else {
                    c.car_max_height
                });
    if car_shaped {
        return Object(ObjectClass::Car);
    }
    ShapeVerdict::Unknown
}

/// A track's accumulated evidence of what it is.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ClassVotes {
    car: f32,
    cyclist: f32,
    pedestrian: f32,
    unknown: f32,
    structure: f32,
}

impl ClassVotes {
    /// Adds the verdict of one more view; older views weigh `memory` times less each time.
    pub fn add(&mut self, verdict: ShapeVerdict, memory: f32) {
        for v in [
            &mut self.car,
            &mut self.cyclist,
            &mut self.pedestrian,
            &mut self.unknown,
            &mut self.structure,
        ] {
            *v *= memory;
        }
        match verdict {
            ShapeVerdict::Structure(_) => self.structure += 1.0,
            ShapeVerdict::Object(ObjectClass::Car) => self.car += 1.0,
            ShapeVerdict::Object(ObjectClass::Cyclist) => self.cyclist += 1.0,
            ShapeVerdict::Object(ObjectClass::Pedestrian) => self.pedestrian += 1.0,
            ShapeVerdict::Object(_) | ShapeVerdict::Unknown => self.unknown += 1.0,
        }
    }

    /// The object class the votes point to, or `None` (structure, or not identified).
    ///
    /// Structure outweighing everything else is structure, moving or not (the visible part of
    /// a wall slides along it as the vehicle passes). A static track is its most voted object
    /// class when object votes outweigh structure and unclear views; a moving one needs only
    /// to outweigh half the unclear views, and is "other movable" when it fits no class.
    pub fn identity(&self, moving: bool) -> Option<ObjectClass> {
        let objects = self.car + self.cyclist + self.pedestrian;
        if self.structure >= objects + self.unknown {
            return None;
        }
        let best = [
            (self.car, ObjectClass::Car),
            (self.cyclist, ObjectClass::Cyclist),
            (self.pedestrian, ObjectClass::Pedestrian),
        ]
        .into_iter()
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .filter(|(v, _)| *v > 0.0)
        .map(|(_, class)| class);
        if moving {
            if objects >= 0.5 * self.unknown {
                return best;
            }
            return Some(ObjectClass::OtherMovable);
        }
        if self.structure >= objects || self.unknown > objects {
            return None;
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn features(length: f64, width: f64, top: f64, upper: f64, lower: f64) -> ShapeFeatures {
        ShapeFeatures {
            length,
            width,
            top,
            bottom: 0.25,
            upper_width: upper,
            lower_width: lower,
            truncated: false,
        }
    }

    #[test]
    fn tells_objects_by_size_and_upper_body() {
        let c = ClassifyConfig::default();
        let v = |f| classify_shape(&f, &c);
        // A car from the side, from behind, and in a corner view.
        assert_eq!(
            v(features(4.4, 0.3, 1.5, 3.0, 4.4)),
            ShapeVerdict::Object(ObjectClass::Car)
        );
        assert_eq!(
            v(features(1.8, 0.3, 1.5, 1.5, 1.8)),
            ShapeVerdict::Object(ObjectClass::Car)
        );
        assert_eq!(
            v(features(4.0, 1.7, 1.5, 2.5, 4.0)),
            ShapeVerdict::Object(ObjectClass::Car)
        );
        // A cyclist from the side: 1.8 m long, but its upper body is narrow.
        assert_eq!(
            v(features(1.8, 0.4, 1.8, 0.5, 1.8)),
            ShapeVerdict::Object(ObjectClass::Cyclist)
        );
        assert_eq!(
            v(features(0.7, 0.5, 1.75, 0.45, 0.6)),
            ShapeVerdict::Object(ObjectClass::Pedestrian)
        );
        // A truck.
        assert_eq!(
            v(features(9.0, 2.5, 3.4, 8.0, 9.0)),
            ShapeVerdict::Object(ObjectClass::Car)
        );
    }

    #[test]
    fn tells_structure_by_shape() {
        let c = ClassifyConfig::default();
        let v = |f| classify_shape(&f, &c);
        use StructureKind::*;
        assert_eq!(
            v(features(30.0, 0.4, 3.0, 30.0, 30.0)),
            ShapeVerdict::Structure(TooLarge)
        );
        assert_eq!(
            v(features(8.0, 6.0, 8.0, 8.0, 8.0)),
            ShapeVerdict::Structure(TooTall)
        );
        assert_eq!(
            v(features(0.3, 0.3, 6.0, 0.3, 0.3)),
            ShapeVerdict::Structure(TooTall)
        );
        assert_eq!(
            v(features(0.3, 0.25, 3.5, 0.3, 0.3)),
            ShapeVerdict::Structure(Pole)
        );
        assert_eq!(
            v(features(4.0, 3.0, 4.0, 4.0, 0.5)),
            ShapeVerdict::Structure(Tree)
        );
        assert_eq!(
            v(features(6.0, 0.3, 0.4, 6.0, 6.0)),
            ShapeVerdict::Structure(TooLow)
        );
        let floating = ShapeFeatures {
            bottom: 2.5,
            ..features(2.0, 1.0, 3.5, 2.0, 2.0)
        };
        assert_eq!(v(floating), ShapeVerdict::Structure(Floating));
    }

    #[test]
    fn odd_shapes_are_not_objects() {
        let c = ClassifyConfig::default();
        let v = |f| classify_shape(&f, &c);
        // A thin post at pedestrian height.
        assert_eq!(
            v(features(0.15, 0.08, 1.8, 0.1, 0.1)),
            ShapeVerdict::Unknown
        );
        // A person-sized trunk whose top is cut by the field of view.
        let trunk = ShapeFeatures {
            truncated: true,
            ..features(0.9, 0.6, 2.05, 0.6, 0.7)
        };
        assert_eq!(v(trunk), ShapeVerdict::Unknown);
        // Car-sized but 2.9 m tall and short: a kiosk, a hedge, a tree's lower canopy.
        assert_eq!(v(features(3.5, 1.7, 2.9, 3.2, 1.6)), ShapeVerdict::Unknown);
        // Car-sized but bottom-heavy: a bicycle stand with a post.
        assert_eq!(v(features(4.3, 1.4, 1.8, 0.8, 3.9)), ShapeVerdict::Unknown);
    }

    #[test]
    fn votes_need_a_majority_for_an_object_and_motion_overrides_size() {
        let mut votes = ClassVotes::default();
        assert_eq!(votes.identity(false), None);
        votes.add(ShapeVerdict::Object(ObjectClass::Car), 0.9);
        votes.add(ShapeVerdict::Object(ObjectClass::Car), 0.9);
        votes.add(ShapeVerdict::Structure(StructureKind::TooLarge), 0.9);
        assert_eq!(votes.identity(false), Some(ObjectClass::Car));
        votes.add(ShapeVerdict::Structure(StructureKind::TooLarge), 0.9);
        votes.add(ShapeVerdict::Structure(StructureKind::TooLarge), 0.9);
        assert_eq!(votes.identity(false), None);
        // Something that keeps moving is an object even if its shape is odd.
        let mut odd = ClassVotes::default();
        for _ in 0..5 {
            odd.add(ShapeVerdict::Unknown, 0.9);
        }
        assert_eq!(odd.identity(false), None);
        assert_eq!(odd.identity(true), Some(ObjectClass::OtherMovable));
        // A wall whose visible part slides along it looks like it moves: still structure.
        let mut wall = ClassVotes::default();
        for _ in 0..5 {
            wall.add(ShapeVerdict::Structure(StructureKind::TooLarge), 0.9);
        }
        wall.add(ShapeVerdict::Unknown, 0.9);
        assert_eq!(wall.identity(true), None);
        // Recent views weigh more: a cyclist first seen merged with a bush.
        let mut recent = ClassVotes::default();
        for _ in 0..3 {
            recent.add(ShapeVerdict::Object(ObjectClass::Car), 0.7);
        }
        for _ in 0..5 {
            recent.add(ShapeVerdict::Object(ObjectClass::Cyclist), 0.7);
        }
        assert_eq!(recent.identity(true), Some(ObjectClass::Cyclist));
    }
}
