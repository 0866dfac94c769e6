//! What each frame contributes to the scores once the protocol's view and ignore rules have
//! run: the counted GT objects and the hypotheses that are neither outside the labelled view nor
//! excused (DontCare regions, near Misc or dropped boxes, paired with a don't-care object).

use std::collections::BTreeMap;

use serde::Serialize;

use crate::{
    assignment::min_cost_matching,
    config::EvalConfig,
    gt::{GroundTruth, GtFrame, GtObject},
    tracks_csv::TrackRow,
    view::View,
};

/// A counted GT object as the metrics see it.
#[derive(Clone, Debug, PartialEq)]
pub struct ScoredObject {
    /// GT identity.
    pub id: u64,
    /// BEV centre (x, y) in the Velodyne frame (metres).
    pub xy: [f64; 2],
    /// A hypothesis may match it only when strictly closer than this (metres).
    pub threshold: f64,
}

/// A scored hypothesis as the metrics see it.
#[derive(Clone, Debug, PartialEq)]
pub struct ScoredHypothesis {
    /// Track identity.
    pub id: u64,
    /// BEV centre (x, y) in the Velodyne frame (metres).
    pub xy: [f64; 2],
}

/// One frame, ready to score.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ScoredFrame {
    /// Frame index.
    pub frame: u32,
    /// Counted GT objects.
    pub objects: Vec<ScoredObject>,
    /// Scored hypotheses.
    pub hypotheses: Vec<ScoredHypothesis>,
}

/// How many hypotheses (track rows) the rules took out of the scoring.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Excused {
    /// Outside the labelled view (camera image or BEV range).
    pub outside_view: usize,
    /// In a DontCare region or near a Misc or dropped box.
    pub ignored: usize,
    /// Paired with a don't-care object.
    pub dont_care: usize,
}

impl ScoredObject {
    /// BEV distance to a hypothesis, if it is below this object's threshold (a possible match).
    pub fn match_distance(&self, hypothesis: &ScoredHypothesis) -> Option<f64> {
        let d = bev_distance(self.xy, hypothesis.xy);
        (d < self.threshold).then_some(d)
    }
}

/// Euclidean distance in the ground plane.
pub fn bev_distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// The frames to score — every frame from the first to the last one that the ground truth or
/// the tracks know, with or without objects — and what was excused.
pub fn prepare(
    gt: &GroundTruth,
    tracks: &[TrackRow],
    config: &EvalConfig,
) -> (Vec<ScoredFrame>, Excused) {
    let mut by_frame: BTreeMap<u32, (Option<&GtFrame>, Vec<&TrackRow>)> = BTreeMap::new();
    for frame in &gt.frames {
        by_frame.entry(frame.frame).or_default().0 = Some(frame);
    }
    for track in tracks {
        by_frame.entry(track.frame).or_default().1.push(track);
    }
    let first = by_frame.first_key_value().map(|(&f, _)| f);
    let last = by_frame.last_key_value().map(|(&f, _)| f);
    if let (Some(first), Some(last)) = (first, last) {
        for frame in first..=last {
            by_frame.entry(frame).or_default();
        }
    }
    let mut excused = Excused::default();
    let frames = by_frame
        .into_iter()
        .map(|(frame, (gt_frame, rows))| {
            let empty = GtFrame {
                frame,
                ..GtFrame::default()
            };
            score_frame(
                gt_frame.unwrap_or(&empty),
                &rows,
                gt.view.as_ref(),
                config,
                &mut excused,
            )
        })
        .collect();
    (frames, excused)
}

/// Applies the view and ignore rules to one frame.
fn score_frame(
    gt: &GtFrame,
    rows: &[&TrackRow],
    view: Option<&View>,
    config: &EvalConfig,
    excused: &mut Excused,
) -> ScoredFrame {
    let scored = |o: &GtObject| ScoredObject {
        id: o.id,
        xy: [o.centre[0], o.centre[1]],
        threshold: config.threshold_for(&o.class),
    };
    let objects: Vec<ScoredObject> = gt.objects.iter().map(scored).collect();
    let mut hypotheses = Vec::with_capacity(rows.len());
    for row in rows {
        if view.is_some_and(|v| !v.contains(row.centre)) {
            excused.outside_view += 1;
            continue;
        }
        let hypothesis = ScoredHypothesis {
            id: row.track_id,
            xy: [row.centre[0], row.centre[1]],
        };
        let near_counted = objects
            .iter()
            .any(|o| o.match_distance(&hypothesis).is_some());
        if !near_counted && is_ignored(gt, row.centre, &hypothesis, view, config) {
            excused.ignored += 1;
            continue;
        }
        hypotheses.push(hypothesis);
    }
    if !gt.dont_care.is_empty() && !hypotheses.is_empty() {
        hypotheses = drop_paired_with_dont_care(&objects, gt, hypotheses, config, excused);
    }
    ScoredFrame {
        frame: gt.frame,
        objects,
        hypotheses,
    }
}

