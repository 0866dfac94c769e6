//! The KITTI rules shared by tracking labels and raw tracklets: a box of a counted class is
//! kept if its centre is in view and it holds enough LiDAR points; otherwise (and for Misc
//! boxes) it becomes an ignore-near box.

use std::collections::HashSet;

use nalgebra::Point3;
use trackd_dataset::DatasetError;

use crate::{
    error::EvalError,
    gt::{GtFiltering, GtFrame, GtObject, oriented_box::OrientedBox},
    view::View,
};

/// A labelled box before the rules.
pub(crate) struct Candidate {
    /// The object, centre in the Velodyne frame.
    pub object: GtObject,
    /// Of a counted class (else Misc).
    pub counted: bool,
    /// The box in the frame of the points given to [`sort_into`].
    pub bbox: OrientedBox,
}

/// Sorts one frame's candidates into kept objects and ignore-near boxes.
/// `points()` gives the frame's LiDAR points in the boxes' frame, `None` when points are not
/// counted; it is called only if a counted box is in view.
pub(crate) fn sort_into(
    frame: &mut GtFrame,
    candidates: Vec<Candidate>,
    view: &View,
    points: impl FnOnce() -> Result<Option<Vec<Point3<f64>>>, DatasetError>,
    min_points: u32,
    filtering: &mut GtFiltering,
    invalid: impl Fn(String) -> EvalError,
) -> Result<(), EvalError> {
    let mut ids = HashSet::new();
    let mut in_view = Vec::new();
    for candidate in candidates {
        if !ids.insert(candidate.object.id) {
            return Err(invalid(format!(
                "frame {}: object {} labelled twice",
                frame.frame, candidate.object.id
            )));
        }
        if !candidate.counted {
            frame.ignore_near.push(candidate.object);
        } else if !view.contains(candidate.object.centre) {
            filtering.outside_view += 1;
            frame.ignore_near.push(candidate.object);
        } else {
            in_view.push(candidate);
        }
    }
    if in_view.is_empty() {
        return Ok(());
    }
    let points = points()?;
    for candidate in in_view {
        let enough = points
            .as_ref()
            .is_none_or(|p| candidate.bbox.count_inside(p) >= min_points as usize);
        if enough {
            frame.objects.push(candidate.object);
        } else {
            filtering.too_few_points += 1;
            frame.ignore_near.push(candidate.object);
        }
    }
    Ok(())
}
