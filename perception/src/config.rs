//! The pipeline's one configuration: a section per stage, in pipeline order, every field with
//! a documented default (see each section's type), read from the `[perception]` table of
//! `trackd.toml`.

use serde::{Deserialize, Serialize};

use crate::cluster::ClusterConfig;
use crate::filter::FilterConfig;
use crate::ground::GroundConfig;
use crate::occupancy::OccupancyConfig;
use crate::pose::PoseConfig;
use crate::superframe::SuperFrameConfig;
use crate::track::TrackConfig;
use crate::vfh::VfhConfig;

/// Every threshold of the perception pipeline.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Config {
    /// Ego-pose EKF (IMU, GPS, velocity).
    pub pose: PoseConfig,
    /// Range band, crop and ego-vehicle box.
    pub filter: FilterConfig,
    /// RANSAC ground removal.
    pub ground: GroundConfig,
    /// DBSCAN.
    pub cluster: ClusterConfig,
    /// Viewpoint Feature Histograms.
    pub vfh: VfhConfig,
    /// Association, motion model, boxes, confidence, identification.
    pub track: TrackConfig,
    /// Log-odds voxel map.
    pub occupancy: OccupancyConfig,
    /// Super frames shared with the fleet.
    pub superframe: SuperFrameConfig,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_round_trip_through_toml_and_a_partial_file_keeps_them() {
        let text = toml::to_string(&Config::default()).expect("serialises");
        let back: Config = toml::from_str(&text).expect("parses");
        assert_eq!(back, Config::default());
        let partial: Config =
            toml::from_str("[track]\nbirth_hits = 3\n[track.association]\nmode = \"chi2\"\n")
                .expect("parses");
        assert_eq!(partial.track.birth_hits, 3);
        assert_eq!(
            partial.track.association.mode,
            crate::track::AssociationMode::Chi2
        );
        assert_eq!(partial.cluster, ClusterConfig::default());
        assert!(toml::from_str::<Config>("[track]\nno_such_key = 1\n").is_err());
    }
}
