//! Identity metrics (Ristani et al. 2016) as py-motmetrics computes them: each GT trajectory is
//! paired with at most one track by a global assignment that maximises the frames in which the
//! pair lies within the match threshold (IDTP).

use std::collections::BTreeMap;

use serde::Serialize;

use crate::{assignment::max_weight_matching, prepare::ScoredFrame};

/// IDF1 and the counts behind it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Identity {
    /// 2 · IDTP / (GT objects + hypotheses).
    pub idf1: f64,
    /// IDTP / (IDTP + IDFP).
    pub idp: f64,
    /// IDTP / (IDTP + IDFN).
    pub idr: f64,
    /// Frames in which a GT object and its globally assigned track are within the threshold.
    pub idtp: u64,
    /// Hypotheses not counted in IDTP.
    pub idfp: u64,
    /// GT objects not counted in IDTP.
    pub idfn: u64,
}

/// Identity metrics of the scored frames.
pub fn identity(frames: &[ScoredFrame]) -> Identity {
    let mut objects: BTreeMap<u64, usize> = BTreeMap::new();
    let mut hypotheses: BTreeMap<u64, usize> = BTreeMap::new();
    for frame in frames {
        for o in &frame.objects {
            let next = objects.len();
            objects.entry(o.id).or_insert(next);
        }
        for h in &frame.hypotheses {
            let next = hypotheses.len();
            hypotheses.entry(h.id).or_insert(next);
        }
    }
    let mut together = vec![vec![0u32; hypotheses.len()]; objects.len()];
    let (mut num_objects, mut num_predictions) = (0u64, 0u64);
    for frame in frames {
        num_objects += frame.objects.len() as u64;
        num_predictions += frame.hypotheses.len() as u64;
        for o in &frame.objects {
            for h in &frame.hypotheses {
                if o.match_distance(h).is_some() {
                    together[objects[&o.id]][hypotheses[&h.id]] += 1;
                }
            }
        }
    }
    let (idtp, _) = max_weight_matching(&together);
    let (idfn, idfp) = (num_objects - idtp, num_predictions - idtp);
    Identity {
        idf1: 2.0 * idtp as f64 / (num_objects + num_predictions) as f64,
        idp: idtp as f64 / (idtp + idfp) as f64,
        idr: idtp as f64 / (idtp + idfn) as f64,
        idtp,
        idfp,
        idfn,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prepare::frame_on_x_axis;

    fn frame(objects: &[(u64, f64)], hypotheses: &[(u64, f64)]) -> ScoredFrame {
        frame_on_x_axis(0, objects, hypotheses)
    }

    #[test]
    fn a_track_that_swaps_objects_counts_once() {
        // Track 10 follows object 1 for two frames, then object 2 for three frames.
        let frames = vec![
            frame(&[(1, 0.0), (2, 10.0)], &[(10, 0.1)]),
            frame(&[(1, 0.0), (2, 10.0)], &[(10, 0.1)]),
            frame(&[(1, 0.0), (2, 10.0)], &[(10, 10.1)]),
            frame(&[(1, 0.0), (2, 10.0)], &[(10, 10.1)]),
            frame(&[(1, 0.0), (2, 10.0)], &[(10, 10.1)]),
        ];
        let m = identity(&frames);
        assert_eq!((m.idtp, m.idfn, m.idfp), (3, 7, 2));
        assert!((m.idf1 - 6.0 / 15.0).abs() < 1e-12);
    }
}
