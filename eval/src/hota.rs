//! HOTA (Luiten et al. 2020) as TrackEval's `metrics/hota.py` computes it, with the BEV
//! similarity max(0, 1 − d / 2 m): per localisation threshold α = 0.05, 0.10, …, 0.95 a
//! per-frame assignment maximising (global alignment × similarity), pairs at similarity ≥ α
//! count; the reported values are the means over α.

use std::collections::HashMap;

use serde::Serialize;

use crate::{
    assignment::max_weight_assignment,
    prepare::{ScoredFrame, bev_distance},
};

/// HOTA's similarity scale: similarity = max(0, 1 − d / 2 m), whatever the match threshold.
pub const SIMILARITY_SCALE: f64 = 2.0;

/// Number of localisation thresholds α.
const ALPHAS: usize = 19;

/// HOTA and its components, each averaged over the localisation thresholds α.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Hota {
    /// √(DetA · AssA).
    pub hota: f64,
    /// Detection accuracy: TP / (TP + FN + FP).
    pub deta: f64,
    /// Association accuracy.
    pub assa: f64,
    /// Detection recall.
    pub detre: f64,
    /// Detection precision.
    pub detpr: f64,
    /// Association recall.
    pub assre: f64,
    /// Association precision.
    pub asspr: f64,
    /// Localisation accuracy: mean similarity of true positives.
    pub loca: f64,
}

/// The value of threshold `a`, as `np.arange(0.05, 0.99, 0.05)` makes it.
fn alpha(a: usize) -> f64 {
    0.05 + a as f64 * 0.05
}

/// Similarity of a GT object and a hypothesis at BEV distance `d`.
pub fn similarity(d: f64) -> f64 {
    (1.0 - d / SIMILARITY_SCALE).max(0.0)
}

/// One frame with ids as indices and its similarity matrix (GT × tracks).
struct IndexedFrame {
    gts: Vec<usize>,
    tracks: Vec<usize>,
    sim: Vec<Vec<f64>>,
}

/// Per-α totals.
struct Totals {
    tp: [f64; ALPHAS],
    fn_: [f64; ALPHAS],
    fp: [f64; ALPHAS],
    loca: [f64; ALPHAS],
}

/// HOTA of the scored frames.
pub fn hota(frames: &[ScoredFrame]) -> Hota {
    let mut gt_index: HashMap<u64, usize> = HashMap::new();
    let mut track_index: HashMap<u64, usize> = HashMap::new();
    for frame in frames {
        for o in &frame.objects {
            let next = gt_index.len();
            gt_index.entry(o.id).or_insert(next);
        }
        for h in &frame.hypotheses {
            let next = track_index.len();
            track_index.entry(h.id).or_insert(next);
        }
    }
    let mut gt_count = vec![0.0; gt_index.len()];
    let mut track_count = vec![0.0; track_index.len()];
    let mut totals = Totals {
        tp: [0.0; ALPHAS],
        fn_: [0.0; ALPHAS],
        fp: [0.0; ALPHAS],
        loca: [0.0; ALPHAS],
    };
    let num_gt: usize = frames.iter().map(|f| f.objects.len()).sum();
    let num_tracks: usize = frames.iter().map(|f| f.hypotheses.len()).sum();
    if num_gt == 0 || num_tracks == 0 {
        totals.fn_ = [num_gt as f64; ALPHAS];
        totals.fp = [num_tracks as f64; ALPHAS];
        totals.loca = [1.0; ALPHAS];
        return summarise(&totals, &[0.0; ALPHAS], &[0.0; ALPHAS], &[0.0; ALPHAS]);
    }

    // Per frame: ids as indices and the similarity matrix.
    let indexed: Vec<IndexedFrame> = frames
        .iter()
        .map(|f| {
            let gts = f.objects.iter().map(|o| gt_index[&o.id]).collect();
            let tracks = f.hypotheses.iter().map(|h| track_index[&h.id]).collect();
            let sim = f
                .objects
                .iter()
                .map(|o| {
                    let row = f.hypotheses.iter();
                    row.map(|h| similarity(bev_distance(o.xy, h.xy))).collect()
                })
                .collect();
            IndexedFrame { gts, tracks, sim }
        })
        .collect();

    // Global alignment: similarity-weighted potential matches between ids.
    let mut potential: HashMap<(usize, usize), f64> = HashMap::new();
    for IndexedFrame { gts, tracks, sim } in &indexed {
        let row_sums: Vec<f64> = sim.iter().map(|row| row.iter().sum()).collect();
        let col_sums: Vec<f64> = (0..tracks.len())
            .map(|j| sim.iter().map(|row| row[j]).sum())
            .collect();
        for (i, &g) in gts.iter().enumerate() {
            for (j, &t) in tracks.iter().enumerate() {
                let denominator = col_sums[j] + row_sums[i] - sim[i][j];
                if denominator > f64::EPSILON && sim[i][j] != 0.0 {
                    *potential.entry((g, t)).or_default() += sim[i][j] / denominator;
                }
            }
        }
        gts.iter().for_each(|&g| gt_count[g] += 1.0);
        tracks.iter().for_each(|&t| track_count[t] += 1.0);
    }
    let alignment = |g: usize, t: usize| {
        potential
            .get(&(g, t))
            .map_or(0.0, |&p| p / (gt_count[g] + track_count[t] - p))
    };

    // Per frame and α: true positives, misses, false positives, matched id pairs.
    let mut matches: HashMap<(usize, usize), [f64; ALPHAS]> = HashMap::new();
    for IndexedFrame { gts, tracks, sim } in &indexed {
        if gts.is_empty() || tracks.is_empty() {
            totals
                .fp
                .iter_mut()
                .for_each(|fp| *fp += tracks.len() as f64);
            totals
                .fn_
                .iter_mut()
                .for_each(|fn_| *fn_ += gts.len() as f64);
            continue;
        }
        let score: Vec<Vec<f64>> = gts
            .iter()
            .enumerate()
            .map(|(i, &g)| {
                let row = tracks.iter().enumerate();
                row.map(|(j, &t)| alignment(g, t) * sim[i][j]).collect()
            })
            .collect();
        let pairs = max_weight_assignment(&score);
        for a in 0..ALPHAS {
            let mut matched = 0.0;
            for &(i, j) in &pairs {
                if sim[i][j] >= alpha(a) - f64::EPSILON {
                    matched += 1.0;
                    totals.loca[a] += sim[i][j];
                    matches.entry((gts[i], tracks[j])).or_insert([0.0; ALPHAS])[a] += 1.0;
                }
            }
            totals.tp[a] += matched;
            totals.fn_[a] += gts.len() as f64 - matched;
            totals.fp[a] += tracks.len() as f64 - matched;
        }
    }

    // Association scores, averaged over true positives.
    let (mut assa, mut assre, mut asspr) = ([0.0; ALPHAS], [0.0; ALPHAS], [0.0; ALPHAS]);
    for (&(g, t), counts) in &matches {
        for a in 0..ALPHAS {
            let m = counts[a];
            assa[a] += m * m / (gt_count[g] + track_count[t] - m).max(1.0);
            assre[a] += m * m / gt_count[g].max(1.0);
            asspr[a] += m * m / track_count[t].max(1.0);
        }
    }
    for a in 0..ALPHAS {
        let tp = totals.tp[a].max(1.0);
        assa[a] /= tp;
        assre[a] /= tp;
        asspr[a] /= tp;
        totals.loca[a] = totals.loca[a].max(1e-10) / totals.tp[a].max(1e-10);
    }
    summarise(&totals, &assa, &assre, &asspr)
}

