//! The scores of one evaluation, as a human table and as JSON.

use serde::Serialize;

use crate::{
    clear_mot::ClearMot,
    config::EvalConfig,
    gt::{GroundTruth, GtFiltering},
    hota::Hota,
    idf1::Identity,
    prepare::Excused,
};

/// Every metric of one evaluation and the counts behind them. Serialised flat: `mota`, `motp`,
/// `idf1`, `idsw`, `fp`, `fn`, `frag`, `hota`, `deta`, `assa`, … A ratio with no finite value
/// (e.g. MOTA without GT objects: −∞ with false positives, NaN without) is `null` in JSON.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Metrics {
    /// CLEAR MOT.
    #[serde(flatten)]
    pub clear: ClearMot,
    /// IDF1 and its counts.
    #[serde(flatten)]
    pub identity: Identity,
    /// HOTA and its components.
    #[serde(flatten)]
    pub hota: Hota,
    /// What the ground truth held.
    pub ground_truth: GtCounts,
    /// Hypotheses taken out of the scoring by the protocol's rules.
    pub hypotheses_excused: Excused,
    /// The thresholds used.
    pub config: EvalConfig,
}

/// What the ground truth held, over all its frames.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct GtCounts {
    /// Frames of the ground truth.
    pub frames: usize,
    /// Counted objects (one per frame it appears in).
    pub objects: usize,
    /// Distinct counted object ids.
    pub unique_objects: usize,
    /// Don't-care objects.
    pub dont_care: usize,
    /// Boxes near which hypotheses are ignored (Misc, dropped boxes).
    pub ignore_near: usize,
    /// DontCare image regions.
    pub ignore_regions: usize,
    /// What the reader dropped.
    pub dropped: GtFiltering,
}

impl GtCounts {
    /// Counts what `gt` holds.
    pub fn of(gt: &GroundTruth) -> Self {
        let mut ids: Vec<u64> = gt
            .frames
            .iter()
            .flat_map(|f| f.objects.iter().map(|o| o.id))
            .collect();
        ids.sort_unstable();
        ids.dedup();
        let sum = |count: &dyn Fn(&crate::gt::GtFrame) -> usize| gt.frames.iter().map(count).sum();
        Self {
            frames: gt.frames.len(),
            objects: sum(&|f| f.objects.len()),
            unique_objects: ids.len(),
            dont_care: sum(&|f| f.dont_care.len()),
            ignore_near: sum(&|f| f.ignore_near.len()),
            ignore_regions: sum(&|f| f.ignore_regions.len()),
            dropped: gt.filtering,
        }
    }
}

impl Metrics {
    /// A human-readable table of the metrics.
    pub fn table(&self) -> String {
        let c = &self.clear;
        let i = &self.identity;
        let h = &self.hota;
        let mut rows = vec![
            ("MOTA", percent(c.mota)),
            ("MOTP (m)", format!("{:.3}", c.motp)),
            ("IDF1", percent(i.idf1)),
            ("HOTA", percent(h.hota)),
            ("  DetA", percent(h.deta)),
            ("  AssA", percent(h.assa)),
            ("  LocA", percent(h.loca)),
            ("IDSW", c.switches.to_string()),
            ("FP", c.false_positives.to_string()),
            ("FN", c.misses.to_string()),
            ("Frag", c.fragmentations.to_string()),
            ("Recall", percent(c.recall)),
            ("Precision", percent(c.precision)),
            (
                "IDP / IDR",
                format!("{} / {}", percent(i.idp), percent(i.idr)),
            ),
            (
                "MT / PT / ML",
                format!(
                    "{} / {} / {}",
                    c.mostly_tracked, c.partially_tracked, c.mostly_lost
                ),
            ),
            ("Frames", c.num_frames.to_string()),
            (
                "GT objects",
                format!("{} ({} ids)", c.num_objects, c.num_unique_objects),
            ),
            ("Hypotheses", c.num_predictions.to_string()),
        ];
        let e = &self.hypotheses_excused;
        rows.push((
            "Excused hyps",
            format!(
                "{} outside view, {} ignored, {} on don't-care",
                e.outside_view, e.ignored, e.dont_care
            ),
        ));
        let thresholds = match self.config.cyclist_threshold {
            Some(cyclist) => format!("{} m ({cyclist} m cyclists)", self.config.threshold),
            None => format!("{} m", self.config.threshold),
        };
        rows.push(("Threshold", thresholds));
        let width = rows.iter().map(|(name, _)| name.len()).max().unwrap_or(0);
        rows.iter()
            .map(|(name, value)| format!("{name:<width$}  {value}\n"))
            .collect()
    }
}

/// A ratio as a percentage with one decimal, or `n/a` when undefined.
fn percent(value: f64) -> String {
    if value.is_finite() {
        format!("{:.1} %", 100.0 * value)
    } else {
        "n/a".to_string()
    }
}
