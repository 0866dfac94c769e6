//! `tracks.csv`: what a tracker claims, one row per confirmed track per frame.
//!
//! Header `frame,track_id,x,y,z,l,w,h,yaw,vx,vy,confidence,class`; `x,y,z` the box centre in the
//! Velodyne frame of that frame. A repeated (frame, track_id) or a non-finite coordinate makes
//! the file invalid.

use std::{collections::HashMap, path::Path};

use crate::{
    csv::{Table, read_text},
    error::EvalError,
};

/// One confirmed track in one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackRow {
    /// Frame index (0-based, as the scans are numbered).
    pub frame: u32,
    /// Track identity, stable across frames.
    pub track_id: u64,
    /// Box centre in the Velodyne frame of that frame (metres).
    pub centre: [f64; 3],
    /// Box length, width, height (metres).
    pub size: [f64; 3],
    /// Heading about z in the Velodyne frame (radians).
    pub yaw: f64,
    /// Velocity over ground (m/s).
    pub velocity: [f64; 2],
    /// Tracking confidence.
    pub confidence: f64,
    /// Class name as written (e.g. `car`, `cyclist`).
    pub class: String,
}

/// The columns of `tracks.csv`, in the order they are written.
pub const TRACKS_HEADER: [&str; 13] = [
    "frame",
    "track_id",
    "x",
    "y",
    "z",
    "l",
    "w",
    "h",
    "yaw",
    "vx",
    "vy",
    "confidence",
    "class",
];

/// Reads and validates a `tracks.csv` file.
pub fn read_tracks_csv(path: &Path) -> Result<Vec<TrackRow>, EvalError> {
    parse_tracks_csv(&read_text(path)?, path)
}

/// Parses and validates the text of a `tracks.csv` file; `path` names it in errors.
pub fn parse_tracks_csv(text: &str, path: &Path) -> Result<Vec<TrackRow>, EvalError> {
    let table = Table::new(path, text, &TRACKS_HEADER)?;
    let mut first_line: HashMap<(u32, u64), usize> = HashMap::new();
    let mut tracks = Vec::new();
    for row in table.rows(&TRACKS_HEADER) {
        let row = row?;
        let track = TrackRow {
            frame: row.parse(0)?,
            track_id: row.parse(1)?,
            centre: [row.finite(2)?, row.finite(3)?, row.finite(4)?],
            size: [row.parse(5)?, row.parse(6)?, row.parse(7)?],
            yaw: row.parse(8)?,
            velocity: [row.parse(9)?, row.parse(10)?],
            confidence: row.parse(11)?,
            class: row.text(12).to_string(),
        };
        if let Some(&first) = first_line.get(&(track.frame, track.track_id)) {
            return Err(EvalError::Duplicate {
                path: path.to_path_buf(),
                line: row.line,
                first_line: first,
                frame: track.frame,
                id: track.track_id,
            });
        }
        first_line.insert((track.frame, track.track_id), row.line);
        tracks.push(track);
    }
    Ok(tracks)
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "frame,track_id,x,y,z,l,w,h,yaw,vx,vy,confidence,class\n";

    fn parse(body: &str) -> Result<Vec<TrackRow>, EvalError> {
        parse_tracks_csv(&format!("{HEADER}{body}"), Path::new("tracks.csv"))
    }

    #[test]
    fn reads_rows() {
        let rows = parse(
            "0,7,1.5,-2,0.1,4,1.8,1.5,0.3,1,0,0.9,car\n\n1,7,2,-2,0.1,4,1.8,1.5,0.3,1,0,0.9,car\n",
        )
        .unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].track_id, 7);
        assert_eq!(rows[0].centre, [1.5, -2.0, 0.1]);
        assert_eq!(rows[1].frame, 1);
        assert_eq!(rows[1].class, "car");
    }

    #[test]
    fn repeated_frame_and_id_is_invalid() {
        let err = parse("0,7,1,2,0,4,2,1.5,0,0,0,1,car\n0,8,1,2,0,4,2,1.5,0,0,0,1,car\n0,7,3,2,0,4,2,1.5,0,0,0,1,car\n")
            .unwrap_err();
        match err {
            EvalError::Duplicate {
                line,
                first_line,
                frame,
                id,
                ..
            } => assert_eq!((line, first_line, frame, id), (4, 2, 0, 7)),
            other => panic!("wrong error {other}"),
        }
    }

    #[test]
    fn non_finite_coordinate_is_invalid() {
        let err =
            parse("0,7,1,2,0,4,2,1.5,0,0,0,1,car\n1,7,NaN,2,0,4,2,1.5,0,0,0,1,car\n").unwrap_err();
        assert!(
            matches!(&err, EvalError::NonFinite { line: 3, column, .. } if column == "x"),
            "{err}"
        );
        let err = parse("0,7,1,2,inf,4,2,1.5,0,0,0,1,car\n").unwrap_err();
        assert!(matches!(&err, EvalError::NonFinite { line: 2, column, .. } if column == "z"));
    }

    #[test]
    fn malformed_rows_name_their_line() {
        let err =
            parse("0,7,1,2,0,4,2,1.5,0,0,0,1,car\n0,x,1,2,0,4,2,1.5,0,0,0,1,car\n").unwrap_err();
        assert!(matches!(err, EvalError::BadRow { line: 3, .. }));
        let err = parse("0,7,1,2,0\n").unwrap_err();
        assert!(matches!(err, EvalError::BadRow { line: 2, .. }));
        let err = parse_tracks_csv("frame,id,x\n", Path::new("t.csv")).unwrap_err();
        assert!(matches!(err, EvalError::MissingColumn { column, .. } if column == "track_id"));
    }
}
