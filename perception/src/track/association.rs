//! Frame-to-frame association: the paper's Algorithm 1, and the gated global assignment that
//! a real tracker adds to it.
//!
//! Algorithm 1, for each track on its own: every cluster whose VFH passes the χ² distance test
//! against the track's last VFH is a candidate; a single candidate is the match; among several,
//! the highest MDT score (1 − the maximum deviation between the CDFs) wins; MDT scores tied
//! within a tolerance go to the motion model (the likeliest position), once the track has a
//! velocity (from its third frame); no candidate is a miss. Nothing stops two tracks from
//! taking the same cluster: the paper's algorithm has no such rule.
//!
//! The gated assignment first keeps only the clusters inside the track's motion gate, applies
//! the χ² test to those, and then assigns clusters to tracks one-to-one, globally, minimising
//! the sum of costs `-log likelihood of the position + w₁ χ² + w₂ MDT-deviation`, plus a
//! fixed cost where the view is structure that the track's class does not show.

use super::assignment::{Assigner, Pair};
use super::config::{AssociationConfig, AssociationMode};

/// What association knows of one (track, cluster) pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairScore {
    /// The cluster.
    pub cluster: usize,
    /// χ² distance between the track's last VFH and the cluster's.
    pub chi2: f64,
    /// Maximum deviation between their CDFs (the MDT statistic; lower is more similar).
    pub max_deviation: f64,
    /// Squared Mahalanobis distance of the cluster's box centre from the track's prediction.
    pub mahalanobis2: f64,
    /// Negative log-likelihood of that centre under the prediction.
    pub nll: f64,
    /// The view is structure that the track's class does not show of itself (a tree's crown
    /// beside a pedestrian): the pair costs
    /// [`AssociationConfig::unlike_structure_cost`] more.
    pub unlike_structure: bool,
}

/// The pairs of one track and what its motion model can do.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TrackPairs {
    /// Scored pairs with clusters (all clusters in the paper's modes, gated ones otherwise).
    pub pairs: Vec<PairScore>,
    /// Whether the motion model has a velocity to break MDT ties with (third frame on).
    pub motion_ready: bool,
    /// `ln det S` of the track's position prediction (for the cost of a miss).
    pub log_det: f64,
}

/// The cluster of each track (`None`: no match).
pub fn associate(
    config: &AssociationConfig,
    tracks: &[TrackPairs],
    clusters: usize,
    assigner: &mut Assigner,
) -> Vec<Option<usize>> {
    match config.mode {
        AssociationMode::GatedAssignment => gated_assignment(config, tracks, clusters, assigner),
        mode => tracks
            .iter()
            .map(|t| algorithm_1(config, mode, t))
            .collect(),
    }
}

/// The paper's Algorithm 1 for one track, with the steps `mode` enables.
fn algorithm_1(
    config: &AssociationConfig,
    mode: AssociationMode,
    track: &TrackPairs,
) -> Option<usize> {
    let passes = |p: &&PairScore| p.chi2 < config.chi2_threshold;
    let lowest_chi2 = |a: &&PairScore, b: &&PairScore| a.chi2.total_cmp(&b.chi2);
    let candidates = || track.pairs.iter().filter(passes);
    let count = candidates().count();
    if count <= 1 || mode == AssociationMode::Chi2 {
        return candidates().min_by(lowest_chi2).map(|p| p.cluster);
    }
    let best_mdt = candidates()
        .map(|p| 1.0 - p.max_deviation)
        .fold(f64::NEG_INFINITY, f64::max);
    let tied =
        || candidates().filter(|p| 1.0 - p.max_deviation >= best_mdt - config.mdt_tie_tolerance);
    let pick = if mode == AssociationMode::Chi2MdtMotion && track.motion_ready {
        tied().min_by(|a, b| a.nll.total_cmp(&b.nll))
    } else {
        tied().min_by(lowest_chi2)
    };
    pick.map(|p| p.cluster)
}

