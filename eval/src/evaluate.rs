//! The whole scoring of one sequence: rules, matching, CLEAR MOT, IDF1, HOTA.

use crate::{
    clear_mot::clear_mot,
    config::EvalConfig,
    gt::GroundTruth,
    hota::hota,
    idf1::identity,
    matching::match_frames,
    prepare::prepare,
    report::{GtCounts, Metrics},
    tracks_csv::TrackRow,
};

/// Scores `tracks` against `gt` (eval-protocol.md): hypotheses outside the labelled view or
/// excused by the ignore rules leave the scoring; the rest are matched on BEV centre distance.
pub fn evaluate(gt: &GroundTruth, tracks: &[TrackRow], config: &EvalConfig) -> Metrics {
    let (frames, excused) = prepare(gt, tracks, config);
    let events = match_frames(&frames);
    Metrics {
        clear: clear_mot(&events),
        identity: identity(&frames),
        hota: hota(&frames),
        ground_truth: GtCounts::of(gt),
        hypotheses_excused: excused,
        config: *config,
    }
}
