//! Every threshold of the tracker.

use serde::{Deserialize, Serialize};

use super::classify::ClassifyConfig;
use super::confidence::ConfidenceConfig;
use super::dormant::DormantConfig;
use super::motion::{MeasurementNoise, ProcessNoise};

/// How clusters are associated with tracks: the paper's Algorithm 1 step by step, then what a
/// real tracker adds. Each mode includes the ones before it (the README's ablation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AssociationMode {
    /// χ² test on the VFHs; the candidate with the lowest distance wins.
    Chi2,
    /// χ² test, then the maximum deviation test (MDT) between CDFs picks among several
    /// candidates.
    Chi2Mdt,
    /// χ², MDT, and MDT ties go to the motion model (the paper's Algorithm 1 in full).
    Chi2MdtMotion,
    /// A spatial gate on the motion model's prediction before the χ² test, then one global
    /// one-to-one assignment on a cost mixing the gate distance and the histogram scores.
    #[default]
    GatedAssignment,
}

/// Parameters of the association.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AssociationConfig {
    /// Which steps run. Default `gated_assignment`.
    pub mode: AssociationMode,
    /// χ² histogram distance a candidate must stay below (the paper's test). Default 1.0.
    pub chi2_threshold: f64,
    /// MDT scores (1 − max CDF deviation) within this of the best are tied. Default 0.02.
    pub mdt_tie_tolerance: f64,
    /// Gate on the squared Mahalanobis distance of a box centre from the prediction (χ², 2
    /// degrees of freedom; 13.8 keeps 99.9 %). Default 13.8.
    pub gate: f64,
    /// Weight of the χ² histogram distance in the assignment cost. Default 2.0.
    pub chi2_weight: f64,
    /// Weight of the max CDF deviation in the assignment cost. Default 2.0.
    pub mdt_weight: f64,
    /// A cluster longer than this many times the track's length, plus 1 m, is another object
    /// (a van next to the pole a track was born on); for a track identified as a pedestrian,
    /// so is one longer than `classify.pedestrian_max_length` plus 1 m. Default 2.0.
    pub size_gate: f64,
    /// Added to the assignment cost of a view judged structure that the track's class does
    /// not show of itself: any structure for a pedestrian or a cyclist, a tree or foliage for
    /// a car (a pole's view no object's track takes at all). Such a view may still be the
    /// track's (a person under a tree), but not when the object's own view lies nearby. On
    /// the simulated drives of seeds 1-3, 2.5-4 gave mean MOTA 91.65-91.69 %, 2 and 5 gave
    /// 91.59 and 91.45 % (91.65 % without the cost). Default 3.0.
    pub unlike_structure_cost: f64,
}

impl Default for AssociationConfig {
    fn default() -> Self {
        Self {
            mode: AssociationMode::GatedAssignment,
            chi2_threshold: 1.0,
            mdt_tie_tolerance: 0.02,
            gate: 13.8,
            chi2_weight: 2.0,
            mdt_weight: 2.0,
            size_gate: 2.0,
            unlike_structure_cost: 3.0,
        }
    }
}

/// Parameters of the motion EKF.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MotionConfig {
    /// White-noise acceleration in the ground plane (m/s²). Default 3.0.
    pub accel: f64,
    /// Random walk of the height (m/√s). Default 0.3.
    pub z_walk: f64,
    /// Random walk of the heading (rad/√s). Default 0.5.
    pub yaw_walk: f64,
    /// Standard deviation of a box centre, m, at 0 m range... Default 0.25.
    pub position_sigma: f64,
    /// ...plus this per metre of range. Default 0.01.
    pub position_sigma_per_metre: f64,
    /// Standard deviation of a box's height, m. Default 0.3.
    pub z_sigma: f64,
    /// Standard deviation of a box's heading, rad. Default 0.3.
    pub yaw_sigma: f64,
    /// Velocity uncertainty at birth (m/s, per axis) of a car-sized cluster: a car may be
    /// first seen at highway speed. Default 15.
    pub birth_velocity_sigma_car: f64,
    /// ... of a cyclist-sized cluster. Default 6.
    pub birth_velocity_sigma_cyclist: f64,
    /// ... of a pedestrian-sized or unidentified cluster. Default 2.5.
    pub birth_velocity_sigma_pedestrian: f64,
    /// A pedestrian track takes no view farther from where it was last seen than this speed
    /// (m/s) allows since then... Default 3 (a jog; walking is 1-2).
    pub pedestrian_max_speed: f64,
    /// ...plus this much (m) for the error of the two box centres. Default 1.
    pub pedestrian_reach_margin: f64,
    /// A parked car's track takes no view lying outside its box by more than a car pulling
    /// out at this acceleration (m/s²) covers since it was last seen... Default 3.
    pub parked_max_acceleration: f64,
    /// ...plus this much (m). Default 1.
    pub parked_reach_margin: f64,
    /// A track faster than this (m/s), and known to be, is headed along its velocity.
    /// Default 1.5.
    pub heading_from_velocity_speed: f64,
}