/// Gate, χ² test, then one global assignment.
fn gated_assignment(
    config: &AssociationConfig,
    tracks: &[TrackPairs],
    clusters: usize,
    assigner: &mut Assigner,
) -> Vec<Option<usize>> {
    let mut pairs = Vec::new();
    let mut miss_costs = Vec::with_capacity(tracks.len());
    for (row, t) in tracks.iter().enumerate() {
        // Missing costs more than any admissible pair: a track always takes a gated
        // candidate unless another track wants it more.
        miss_costs.push(
            config.gate
                + t.log_det
                + config.chi2_weight * config.chi2_threshold
                + config.mdt_weight,
        );
        pairs.extend(
            t.pairs
                .iter()
                .filter(|p| p.mahalanobis2 <= config.gate && p.chi2 < config.chi2_threshold)
                .map(|p| Pair {
                    row,
                    col: p.cluster,
                    cost: p.nll
                        + config.chi2_weight * p.chi2
                        + config.mdt_weight * p.max_deviation
                        + if p.unlike_structure {
                            config.unlike_structure_cost
                        } else {
                            0.0
                        },
                }),
        );
    }
    assigner.assign(clusters, &pairs, &miss_costs)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pair(cluster: usize, chi2: f64, max_deviation: f64, d2: f64) -> PairScore {
        PairScore {
            cluster,
            chi2,
            max_deviation,
            mahalanobis2: d2,
            nll: d2,
            unlike_structure: false,
        }
    }

    fn config(mode: AssociationMode) -> AssociationConfig {
        AssociationConfig {
            mode,
            ..Default::default()
        }
    }

    fn run(mode: AssociationMode, tracks: &[TrackPairs], clusters: usize) -> Vec<Option<usize>> {
        associate(&config(mode), tracks, clusters, &mut Assigner::default())
    }

    #[test]
    fn a_single_candidate_is_the_match_and_none_is_a_miss() {
        let t = TrackPairs {
            pairs: vec![pair(0, 5.0, 0.1, 1.0), pair(1, 0.3, 0.4, 100.0)],
            motion_ready: true,
            log_det: 0.0,
        };
        for mode in [
            AssociationMode::Chi2,
            AssociationMode::Chi2Mdt,
            AssociationMode::Chi2MdtMotion,
        ] {
            assert_eq!(run(mode, std::slice::from_ref(&t), 2), vec![Some(1)]);
        }
        let none = TrackPairs {
            pairs: vec![pair(0, 5.0, 0.1, 1.0)],
            ..t
        };
        assert_eq!(run(AssociationMode::Chi2MdtMotion, &[none], 1), vec![None]);
    }

    #[test]
    fn mdt_picks_among_candidates_and_motion_breaks_ties() {
        // Cluster 0: lowest χ²; cluster 1: best MDT; cluster 2: MDT tied with 1 but near
        // the prediction.
        let t = TrackPairs {
            pairs: vec![
                pair(0, 0.1, 0.30, 50.0),
                pair(1, 0.4, 0.100, 40.0),
                pair(2, 0.5, 0.105, 0.5),
            ],
            motion_ready: true,
            log_det: 0.0,
        };
        let one = std::slice::from_ref(&t);
        assert_eq!(run(AssociationMode::Chi2, one, 3), vec![Some(0)]);
        assert_eq!(run(AssociationMode::Chi2Mdt, one, 3), vec![Some(1)]);
        assert_eq!(run(AssociationMode::Chi2MdtMotion, one, 3), vec![Some(2)]);
        // Before the third frame the motion model cannot break the tie.
        let young = TrackPairs {
            motion_ready: false,
            ..t
        };
        assert_eq!(
            run(AssociationMode::Chi2MdtMotion, &[young], 3),
            vec![Some(1)]
        );
    }

    #[test]
    fn the_paper_lets_two_tracks_share_a_cluster_the_assignment_does_not() {
        let a = TrackPairs {
            pairs: vec![pair(0, 0.1, 0.1, 1.0), pair(1, 0.2, 0.2, 2.0)],
            motion_ready: true,
            log_det: 0.0,
        };
        let b = TrackPairs {
            pairs: vec![pair(0, 0.1, 0.1, 0.5), pair(1, 0.3, 0.3, 9.0)],
            motion_ready: true,
            log_det: 0.0,
        };
        let both = [a, b];
        assert_eq!(
            run(AssociationMode::Chi2Mdt, &both, 2),
            vec![Some(0), Some(0)]
        );
        let assigned = run(AssociationMode::GatedAssignment, &both, 2);
        assert_eq!(assigned, vec![Some(1), Some(0)]);
    }

    #[test]
    fn structure_unlike_the_track_costs_more_than_a_farther_view() {
        let structure = PairScore {
            unlike_structure: true,
            ..pair(0, 0.1, 0.1, 0.5)
        };
        let t = TrackPairs {
            pairs: vec![structure, pair(1, 0.1, 0.1, 2.0)],
            motion_ready: true,
            log_det: 0.0,
        };
        assert_eq!(
            run(
                AssociationMode::GatedAssignment,
                std::slice::from_ref(&t),
                2
            ),
            vec![Some(1)]
        );
        // Alone, such a view is still taken.
        let alone = TrackPairs {
            pairs: vec![structure],
            ..t
        };
        assert_eq!(
            run(AssociationMode::GatedAssignment, &[alone], 1),
            vec![Some(0)]
        );
    }

    #[test]
    fn the_gate_and_chi2_test_bound_the_assignment() {
        let t = TrackPairs {
            pairs: vec![pair(0, 0.1, 0.1, 20.0), pair(1, 3.0, 0.1, 0.1)],
            motion_ready: true,
            log_det: 0.0,
        };
        assert_eq!(run(AssociationMode::GatedAssignment, &[t], 2), vec![None]);
    }
}
