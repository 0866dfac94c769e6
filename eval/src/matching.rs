//! Frame-by-frame correspondence between GT objects and hypotheses, as py-motmetrics'
//! `MOTAccumulator.update` makes it: first keep each object's previous hypothesis if it is
//! still present and within the threshold, then match the rest by a minimum-cost assignment
//! (as many pairs as possible, then least total distance); a match whose object was last
//! matched to another hypothesis is an ID switch.

use std::collections::HashMap;

use crate::{assignment::min_cost_matching, prepare::ScoredFrame};

/// What happened to one GT object or hypothesis in one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Event {
    /// The object matched the hypothesis it matched last (or its first hypothesis).
    Match {
        /// GT object id.
        object: u64,
        /// Track id.
        hypothesis: u64,
        /// BEV centre distance (metres).
        distance: f64,
    },
    /// The object matched a hypothesis other than the one it matched last.
    Switch {
        /// GT object id.
        object: u64,
        /// Track id.
        hypothesis: u64,
        /// BEV centre distance (metres).
        distance: f64,
    },
    /// The object matched nothing.
    Miss {
        /// GT object id.
        object: u64,
    },
    /// The hypothesis matched nothing.
    FalsePositive {
        /// Track id.
        hypothesis: u64,
    },
}

/// The events of one frame: matches and switches, then misses, then false positives.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameEvents {
    /// Frame index.
    pub frame: u32,
    /// The events.
    pub events: Vec<Event>,
}

/// Matches every frame in order.
pub fn match_frames(frames: &[ScoredFrame]) -> Vec<FrameEvents> {
    let mut last_hypothesis: HashMap<u64, u64> = HashMap::new();
    frames
        .iter()
        .map(|frame| FrameEvents {
            frame: frame.frame,
            events: match_frame(frame, &mut last_hypothesis),
        })
        .collect()
}

/// Matches one frame; `last_hypothesis` maps each object to the hypothesis it matched last.
fn match_frame(frame: &ScoredFrame, last_hypothesis: &mut HashMap<u64, u64>) -> Vec<Event> {
    let objects = &frame.objects;
    let hypotheses = &frame.hypotheses;
    let mut distances: Vec<Vec<Option<f64>>> = objects
        .iter()
        .map(|o| hypotheses.iter().map(|h| o.match_distance(h)).collect())
        .collect();
    let mut object_done = vec![false; objects.len()];
    let mut hypothesis_done = vec![false; hypotheses.len()];
    let mut events = Vec::with_capacity(objects.len().max(hypotheses.len()));

    // 1. Keep previous correspondences that still hold.
    for (i, object) in objects.iter().enumerate() {
        let Some(&previous) = last_hypothesis.get(&object.id) else {
            continue;
        };
        let Some(j) = hypotheses.iter().position(|h| h.id == previous) else {
            continue;
        };
        if let (Some(distance), false) = (distances[i][j], hypothesis_done[j]) {
            object_done[i] = true;
            hypothesis_done[j] = true;
            events.push(Event::Match {
                object: object.id,
                hypothesis: previous,
                distance,
            });
        }
    }

    // 2. Assign the rest.
    for (i, row) in distances.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            if object_done[i] || hypothesis_done[j] {
                *cell = None;
            }
        }
    }
    for (i, j) in min_cost_matching(&distances) {
        let Some(distance) = distances[i][j] else {
            continue;
        };
        let (object, hypothesis) = (objects[i].id, hypotheses[j].id);
        let switched = last_hypothesis
            .insert(object, hypothesis)
            .is_some_and(|previous| previous != hypothesis);
        events.push(if switched {
            Event::Switch {
                object,
                hypothesis,
                distance,
            }
        } else {
            Event::Match {
                object,
                hypothesis,
                distance,
            }
        });
        object_done[i] = true;
        hypothesis_done[j] = true;
    }

    // 3. Misses, 4. false positives.
    let misses = objects
        .iter()
        .zip(&object_done)
        .filter(|(_, done)| !**done)
        .map(|(o, _)| Event::Miss { object: o.id });
    let false_positives = hypotheses
        .iter()
        .zip(&hypothesis_done)
        .filter(|(_, done)| !**done)
        .map(|(h, _)| Event::FalsePositive { hypothesis: h.id });
    events.extend(misses);
    events.extend(false_positives);
    events
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prepare::frame_on_x_axis as frame;

    fn kinds(events: &FrameEvents) -> Vec<&'static str> {
        let mut kinds: Vec<_> = events
            .events
            .iter()
            .map(|e| match e {
                Event::Match { .. } => "match",
                Event::Switch { .. } => "switch",
                Event::Miss { .. } => "miss",
                Event::FalsePositive { .. } => "fp",
            })
            .collect();
        kinds.sort();
        kinds
    }

    #[test]
    fn previous_correspondence_is_kept_over_a_closer_hypothesis() {
        let frames = [
            frame(0, &[(1, 0.0)], &[(10, 0.5), (11, 3.0)]),
            // Hypothesis 11 is now closer, but 10 is still within the threshold.
            frame(1, &[(1, 0.0)], &[(10, 1.5), (11, 0.1)]),
        ];
        let events = match_frames(&frames);
        assert!(events[1].events.contains(&Event::Match {
            object: 1,
            hypothesis: 10,
            distance: 1.5
        }));
        assert_eq!(kinds(&events[1]), ["fp", "match"]);
    }

    #[test]
    fn a_new_hypothesis_for_a_tracked_object_is_a_switch_even_after_a_gap() {
        let frames = [
            frame(0, &[(1, 0.0)], &[(10, 0.5)]),
            frame(1, &[(1, 0.0)], &[]),
            frame(2, &[], &[]),
            frame(3, &[(1, 0.0)], &[(11, 0.5)]),
            frame(4, &[(1, 0.0)], &[(10, 0.5), (11, 0.4)]),
        ];
        let events = match_frames(&frames);
        assert_eq!(kinds(&events[1]), ["miss"]);
        assert_eq!(kinds(&events[3]), ["switch"]);
        // Frame 4: 11 is the last match now; 10 is a false positive.
        assert_eq!(kinds(&events[4]), ["fp", "match"]);
    }

    #[test]
    fn threshold_is_strict() {
        let frames = [frame(0, &[(1, 0.0), (2, 10.0)], &[(10, 2.0), (11, 11.999)])];
        let events = match_frames(&frames);
        assert_eq!(kinds(&events[0]), ["fp", "match", "miss"]);
        assert!(events[0].events.contains(&Event::Miss { object: 1 }));
    }
}
