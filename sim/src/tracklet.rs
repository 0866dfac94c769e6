//! Ground truth as KITTI tracklets (`tracklet_labels.xml`): one tracklet per stretch of
//! consecutive frames an object is in a vehicle's ground truth.

use std::collections::BTreeMap;

use trackd_dataset::tracklets::{Tracklet, TrackletPose};

use crate::gt::GtObject;

/// Half of the front camera's horizontal field of view (KITTI's colour cameras see ~±40°).
const CAMERA_HALF_FOV: f64 = 0.7;

/// The tracklets of one vehicle's ground truth (rows of any frame order).
pub fn tracklets(objects: &[GtObject]) -> Vec<Tracklet> {
    let mut by_id: BTreeMap<u32, Vec<&GtObject>> = BTreeMap::new();
    for o in objects {
        by_id.entry(o.id).or_default().push(o);
    }
    let mut out = Vec::new();
    for rows in by_id.values_mut() {
        rows.sort_by_key(|o| o.frame);
        let mut start = 0;
        for i in 1..=rows.len() {
            if i == rows.len() || rows[i].frame != rows[i - 1].frame + 1 {
                out.push(tracklet(&rows[start..i]));
                start = i;
            }
        }
    }
    out.sort_by_key(|t| t.first_frame);
    out
}

/// One tracklet from consecutive rows of one object.
fn tracklet(rows: &[&GtObject]) -> Tracklet {
    let [l, w, h] = rows[0].size;
    Tracklet {
        object_type: rows[0].class.kitti_name().to_string(),
        h,
        w,
        l,
        first_frame: rows[0].frame,
        poses: rows.iter().map(|o| pose(o)).collect(),
    }
}

/// KITTI's pose of a box: bottom centre, yaw; occlusion from the points on it, truncation
/// from whether the front camera sees it.
fn pose(o: &GtObject) -> TrackletPose {
    let in_image = o.center.x > 0.0 && o.center.y.atan2(o.center.x).abs() < CAMERA_HALF_FOV;
    TrackletPose {
        tx: o.center.x,
        ty: o.center.y,
        tz: o.center.z - o.size[2] / 2.0,
        rz: o.yaw,
        state: 2,
        occlusion: if o.npoints == 0 { 2 } else { 0 },
        occlusion_kf: 0,
        truncation: if in_image { 0 } else { 2 },
        amt_occlusion_kf: -1,
        amt_border_kf: -1,
        ..TrackletPose::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::class::Class;
    use nalgebra::{Vector2, Vector3};

    fn row(id: u32, frame: usize) -> GtObject {
        GtObject {
            frame,
            id,
            class: Class::Van,
            center: Vector3::new(10.0 + frame as f64, 2.0, -0.7),
            size: [5.0, 2.0, 2.0],
            yaw: 0.1,
            velocity: Vector2::new(10.0, 0.0),
            npoints: frame,
        }
    }

    #[test]
    fn gaps_split_tracklets_and_boxes_stand_on_their_bottom() {
        let rows = [row(4, 3), row(4, 1), row(4, 2), row(4, 6), row(9, 0)];
        let t = tracklets(&rows);
        assert_eq!(t.len(), 3);
        assert_eq!((t[0].first_frame, t[0].poses.len()), (0, 1));
        assert_eq!((t[1].first_frame, t[1].poses.len()), (1, 3));
        assert_eq!((t[2].first_frame, t[2].poses.len()), (6, 1));
        let p = t[1].pose_at(2).unwrap();
        assert_eq!((p.tx, p.tz), (12.0, -1.7));
        assert_eq!(t[1].object_type, "Van");
        assert_eq!(t[0].poses[0].occlusion, 2);
    }
}