/// The final fields per α, averaged over α.
fn summarise(
    totals: &Totals,
    assa: &[f64; ALPHAS],
    assre: &[f64; ALPHAS],
    asspr: &[f64; ALPHAS],
) -> Hota {
    let mean = |f: &dyn Fn(usize) -> f64| (0..ALPHAS).map(f).sum::<f64>() / ALPHAS as f64;
    let (tp, fn_, fp) = (&totals.tp, &totals.fn_, &totals.fp);
    let deta = |a: usize| tp[a] / (tp[a] + fn_[a] + fp[a]).max(1.0);
    Hota {
        hota: mean(&|a| (deta(a) * assa[a]).sqrt()),
        deta: mean(&deta),
        assa: mean(&|a| assa[a]),
        detre: mean(&|a| tp[a] / (tp[a] + fn_[a]).max(1.0)),
        detpr: mean(&|a| tp[a] / (tp[a] + fp[a]).max(1.0)),
        assre: mean(&|a| assre[a]),
        asspr: mean(&|a| asspr[a]),
        loca: mean(&|a| totals.loca[a]),
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
    fn perfect_tracking_scores_one() {
        let frames: Vec<_> = (0..5)
            .map(|k| frame(&[(1, k as f64), (2, 20.0)], &[(7, k as f64), (8, 20.0)]))
            .collect();
        let h = hota(&frames);
        assert!((h.hota - 1.0).abs() < 1e-12, "{h:?}");
        assert!((h.loca - 1.0).abs() < 1e-12);
    }

    #[test]
    fn localisation_error_lowers_detection_by_alpha() {
        // Always 1 m off: similarity 0.5, a true positive for α ≤ 0.5 only (10 of 19).
        let frames: Vec<_> = (0..4).map(|_| frame(&[(1, 0.0)], &[(7, 1.0)])).collect();
        let h = hota(&frames);
        assert!((h.deta - 10.0 / 19.0).abs() < 1e-12, "{h:?}");
        assert!((h.assa - 10.0 / 19.0).abs() < 1e-12);
        assert!((h.hota - 10.0 / 19.0).abs() < 1e-12);
        // LocA is 0.5 where there are true positives and 1 (TrackEval's value) where none.
        assert!((h.loca - 14.0 / 19.0).abs() < 1e-12);
    }

    #[test]
    fn an_id_swap_halves_association() {
        // One object, a track per half of its life: AssA = 1/2 at every α.
        let frames: Vec<_> = (0..4)
            .map(|k| frame(&[(1, 0.0)], &[(if k < 2 { 7 } else { 8 }, 0.0)]))
            .collect();
        let h = hota(&frames);
        assert!((h.deta - 1.0).abs() < 1e-12);
        assert!((h.assa - 0.5).abs() < 1e-12);
        assert!((h.hota - 0.5f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn no_tracks_scores_zero() {
        let h = hota(&[frame(&[(1, 0.0)], &[])]);
        assert_eq!((h.hota, h.deta, h.assa), (0.0, 0.0, 0.0));
    }
}