impl Default for MotionConfig {
    fn default() -> Self {
        Self {
            accel: 3.0,
            z_walk: 0.3,
            yaw_walk: 0.5,
            position_sigma: 0.25,
            position_sigma_per_metre: 0.01,
            z_sigma: 0.3,
            yaw_sigma: 0.3,
            birth_velocity_sigma_car: 15.0,
            birth_velocity_sigma_cyclist: 6.0,
            birth_velocity_sigma_pedestrian: 2.5,
            pedestrian_max_speed: 3.0,
            pedestrian_reach_margin: 1.0,
            parked_max_acceleration: 3.0,
            parked_reach_margin: 1.0,
            heading_from_velocity_speed: 1.5,
        }
    }
}

impl MotionConfig {
    /// The process noise.
    pub fn process_noise(&self) -> ProcessNoise {
        ProcessNoise {
            accel: self.accel,
            z_walk: self.z_walk,
            yaw_walk: self.yaw_walk,
        }
    }

    /// The noise of a box measured `range` metres from the sensor.
    pub fn measurement_noise(&self, range: f64) -> MeasurementNoise {
        MeasurementNoise {
            position: self.position_sigma + self.position_sigma_per_metre * range,
            z: self.z_sigma,
            yaw: self.yaw_sigma,
        }
    }
}

/// Everything the tracker needs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TrackConfig {
    /// Association.
    pub association: AssociationConfig,
    /// Motion model.
    pub motion: MotionConfig,
    /// Confidence decay.
    pub confidence: ConfidenceConfig,
    /// Ids of dropped static objects, given back when they are seen again.
    pub dormant: DormantConfig,
    /// Identification of objects and structure.
    pub classify: ClassifyConfig,
    /// Matches needed before a track is reported (M of "birth after M hits"). Default 1: an
    /// object identified in its first view is reported in it (every scan counts); it coasts
    /// through misses only once matched twice.
    pub birth_hits: u32,
    /// A confirmed track missed for at most this many scans is still reported at its
    /// predicted position (coasting through short occlusions), unless the scan sees through
    /// its box. Default 2.
    pub report_coasting_scans: u32,
    /// A parked track (see `Track::is_parked`: a parked car, or a person standing, held as
    /// such) missed for at most this many scans is still reported where it stands while the
    /// scans show that nothing is seen through its box: a parked car does not drive off
    /// unseen, and one hidden by a passing car or thinned out to a handful of returns at
    /// range is still there. Only where the scans' free space tells (tracking in the world
    /// frame). Default 4.
    pub report_parked_coasting_scans: u32,
    /// Split clusters DBSCAN merged: people a gap away peeled off, a cluster that holds
    /// the predicted boxes of several confirmed tracks shared out among them (two riders side
    /// by side), person-sized groups of newcomers peeled off large clusters (a pedestrian
    /// walking along a wall: see [`super::arrivals`]), and people standing by anything longer
    /// than a car peeled off it (see [`super::standing_peel`]). Default true.
    pub split_merged_clusters: bool,
    /// Weight of the new view in the smoothed size when it is smaller than the current
    /// estimate (partial views shrink slowly). Larger views count in full. Default 0.1.
    pub size_shrink_rate: f64,
}

impl Default for TrackConfig {
    fn default() -> Self {
        Self {
            association: AssociationConfig::default(),
            motion: MotionConfig::default(),
            confidence: ConfidenceConfig::default(),
            dormant: DormantConfig::default(),
            classify: ClassifyConfig::default(),
            birth_hits: 1,
            report_coasting_scans: 2,
            report_parked_coasting_scans: 4,
            split_merged_clusters: true,
            size_shrink_rate: 0.1,
        }
    }
}