/// Whether a hypothesis lies in a DontCare region or within the threshold of an ignore-near box.
fn is_ignored(
    gt: &GtFrame,
    centre: [f64; 3],
    hypothesis: &ScoredHypothesis,
    view: Option<&View>,
    config: &EvalConfig,
) -> bool {
    let in_region = || {
        let camera = view.and_then(|v| v.camera.as_ref());
        camera
            .and_then(|c| c.project(centre))
            .is_some_and(|uv| gt.ignore_regions.iter().any(|r| r.contains(uv)))
    };
    let near_box = || {
        gt.ignore_near.iter().any(|o| {
            bev_distance([o.centre[0], o.centre[1]], hypothesis.xy) < config.threshold_for(&o.class)
        })
    };
    in_region() || near_box()
}

/// The per-frame assignment of all GT objects (counted and don't care) to the hypotheses, as
/// py-motmetrics' MOT16 preprocessing does with distractors: hypotheses paired with a
/// don't-care object leave the scoring.
fn drop_paired_with_dont_care(
    objects: &[ScoredObject],
    gt: &GtFrame,
    hypotheses: Vec<ScoredHypothesis>,
    config: &EvalConfig,
    excused: &mut Excused,
) -> Vec<ScoredHypothesis> {
    let dont_care = gt.dont_care.iter().map(|o| ScoredObject {
        id: o.id,
        xy: [o.centre[0], o.centre[1]],
        threshold: config.threshold_for(&o.class),
    });
    let all: Vec<ScoredObject> = objects.iter().cloned().chain(dont_care).collect();
    let costs: Vec<Vec<Option<f64>>> = all
        .iter()
        .map(|o| hypotheses.iter().map(|h| o.match_distance(h)).collect())
        .collect();
    let mut dropped = vec![false; hypotheses.len()];
    for (o, h) in min_cost_matching(&costs) {
        if o >= objects.len() {
            dropped[h] = true;
            excused.dont_care += 1;
        }
    }
    hypotheses
        .into_iter()
        .zip(dropped)
        .filter_map(|(h, drop)| (!drop).then_some(h))
        .collect()
}

