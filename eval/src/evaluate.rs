//! The whole scoring of one sequence: rules, matching, CLEAR MOT, IDF1, HOTA.

use crate::{
    clear_mot::clear_mot,
    config::EvalConfig,
    events_csv::events_csv,
    gt::GroundTruth,
    hota::hota,
    idf1::identity,
    matching::{FrameEvents, match_frames},
    prepare::{ScoredFrame, prepare},
    report::{GtCounts, Metrics},
    tracks_csv::TrackRow,
};

/// Scores `tracks` against `gt` (eval-protocol.md): hypotheses outside the labelled view or
/// excused by the ignore rules leave the scoring; the rest are matched on BEV centre distance.
pub fn evaluate(gt: &GroundTruth, tracks: &[TrackRow], config: &EvalConfig) -> Metrics {
    score(gt, tracks, config).0
}

/// [`evaluate`], and every frame's matches, misses and false positives as CSV
/// ([`crate::events_csv`]).
pub fn evaluate_with_events(
    gt: &GroundTruth,
    tracks: &[TrackRow],
    config: &EvalConfig,
) -> (Metrics, String) {
    let (metrics, frames, events) = score(gt, tracks, config);
    (metrics, events_csv(&frames, &events))
}

/// The metrics, the scored frames and their events.
fn score(
    gt: &GroundTruth,
    tracks: &[TrackRow],
    config: &EvalConfig,
) -> (Metrics, Vec<ScoredFrame>, Vec<FrameEvents>) {
    let (frames, excused) = prepare(gt, tracks, config);
    let events = match_frames(&frames);
    let metrics = Metrics {
        clear: clear_mot(&events),
        identity: identity(&frames),
        hota: hota(&frames),
        ground_truth: GtCounts::of(gt),
        hypotheses_excused: excused,
        config: *config,
    };
    (metrics, frames, events)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gt::{GtFrame, GtObject};

    fn rider(id: u64, y: f64) -> GtObject {
        GtObject {
            id,
            class: "Cyclist".to_string(),
            centre: [15.0, y, -0.9],
        }
    }

    fn track(frame: u32, id: u64, y: f64) -> TrackRow {
        TrackRow {
            frame,
            track_id: id,
            centre: [15.0, y, -0.9],
            size: [1.8, 0.6, 1.7],
            yaw: 0.0,
            velocity: [0.0, 0.0],
            confidence: 1.0,
            class: "cyclist".to_string(),
        }
    }

    /// Two riders side by side 1 m apart; from frame 5 on the tracks swap riders.
    fn swapped_riders() -> (GroundTruth, Vec<TrackRow>) {
        let frames = (0..10)
            .map(|frame| GtFrame {
                frame,
                objects: vec![rider(1, 0.0), rider(2, 1.0)],
                ..GtFrame::default()
            })
            .collect();
        let gt = GroundTruth {
            frames,
            ..GroundTruth::default()
        };
        let tracks = (0..10)
            .flat_map(|frame| {
                let (a, b) = if frame < 5 {
                    (0.05, 0.95)
                } else {
                    (0.95, 0.05)
                };
                [track(frame, 7, a), track(frame, 8, b)]
            })
            .collect();
        (gt, tracks)
    }

    #[test]
    fn a_swap_between_riders_1_m_apart_shows_only_at_the_cyclist_threshold() {
        let (gt, tracks) = swapped_riders();
        // At 2 m the swapped tracks are still within reach of their old riders: no switch, but
        // the matched distance grows to 0.95 m.
        let loose = evaluate(&gt, &tracks, &EvalConfig::default());
        assert_eq!(loose.clear.switches, 0);
        assert!((loose.clear.motp - 0.5).abs() < 1e-12);
        // At 0.6 m for cyclists each rider switches track once.
        let config = EvalConfig {
            threshold: 2.0,
            cyclist_threshold: Some(0.6),
        };
        let strict = evaluate(&gt, &tracks, &config);
        assert_eq!(strict.clear.switches, 2);
        assert_eq!((strict.clear.false_positives, strict.clear.misses), (0, 0));
        assert!((strict.clear.mota - (1.0 - 2.0 / 20.0)).abs() < 1e-12);
        assert!((strict.identity.idf1 - 0.5).abs() < 1e-12);
        assert_eq!(strict.config, config);
    }
}
