//! What a track is, from the verdicts on its views: each view votes for a class, for clutter
//! or for structure, older views weighing less, and the votes give the track's identity.

use super::classify::ShapeVerdict;
use crate::ObjectClass;

/// A track's accumulated evidence of what it is.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ClassVotes {
    /// Votes of `Object` verdicts: car, cyclist, pedestrian.
    sure: [f32; 3],
    /// Votes of `Movable` verdicts: car, cyclist, pedestrian.
    movable: [f32; 3],
    unknown: f32,
    structure: f32,
}

/// The classes votes are kept for, in vote order.
const VOTED: [ObjectClass; 3] = [
    ObjectClass::Car,
    ObjectClass::Cyclist,
    ObjectClass::Pedestrian,
];

/// The vote slot of `class`.
fn slot(class: ObjectClass) -> Option<usize> {
    VOTED.iter().position(|c| *c == class)
}

impl ClassVotes {
    /// Adds the verdict of one more view; older views weigh `memory` times less each time.
    pub fn add(&mut self, verdict: ShapeVerdict, memory: f32) {
        for v in self
            .sure
            .iter_mut()
            .chain(&mut self.movable)
            .chain([&mut self.unknown, &mut self.structure])
        {
            *v *= memory;
        }
        match verdict {
            ShapeVerdict::Structure(_) => self.structure += 1.0,
            ShapeVerdict::Object(class) => match slot(class) {
                Some(k) => self.sure[k] += 1.0,
                None => self.unknown += 1.0,
            },
            ShapeVerdict::Movable(class) => match slot(class) {
                Some(k) => self.movable[k] += 1.0,
                None => self.unknown += 1.0,
            },
            ShapeVerdict::Unknown => self.unknown += 1.0,
        }
    }

    /// Whether a static track once identified as `class` may stay so: views shaped like it
    /// still outweigh those shaped like another class, and structure does not outweigh them.
    /// Seen from farther, a parked car's views turn partial (unclear, too low, floating), not
    /// into another thing.
    pub fn may_hold(&self, class: ObjectClass) -> bool {
        let Some(k) = slot(class) else {
            return false;
        };
        let sure: f32 = self.sure.iter().sum();
        self.sure.iter().all(|&v| v <= self.sure[k]) && self.structure < sure
    }

    /// The object class the votes point to, or `None` (structure, or not identified).
    ///
    /// Structure outweighing everything else is structure, moving or not. A static track is
    /// its most voted class when views shaped like nothing static outweigh the others; a
    /// moving one counts the views shaped like clutter too and needs to outweigh only half the
    /// unclear views. A moving track shaped like no class is not identified: the strips a
    /// grazing wall breaks into at range slide along with the sensor.
    pub fn identity(&self, moving: bool) -> Option<ObjectClass> {
        let sure: f32 = self.sure.iter().sum();
        let movable: f32 = self.movable.iter().sum();
        if self.structure >= sure + movable + self.unknown {
            return None;
        }
        let best = |votes: [f32; 3]| {
            (0..3)
                .max_by(|&a, &b| votes[a].total_cmp(&votes[b]))
                .filter(|&k| votes[k] > 0.0)
                .map(|k| VOTED[k])
        };
        if moving {
            let all = [0, 1, 2].map(|k| self.sure[k] + self.movable[k]);
            if sure + movable >= 0.5 * self.unknown {
                return best(all);
            }
            return None;
        }
        if self.structure >= sure || self.unknown + movable > sure {
            return None;
        }
        best(self.sure)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::track::classify::StructureKind;

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
        // Something that moves but never looks like an object is not one (the strips of a
        // grazing wall slide along with the sensor); with a few views shaped like a class it is.
        let mut odd = ClassVotes::default();
        for _ in 0..5 {
            odd.add(ShapeVerdict::Unknown, 0.9);
        }
        assert_eq!(odd.identity(false), None);
        assert_eq!(odd.identity(true), None);
        for _ in 0..3 {
            odd.add(ShapeVerdict::Movable(ObjectClass::Car), 0.9);
        }
        assert_eq!(odd.identity(true), Some(ObjectClass::Car));
        // A wall whose visible part slides along it looks like it moves: still structure.
        let mut wall = ClassVotes::default();
        for _ in 0..5 {
            wall.add(ShapeVerdict::Structure(StructureKind::TooLarge), 0.9);
        }
        wall.add(ShapeVerdict::Unknown, 0.9);
        assert_eq!(wall.identity(true), None);
        // A post never seen moving is not a pedestrian; a walker is.
        let mut post = ClassVotes::default();
        for _ in 0..10 {
            post.add(ShapeVerdict::Movable(ObjectClass::Pedestrian), 0.9);
        }
        assert_eq!(post.identity(false), None);
        assert_eq!(post.identity(true), Some(ObjectClass::Pedestrian));
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

    #[test]
    fn an_identified_car_holds_through_unclear_views_not_through_structure() {
        let mut votes = ClassVotes::default();
        for _ in 0..5 {
            votes.add(ShapeVerdict::Object(ObjectClass::Car), 0.9);
        }
        let mut unclear = votes;
        for _ in 0..8 {
            unclear.add(ShapeVerdict::Unknown, 0.9);
        }
        assert_eq!(unclear.identity(false), None);
        assert!(unclear.may_hold(ObjectClass::Car));
        assert!(!unclear.may_hold(ObjectClass::Pedestrian));
        let mut walls = votes;
        for _ in 0..8 {
            walls.add(ShapeVerdict::Structure(StructureKind::TooLarge), 0.9);
        }
        assert!(!walls.may_hold(ObjectClass::Car));
    }
}
