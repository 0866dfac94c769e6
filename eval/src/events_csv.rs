//! The per-frame outcome of the scoring as CSV (`trackd eval --events`): which GT object
//! matched which track, which were missed and which hypotheses were false positives, with
//! their BEV positions, so that a score can be taken apart.

use std::fmt::Write;

use crate::matching::{Event, FrameEvents};
use crate::prepare::ScoredFrame;

/// The CSV header of [`events_csv`].
pub const HEADER: &str = "frame,event,gt_id,track_id,distance,gt_x,gt_y,track_x,track_y";

/// Writes every event of `events` (frames as `frames` scored them) as one CSV row.
pub fn events_csv(frames: &[ScoredFrame], events: &[FrameEvents]) -> String {
    let mut out = String::from(HEADER);
    out.push('\n');
    for (frame, frame_events) in frames.iter().zip(events) {
        let object_xy = |id: u64| frame.objects.iter().find(|o| o.id == id).map(|o| o.xy);
        let track_xy = |id: u64| frame.hypotheses.iter().find(|h| h.id == id).map(|h| h.xy);
        for event in &frame_events.events {
            let (kind, object, hypothesis, distance) = match *event {
                Event::Match {
                    object,
                    hypothesis,
                    distance,
                } => ("match", Some(object), Some(hypothesis), Some(distance)),
                Event::Switch {
                    object,
                    hypothesis,
                    distance,
                } => ("switch", Some(object), Some(hypothesis), Some(distance)),
                Event::Miss { object } => ("miss", Some(object), None, None),
                Event::FalsePositive { hypothesis } => ("fp", None, Some(hypothesis), None),
            };
            let id = |v: Option<u64>| v.map(|v| v.to_string()).unwrap_or_default();
            let num = |v: Option<f64>| v.map(|v| format!("{v:.3}")).unwrap_or_default();
            let gt = object.and_then(object_xy);
            let track = hypothesis.and_then(track_xy);
            let _ = writeln!(
                out,
                "{},{kind},{},{},{},{},{},{},{}",
                frame.frame,
                id(object),
                id(hypothesis),
                num(distance),
                num(gt.map(|p| p[0])),
                num(gt.map(|p| p[1])),
                num(track.map(|p| p[0])),
                num(track.map(|p| p[1])),
            );
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::matching::match_frames;
    use crate::prepare::frame_on_x_axis as frame;

    #[test]
    fn every_event_is_a_row_with_its_positions() {
        let frames = [frame(0, &[(1, 0.0), (2, 10.0)], &[(10, 0.5), (11, 30.0)])];
        let events = match_frames(&frames);
        let csv = events_csv(&frames, &events);
        let rows: Vec<&str> = csv.lines().collect();
        assert_eq!(rows[0], HEADER);
        assert_eq!(rows.len(), 4, "{csv}");
        assert!(
            rows.contains(&"0,match,1,10,0.500,0.000,0.000,0.500,0.000"),
            "{csv}"
        );
        assert!(rows.contains(&"0,miss,2,,,10.000,0.000,,"), "{csv}");
        assert!(rows.contains(&"0,fp,,11,,,,30.000,0.000"), "{csv}");
    }
}
