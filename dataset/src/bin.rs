//! KITTI Velodyne `.bin` scans: N x 4 little-endian `f32` (x, y, z, reflectance), no header.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use trackd_perception::Point;

use crate::error::{DatasetError, write_bytes};

/// Bytes per point in a `.bin` file.
pub const POINT_BYTES: usize = std::mem::size_of::<Point>();

/// Reads a `.bin` scan as it is (no point dropped). A size that is not a multiple of 16 bytes
/// is a [`DatasetError::Format`] (a truncated file). The file is read straight into the
/// points' memory, with no byte buffer between.
pub fn read_bin(path: &Path) -> Result<Vec<Point>, DatasetError> {
    let io = |e| DatasetError::io(path, e);
    let mut file = File::open(path).map_err(io)?;
    let bytes = file.metadata().map_err(io)?.len();
    let len = usize::try_from(bytes)
        .ok()
        .filter(|len| len.is_multiple_of(POINT_BYTES))
        .ok_or_else(|| {
            DatasetError::format(
                path,
                format!(
                    "{bytes} bytes is not a whole number of {POINT_BYTES}-byte points (truncated file?)"
                ),
            )
        })?;
    let mut points = vec![Point::default(); len / POINT_BYTES];
    file.read_exact(bytemuck::cast_slice_mut::<Point, u8>(&mut points))
        .map_err(io)?;
    from_le_in_place(&mut points);
    Ok(points)
}

/// Writes points as a `.bin` scan (little-endian `f32`, x y z intensity).
pub fn write_bin(path: &Path, points: &[Point]) -> Result<(), DatasetError> {
    write_bytes(path, &points_to_le_bytes(points))
}

/// Points from packed little-endian x y z intensity `f32`s (one copy, no per-point parsing);
/// `None` when the length is not a multiple of 16.
pub(crate) fn points_from_le_bytes(bytes: &[u8]) -> Option<Vec<Point>> {
    if !bytes.len().is_multiple_of(POINT_BYTES) {
        return None;
    }
    let mut points = vec![Point::default(); bytes.len() / POINT_BYTES];
    bytemuck::cast_slice_mut::<Point, u8>(&mut points).copy_from_slice(bytes);
    from_le_in_place(&mut points);
    Some(points)
}

/// Turns points holding little-endian `f32` bits into native ones (nothing to do on
/// little-endian machines).
fn from_le_in_place(points: &mut [Point]) {
    if cfg!(target_endian = "big") {
        for v in bytemuck::cast_slice_mut::<Point, u32>(points) {
            *v = u32::from_le(*v);
        }
    }
}

/// Packed little-endian bytes of points.
pub(crate) fn points_to_le_bytes(points: &[Point]) -> Vec<u8> {
    let mut bytes = bytemuck::cast_slice::<Point, u8>(points).to_vec();
    if cfg!(target_endian = "big") {
        for v in bytemuck::cast_slice_mut::<u8, u32>(&mut bytes) {
            *v = v.to_le();
        }
    }
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shared_data_dir;

    #[test]
    fn write_then_read_gives_the_same_points() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("scan.bin");
        let points = vec![
            Point::new(1.5, -2.25, 0.125, 0.5),
            Point::new(-80.0, 3.0, -1.73, 0.0),
        ];
        write_bin(&path, &points).unwrap();
        assert_eq!(std::fs::metadata(&path).unwrap().len(), 32);
        assert_eq!(read_bin(&path).unwrap(), points);
    }

    #[test]
    fn truncated_file_is_a_format_error_naming_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cut.bin");
        std::fs::write(&path, [0u8; 20]).unwrap();
        let err = read_bin(&path).unwrap_err();
        assert!(matches!(err, DatasetError::Format { .. }), "{err}");
        assert!(err.to_string().contains("cut.bin"), "{err}");
    }

    #[test]
    fn missing_file_is_an_io_error() {
        let err = read_bin(Path::new("/nonexistent/x.bin")).unwrap_err();
        assert!(matches!(err, DatasetError::Io { .. }), "{err}");
    }

    #[test]
    fn reads_a_real_odometry_scan() {
        let Some(data) = shared_data_dir("bin::reads_a_real_odometry_scan") else {
            return;
        };
        let path = data.join("kitti-odometry-00/000000.bin");
        let points = read_bin(&path).unwrap();
        let bytes = std::fs::metadata(&path).unwrap().len() as usize;
        assert_eq!(points.len(), bytes / 16);
        assert!(points.len() > 100_000);
        // HDL-64E: everything within ~120 m, reflectance in [0, 1], the ground ~1.73 m below.
        assert!(points.iter().all(|p| p.norm_squared() < 130.0f32.powi(2)));
        assert!(points.iter().all(|p| (0.0..=1.0).contains(&p.intensity)));
        let below = points.iter().filter(|p| p.z < -1.5 && p.z > -2.0).count();
        assert!(below > points.len() / 10, "{below} ground-level points");
    }
}
