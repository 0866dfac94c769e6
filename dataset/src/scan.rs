//! One scan file of either format, chosen by its extension.

use std::path::Path;

use trackd_perception::Point;

use crate::error::DatasetError;
use crate::{bin, pcd};

/// The scan formats this crate reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScanFormat {
    /// KITTI Velodyne `.bin`.
    Bin,
    /// PCD v0.7 `.pcd`.
    Pcd,
}

impl ScanFormat {
    /// The format of a file, from its extension (case-insensitive); `None` for anything else.
    pub fn of(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "bin" => Some(Self::Bin),
            "pcd" => Some(Self::Pcd),
            _ => None,
        }
    }
}

/// Reads a `.bin` or `.pcd` scan as it is (no point dropped).
pub fn read_scan(path: &Path) -> Result<Vec<Point>, DatasetError> {
    match ScanFormat::of(path) {
        Some(ScanFormat::Bin) => bin::read_bin(path),
        Some(ScanFormat::Pcd) => pcd::read_pcd(path),
        None => Err(DatasetError::format(
            path,
            "not a scan file: expected a .bin or .pcd extension",
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dispatches_on_extension() {
        let dir = tempfile::tempdir().unwrap();
        let points = vec![Point::new(1.0, 2.0, 3.0, 0.5)];
        let (b, p) = (dir.path().join("a.BIN"), dir.path().join("a.pcd"));
        bin::write_bin(&b, &points).unwrap();
        pcd::write_pcd_binary(&p, &points).unwrap();
        assert_eq!(read_scan(&b).unwrap(), points);
        assert_eq!(read_scan(&p).unwrap(), points);
        let err = read_scan(&dir.path().join("a.ply")).unwrap_err();
        assert!(err.to_string().contains("a.ply: not a scan file"), "{err}");
    }
}
