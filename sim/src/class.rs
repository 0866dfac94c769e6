//! Object classes of the ground truth, named as KITTI names them.

use rand::Rng;
use serde::{Deserialize, Serialize};
use trackd_perception::ObjectClass;

use crate::random::between;

/// The class of a ground-truth object (KITTI's names).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Class {
    /// Passenger car.
    Car,
    /// Van or minibus.
    Van,
    /// Lorry.
    Truck,
    /// A rider on a bicycle.
    Cyclist,
    /// A person on foot.
    Pedestrian,
}

impl Class {
    /// Every class.
    pub const ALL: [Self; 5] = [
        Self::Car,
        Self::Van,
        Self::Truck,
        Self::Cyclist,
        Self::Pedestrian,
    ];

    /// KITTI's name, as in `tracklet_labels.xml` and `gt_tracks.csv`.
    pub fn kitti_name(&self) -> &'static str {
        match self {
            Self::Car => "Car",
            Self::Van => "Van",
            Self::Truck => "Truck",
            Self::Cyclist => "Cyclist",
            Self::Pedestrian => "Pedestrian",
        }
    }

    /// The class of a KITTI name.
    pub fn from_kitti_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|c| c.kitti_name() == name)
    }

    /// The coarser class trackd reports.
    pub fn object_class(&self) -> ObjectClass {
        match self {
            Self::Car | Self::Van | Self::Truck => ObjectClass::Car,
            Self::Cyclist => ObjectClass::Cyclist,
            Self::Pedestrian => ObjectClass::Pedestrian,
        }
    }

    /// A plausible size (length, width, height in metres) for an object of this class.
    pub fn random_size<R: Rng + ?Sized>(&self, rng: &mut R) -> [f64; 3] {
        match self {
            Self::Car => [
                between(rng, 3.8, 4.8),
                between(rng, 1.65, 1.9),
                between(rng, 1.4, 1.6),
            ],
            Self::Van => [
                between(rng, 4.8, 5.8),
                between(rng, 1.9, 2.1),
                between(rng, 1.9, 2.4),
            ],
            Self::Truck => [
                between(rng, 7.5, 11.0),
                between(rng, 2.4, 2.55),
                between(rng, 3.0, 3.6),
            ],
            Self::Cyclist => [
                between(rng, 1.7, 1.9),
                between(rng, 0.55, 0.65),
                between(rng, 1.65, 1.85),
            ],
            Self::Pedestrian => [
                between(rng, 0.7, 0.9),
                between(rng, 0.55, 0.65),
                between(rng, 1.55, 1.9),
            ],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for c in Class::ALL {
            assert_eq!(Class::from_kitti_name(c.kitti_name()), Some(c));
        }
        assert_eq!(Class::from_kitti_name("Tram"), None);
    }
}
