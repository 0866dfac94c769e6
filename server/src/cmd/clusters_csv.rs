//! `trackd run --debug-clusters`: one row per cluster per scan with what the tracker measured
//! of it (outline, height profile, shape verdict) and the track that took it, so that a missed
//! object or a false positive can be traced to its cause.

use std::fs::File;
use std::io::{BufWriter, Write};

use nalgebra::{Isometry3, Point3};
use trackd_perception::track::Tracker;

/// Header of `clusters.csv`.
pub const HEADER: &str = "frame,cluster,x,y,npoints,length,width,top,bottom,upper_width,\
lower_width,surface_variation,truncated,oblique,verdict,track_id,track_hits,track_moving,track_identity,reported";

/// The open `clusters.csv`.
pub struct ClustersCsv(pub BufWriter<File>);

impl ClustersCsv {
    /// Writes the header to `file`.
    pub fn new(mut file: BufWriter<File>) -> std::io::Result<Self> {
        writeln!(file, "{HEADER}")?;
        Ok(Self(file))
    }

    /// Writes the clusters of scan `index` (sensor pose `ego_pose` in the tracking frame) as
    /// `tracker` saw them;
    /// `x, y` is the outline's centre in the Velodyne frame of the scan.
    pub fn write_frame(
        &mut self,
        index: usize,
        ego_pose: &Isometry3<f64>,
        tracker: &Tracker,
    ) -> std::io::Result<()> {
        let to_sensor = ego_pose.inverse();
        for (j, o) in tracker.observations().iter().enumerate() {
            let c = to_sensor * Point3::new(o.rect.center.x, o.rect.center.y, o.centroid.z);
            let f = &o.shape;
            write!(
                self.0,
                "{index},{j},{:.3},{:.3},{},{:.3},{:.3},{:.3},{:.3},{:.3},{:.3},{:.4},{},{},{:?},",
                c.x,
                c.y,
                o.points,
                f.length,
                f.width,
                f.top,
                f.bottom,
                f.upper_width,
                f.lower_width,
                f.surface_variation,
                f.truncated,
                f.oblique_face,
                o.verdict
            )?;
            match tracker.tracks().iter().find(|t| t.cluster() == Some(j)) {
                Some(t) => writeln!(
                    self.0,
                    "{},{},{},{:?},{}",
                    t.id(),
                    t.state().hits,
                    t.is_moving(),
                    t.identity(),
                    tracker.is_reported(t)
                )?,
                None => writeln!(self.0, ",,,,")?,
            }
        }
        Ok(())
    }
}
