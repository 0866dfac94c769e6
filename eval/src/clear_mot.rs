//! CLEAR MOT (Bernardin & Stiefelhagen 2008) counted from the match events exactly as
//! py-motmetrics' `metrics.py` counts them.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::matching::{Event, FrameEvents};

/// CLEAR MOT metrics and the counts behind them.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ClearMot {
    /// 1 − (misses + switches + false positives) / GT objects.
    pub mota: f64,
    /// Mean BEV distance of matched pairs, switches included (metres).
    pub motp: f64,
    /// Matched pairs over GT objects.
    pub recall: f64,
    /// Matched pairs over hypotheses.
    pub precision: f64,
    /// Matches that kept the object's hypothesis.
    pub matches: usize,
    /// ID switches: matches to another hypothesis than the object's last one.
    #[serde(rename = "idsw")]
    pub switches: usize,
    /// False positives: unmatched hypotheses.
    #[serde(rename = "fp")]
    pub false_positives: usize,
    /// Misses (false negatives): unmatched GT objects.
    #[serde(rename = "fn")]
    pub misses: usize,
    /// Fragmentations: times an object's matching is interrupted by misses and later resumes.
    #[serde(rename = "frag")]
    pub fragmentations: usize,
    /// Objects matched in at least 80 % of their frames.
    pub mostly_tracked: usize,
    /// Objects matched in 20 % to 80 % of their frames.
    pub partially_tracked: usize,
    /// Objects matched in less than 20 % of their frames.
    pub mostly_lost: usize,
    /// GT objects over all frames.
    pub num_objects: usize,
    /// Hypotheses over all frames.
    pub num_predictions: usize,
    /// Distinct GT object ids.
    pub num_unique_objects: usize,
    /// Frames scored.
    pub num_frames: usize,
}

/// Per-object state while counting.
#[derive(Default)]
struct ObjectHistory {
    /// Frames in which the object appears.
    frames: usize,
    /// Frames in which it was matched (switches included).
    tracked: usize,
    /// It has been matched at least once.
    started: bool,
    /// It is in a run of misses after having been matched.
    interrupted: bool,
    /// Runs of misses followed by a match.
    fragmentations: usize,
}

/// Counts CLEAR MOT from the match events of every frame, in frame order.
pub fn clear_mot(frames: &[FrameEvents]) -> ClearMot {
    let mut objects: BTreeMap<u64, ObjectHistory> = BTreeMap::new();
    let (mut matches, mut switches, mut false_positives, mut misses) = (0, 0, 0, 0);
    let mut distance_sum = 0.0;
    for event in frames.iter().flat_map(|f| &f.events) {
        let (object, matched) = match *event {
            Event::Match {
                object, distance, ..
            } => {
                matches += 1;
                distance_sum += distance;
                (object, true)
            }
            Event::Switch {
                object, distance, ..
            } => {
                switches += 1;
                distance_sum += distance;
                (object, true)
            }
            Event::Miss { object } => {
                misses += 1;
                (object, false)
            }
            Event::FalsePositive { .. } => {
                false_positives += 1;
                continue;
            }
        };
        let history = objects.entry(object).or_default();
        history.frames += 1;
        if matched {
            history.tracked += 1;
            if history.interrupted {
                history.fragmentations += 1;
            }
            history.started = true;
            history.interrupted = false;
        } else if history.started {
            history.interrupted = true;
        }
    }
    let detections = matches + switches;
    let num_objects = detections + misses;
    let num_predictions = detections + false_positives;
    let ratio = |h: &ObjectHistory| h.tracked as f64 / h.frames as f64;
    let count = |keep: &dyn Fn(f64) -> bool| objects.values().filter(|h| keep(ratio(h))).count();
    ClearMot {
        mota: 1.0 - (misses + switches + false_positives) as f64 / num_objects as f64,
        motp: distance_sum / detections as f64,
        recall: detections as f64 / num_objects as f64,
        precision: detections as f64 / num_predictions as f64,
        matches,
        switches,
        false_positives,
        misses,
        fragmentations: objects.values().map(|h| h.fragmentations).sum(),
        mostly_tracked: count(&|r| r >= 0.8),
        partially_tracked: count(&|r| (0.2..0.8).contains(&r)),
        mostly_lost: count(&|r| r < 0.2),
        num_objects,
        num_predictions,
        num_unique_objects: objects.len(),
        num_frames: frames.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn events(frames: Vec<Vec<Event>>) -> Vec<FrameEvents> {
        frames
            .into_iter()
            .enumerate()
            .map(|(i, events)| FrameEvents {
                frame: i as u32,
                events,
            })
            .collect()
    }

    fn hit(object: u64, hypothesis: u64, distance: f64) -> Event {
        Event::Match {
            object,
            hypothesis,
            distance,
        }
    }

    #[test]
    fn counts_and_ratios() {
        let frames = events(vec![
            vec![hit(1, 10, 0.5), Event::Miss { object: 2 }],
            vec![
                Event::Switch {
                    object: 1,
                    hypothesis: 11,
                    distance: 1.0,
                },
                Event::FalsePositive { hypothesis: 12 },
            ],
        ]);
        let m = clear_mot(&frames);
        assert_eq!(
            (m.matches, m.switches, m.misses, m.false_positives),
            (1, 1, 1, 1)
        );
        assert_eq!((m.num_objects, m.num_predictions, m.num_frames), (3, 3, 2));
        assert!((m.mota - (1.0 - 3.0 / 3.0)).abs() < 1e-12);
        assert!((m.motp - 0.75).abs() < 1e-12);
        assert_eq!((m.mostly_tracked, m.mostly_lost), (1, 1));
    }

    #[test]
    fn fragmentations_count_interrupted_runs_only() {
        let miss = Event::Miss { object: 1 };
        let frames = events(vec![
            vec![miss],            // before the first match: not a fragmentation
            vec![hit(1, 10, 0.1)], //
            vec![miss],            // interrupted…
            vec![miss],            //
            vec![hit(1, 10, 0.1)], // …and resumed: 1
            vec![miss],            //
            vec![hit(1, 11, 0.1)], // resumed with another track: 2
            vec![miss],            // trailing misses: not counted
        ]);
        let m = clear_mot(&frames);
        assert_eq!(m.fragmentations, 2);
        assert_eq!(m.partially_tracked, 1);
    }
}