/// Test data: a frame of objects and hypotheses on the x axis, given as (id, x), every object
/// matched within 2 m.
#[cfg(test)]
pub(crate) fn frame_on_x_axis(
    frame: u32,
    objects: &[(u64, f64)],
    hypotheses: &[(u64, f64)],
) -> ScoredFrame {
    ScoredFrame {
        frame,
        objects: objects
            .iter()
            .map(|&(id, x)| ScoredObject {
                id,
                xy: [x, 0.0],
                threshold: 2.0,
            })
            .collect(),
        hypotheses: hypotheses
            .iter()
            .map(|&(id, x)| ScoredHypothesis { id, xy: [x, 0.0] })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::view::{ImageBox, forward_camera};

    fn object(id: u64, class: &str, x: f64, y: f64) -> GtObject {
        GtObject {
            id,
            class: class.to_string(),
            centre: [x, y, 0.0],
        }
    }

    fn track(frame: u32, id: u64, x: f64, y: f64) -> TrackRow {
        TrackRow {
            frame,
            track_id: id,
            centre: [x, y, 0.0],
            size: [4.0, 1.8, 1.5],
            yaw: 0.0,
            velocity: [0.0, 0.0],
            confidence: 1.0,
            class: "car".to_string(),
        }
    }

    fn kitti_like(frame: GtFrame) -> GroundTruth {
        GroundTruth {
            frames: vec![frame],
            view: Some(View {
                max_range: 40.0,
                camera: Some(forward_camera()),
            }),
            ..GroundTruth::default()
        }
    }

    fn ids(frame: &ScoredFrame) -> Vec<u64> {
        frame.hypotheses.iter().map(|h| h.id).collect()
    }

    #[test]
    fn hypotheses_outside_the_view_are_not_scored() {
        let gt = kitti_like(GtFrame::default());
        let tracks = [
            track(0, 1, 10.0, 0.0),
            track(0, 2, -10.0, 0.0),
            track(0, 3, 45.0, 0.0),
            track(0, 4, 5.0, 10.0),
        ];
        let (frames, excused) = prepare(&gt, &tracks, &EvalConfig::default());
        assert_eq!(ids(&frames[0]), [1]);
        assert_eq!(excused.outside_view, 3);
    }

    #[test]
    fn dont_care_regions_ignore_hypotheses_unless_near_a_counted_object() {
        // The region spans u in [500, 800]: Velodyne y in [−2.56, 1.73] at x = 10.
        let gt = kitti_like(GtFrame {
            objects: vec![object(5, "Car", 10.0, -2.5)],
            ignore_regions: vec![ImageBox {
                left: 500.0,
                top: 100.0,
                right: 800.0,
                bottom: 300.0,
            }],
            ..GtFrame::default()
        });
        // Track 1 is in the region but 1.5 m from the counted car: scored.
        // Track 2 is in the region and 3 m from the car: ignored.
        // Track 3 is outside the region: scored (a false positive).
        let tracks = [
            track(0, 1, 10.0, -1.0),
            track(0, 2, 10.0, 0.5),
            track(0, 3, 10.0, 5.0),
        ];
        let (frames, excused) = prepare(&gt, &tracks, &EvalConfig::default());
        assert_eq!(ids(&frames[0]), [1, 3]);
        assert_eq!(excused.ignored, 1);
    }

    #[test]
    fn hypotheses_near_misc_or_dropped_boxes_are_ignored() {
        let gt = kitti_like(GtFrame {
            objects: vec![object(5, "Car", 20.0, 0.0)],
            ignore_near: vec![
                object(6, "Misc", 10.0, 0.0),
                object(7, "Cyclist", 30.0, 0.0),
            ],
            ..GtFrame::default()
        });
        let tracks = [
            track(0, 1, 11.9, 0.0), // 1.9 m from the Misc box: ignored
            track(0, 2, 12.0, 0.0), // 2.0 m: not below the threshold, scored
            track(0, 3, 30.5, 0.0), // near the dropped cyclist: ignored
            track(0, 4, 21.0, 0.0), // near the counted car: scored
        ];
        let (frames, excused) = prepare(&gt, &tracks, &EvalConfig::default());
        assert_eq!(ids(&frames[0]), [2, 4]);
        assert_eq!(excused.ignored, 2);
        // With a 0.6 m cyclist threshold, 0.5 m is still near; 0.7 m would not be.
        let config = EvalConfig {
            threshold: 2.0,
            cyclist_threshold: Some(0.6),
        };
        let tracks = [track(0, 3, 30.5, 0.0), track(0, 8, 30.7, 0.0)];
        let (frames, _) = prepare(&gt, &tracks, &config);
        assert_eq!(ids(&frames[0]), [8]);
    }

    #[test]
    fn a_hypothesis_paired_with_a_dont_care_object_is_neither_true_nor_false() {
        let gt = GroundTruth {
            frames: vec![GtFrame {
                objects: vec![object(1, "car", 10.0, 0.0)],
                dont_care: vec![object(2, "car", 10.0, 3.0), object(3, "car", 60.0, 0.0)],
                ..GtFrame::default()
            }],
            view: None,
            ..GroundTruth::default()
        };
        let tracks = [
            track(0, 10, 10.0, 0.2),  // pairs with the counted object
            track(0, 11, 10.0, 2.9),  // pairs with don't-care 2: excused
            track(0, 12, 60.5, 0.0),  // pairs with don't-care 3: excused
            track(0, 13, 60.0, -0.5), // 3 is taken: a false positive
            track(0, 14, 30.0, 0.0),  // near nothing: a false positive
        ];
        let (frames, excused) = prepare(&gt, &tracks, &EvalConfig::default());
        assert_eq!(ids(&frames[0]), [10, 13, 14]);
        assert_eq!(excused.dont_care, 2);
    }

    #[test]
    fn frames_span_gt_and_track_frames() {
        let gt = GroundTruth {
            frames: vec![GtFrame {
                frame: 0,
                objects: vec![object(1, "car", 10.0, 0.0)],
                ..GtFrame::default()
            }],
            view: None,
            ..GroundTruth::default()
        };
        let tracks = [track(0, 10, 10.0, 0.0), track(3, 10, 10.0, 0.0)];
        let (frames, _) = prepare(&gt, &tracks, &EvalConfig::default());
        assert_eq!(
            frames.iter().map(|f| f.frame).collect::<Vec<_>>(),
            [0, 1, 2, 3]
        );
        assert!(frames[1].objects.is_empty() && frames[1].hypotheses.is_empty());
        assert!(frames[3].objects.is_empty());
        assert_eq!(ids(&frames[3]), [10]);
    }
}
