//! PCD v0.7 point clouds (PCL's format): `ascii`, `binary` and `binary_compressed` (LZF) data,
//! fields in any order and of any PCL type; `x y z` required, `intensity` optional (0 when
//! absent), other fields ignored. Exactly `POINTS` points are read: bytes or lines after them
//! (padding) are ignored.

use std::path::Path;

use trackd_perception::Point;

use crate::bin::{points_from_le_bytes, points_to_le_bytes};
use crate::error::{DatasetError, read_bytes, write_bytes};

/// How a PCD file stores its points (its `DATA` line).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PcdData {
    /// One text line per point.
    Ascii,
    /// Packed records, one per point, fields in `FIELDS` order.
    Binary,
    /// One LZF block holding each field's values for all points in turn.
    BinaryCompressed,
}

impl PcdData {
    fn keyword(self) -> &'static str {
        match self {
            Self::Ascii => "ascii",
            Self::Binary => "binary",
            Self::BinaryCompressed => "binary_compressed",
        }
    }
}

/// A PCL scalar type: `TYPE` letter and `SIZE` in bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    F32,
    F64,
    I8,
    I16,
    I32,
    I64,
    U8,
    U16,
    U32,
    U64,
}

impl Scalar {
    fn from_type_and_size(kind: &str, size: usize) -> Option<Self> {
        Some(match (kind, size) {
            ("F", 4) => Self::F32,
            ("F", 8) => Self::F64,
            ("I", 1) => Self::I8,
            ("I", 2) => Self::I16,
            ("I", 4) => Self::I32,
            ("I", 8) => Self::I64,
            ("U", 1) => Self::U8,
            ("U", 2) => Self::U16,
            ("U", 4) => Self::U32,
            ("U", 8) => Self::U64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::F32 | Self::I32 | Self::U32 => 4,
            Self::F64 | Self::I64 | Self::U64 => 8,
        }
    }

    /// The value at the start of `b` (little-endian), as `f32`. `b` holds at least `size()`
    /// bytes.
    fn read(self, b: &[u8]) -> f32 {
        fn arr<const N: usize>(b: &[u8]) -> [u8; N] {
            let mut a = [0; N];
            a.copy_from_slice(&b[..N]);
            a
        }
        match self {
            Self::F32 => f32::from_le_bytes(arr(b)),
            Self::F64 => f64::from_le_bytes(arr(b)) as f32,
            Self::I8 => f32::from(i8::from_le_bytes(arr(b))),
            Self::I16 => f32::from(i16::from_le_bytes(arr(b))),
            Self::I32 => i32::from_le_bytes(arr(b)) as f32,
            Self::I64 => i64::from_le_bytes(arr(b)) as f32,
            Self::U8 => f32::from(u8::from_le_bytes(arr(b))),
            Self::U16 => f32::from(u16::from_le_bytes(arr(b))),
            Self::U32 => u32::from_le_bytes(arr(b)) as f32,
            Self::U64 => u64::from_le_bytes(arr(b)) as f32,
        }
    }
}

/// One `FIELDS` entry.
#[derive(Debug)]
struct Field {
    name: String,
    scalar: Scalar,
    count: usize,
    /// Byte offset in a binary record.
    offset: usize,
    /// Index of its first value on an ascii line.
    column: usize,
}

/// What the header says, and where the data starts.
#[derive(Debug)]
struct Header {
    fields: Vec<Field>,
    points: usize,
    data: PcdData,
    /// Byte offset of the first data byte.
    data_start: usize,
    /// Line number of the `DATA` line.
    data_line: usize,
}

impl Header {
    /// Bytes of one binary record.
    fn record_size(&self) -> usize {
        self.fields.iter().map(|f| f.scalar.size() * f.count).sum()
    }

    /// Values on one ascii line.
    fn columns(&self) -> usize {
        self.fields.iter().map(|f| f.count).sum()
    }

    /// The fields holding x, y, z and (if present) intensity.
    fn xyzi(&self, path: &Path) -> Result<[Option<&Field>; 4], DatasetError> {
        let find = |names: &[&str]| {
            self.fields
                .iter()
                .find(|f| names.contains(&f.name.as_str()))
        };
        let need = |name: &str| {
            find(&[name]).ok_or_else(|| {
                DatasetError::format(
                    path,
                    format!("PCD has no field {name:?} (FIELDS must hold x y z)"),
                )
            })
        };
        Ok([
            Some(need("x")?),
            Some(need("y")?),
            Some(need("z")?),
            find(&["intensity", "i"]),
        ])
    }

    /// Whether binary records are exactly x y z intensity as `f32`: then the data is a
    /// `&[Point]` as it is.
    fn is_packed_xyzi(&self) -> bool {
        let names = ["x", "y", "z", "intensity"];
        self.fields.len() == 4
            && self
                .fields
                .iter()
                .zip(names)
                .all(|(f, n)| f.name == n && f.scalar == Scalar::F32 && f.count == 1)
    }
}

/// Reads a PCD file's points as they are (no point dropped).
pub fn read_pcd(path: &Path) -> Result<Vec<Point>, DatasetError> {
    let bytes = read_bytes(path)?;
    let header = parse_header(path, &bytes)?;
    let data = &bytes[header.data_start..];
    match header.data {
        PcdData::Ascii => read_ascii(path, &header, data),
        PcdData::Binary => read_binary(path, &header, data),
        PcdData::BinaryCompressed => read_compressed(path, &header, data),
    }
}

/// Writes points as a binary PCD v0.7 file (`FIELDS x y z intensity`, `float32`), the layout
/// PCL's `savePCDFileBinary` writes for `PointXYZI`.
pub fn write_pcd_binary(path: &Path, points: &[Point]) -> Result<(), DatasetError> {
    write_pcd(path, points, PcdData::Binary)
}

/// Writes points as a PCD v0.7 file (`FIELDS x y z intensity`, `float32`) with the given data
/// encoding.
pub fn write_pcd(path: &Path, points: &[Point], data: PcdData) -> Result<(), DatasetError> {
    let mut out = format!(
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z intensity\n\
         SIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH {n}\nHEIGHT 1\n\
         VIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\nDATA {}\n",
        data.keyword(),
        n = points.len()
    )
    .into_bytes();
    match data {
        PcdData::Ascii => {
            for p in points {
                out.extend_from_slice(
                    format!("{} {} {} {}\n", p.x, p.y, p.z, p.intensity).as_bytes(),
                );
            }
        }
        PcdData::Binary => out.extend_from_slice(&points_to_le_bytes(points)),
        PcdData::BinaryCompressed => {
            let mut columns = Vec::with_capacity(points.len() * 16);
            for get in [
                |p: &Point| p.x,
                |p: &Point| p.y,
                |p: &Point| p.z,
                |p: &Point| p.intensity,
            ] {
                for p in points {
                    columns.extend_from_slice(&get(p).to_le_bytes());
                }
            }
            let compressed = lzf_compress(&columns);
            let sizes = [compressed.len(), columns.len()].map(|n| {
                u32::try_from(n)
                    .map_err(|_| DatasetError::format(path, "too many points for a compressed PCD"))
            });
            for size in sizes {
                out.extend_from_slice(&size?.to_le_bytes());
            }
            out.extend_from_slice(&compressed);
        }
    }
    write_bytes(path, &out)
}

/// LZF-compresses `data`; data LZF cannot shrink is stored as literal runs (valid LZF too).
fn lzf_compress(data: &[u8]) -> Vec<u8> {
    if data.is_empty() {
        return Vec::new();
    }
    lzf::compress(data).unwrap_or_else(|_| {
        let mut out = Vec::with_capacity(data.len() + data.len() / 32 + 1);
        for run in data.chunks(32) {
            out.push((run.len() - 1) as u8);
            out.extend_from_slice(run);
        }
        out
    })
}

fn parse_header(path: &Path, bytes: &[u8]) -> Result<Header, DatasetError> {
    let mut names: Vec<String> = Vec::new();
    let mut sizes: Vec<usize> = Vec::new();
    let mut types: Vec<String> = Vec::new();
    let mut counts: Option<Vec<usize>> = None;
    let mut width: Option<usize> = None;
    let mut height: usize = 1;
    let mut points: Option<usize> = None;
    let mut type_line = 0;

    let mut start = 0;
    let mut line_no = 0;
    while start < bytes.len() {
        line_no += 1;
        let end = bytes[start..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(bytes.len(), |i| start + i + 1);
        let line = std::str::from_utf8(&bytes[start..end])
            .map_err(|_| DatasetError::parse(path, line_no, "PCD header is not text"))?
            .trim();
        start = end;
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let mut tokens = line.split_whitespace();
        let key = tokens.next().unwrap_or_default().to_ascii_uppercase();
        let values: Vec<&str> = tokens.collect();
        let numbers = |what: &str| -> Result<Vec<usize>, DatasetError> {
            values
                .iter()
                .map(|v| {
                    v.parse::<usize>().map_err(|_| {
                        DatasetError::parse(path, line_no, format!("{what}: {v:?} is not a count"))
                    })
                })
                .collect()
        };
        let one = |what: &str| -> Result<usize, DatasetError> {
            match numbers(what)?.as_slice() {
                [n] => Ok(*n),
                _ => Err(DatasetError::parse(
                    path,
                    line_no,
                    format!("{what} takes one value"),
                )),
            }
        };
        match key.as_str() {
            "VERSION" | "VIEWPOINT" => {}
            "FIELDS" | "COLUMNS" => names = values.iter().map(|s| s.to_string()).collect(),
            "SIZE" => sizes = numbers("SIZE")?,
            "TYPE" => {
                types = values.iter().map(|s| s.to_ascii_uppercase()).collect();
                type_line = line_no;
            }
            "COUNT" => counts = Some(numbers("COUNT")?),
            "WIDTH" => width = Some(one("WIDTH")?),
            "HEIGHT" => height = one("HEIGHT")?,
            "POINTS" => points = Some(one("POINTS")?),
            "DATA" => {
                let data = match values.first().map(|s| s.to_ascii_lowercase()).as_deref() {
                    Some("ascii") => PcdData::Ascii,
                    Some("binary") => PcdData::Binary,
                    Some("binary_compressed") => PcdData::BinaryCompressed,
                    other => {
                        return Err(DatasetError::parse(
                            path,
                            line_no,
                            format!("unknown PCD DATA kind {:?}", other.unwrap_or("")),
                        ));
                    }
                };
                let counts = counts.unwrap_or_else(|| vec![1; names.len()]);
                if names.is_empty()
                    || sizes.len() != names.len()
                    || types.len() != names.len()
                    || counts.len() != names.len()
                {
                    return Err(DatasetError::format(
                        path,
                        format!(
                            "PCD header: FIELDS ({}), SIZE ({}), TYPE ({}) and COUNT ({}) must list the same number of fields",
                            names.len(),
                            sizes.len(),
                            types.len(),
                            counts.len()
                        ),
                    ));
                }
                let width =
                    width.ok_or_else(|| DatasetError::format(path, "PCD header has no WIDTH"))?;
                let mut fields = Vec::with_capacity(names.len());
                let (mut offset, mut column) = (0, 0);
                for (((name, size), kind), count) in
                    names.into_iter().zip(sizes).zip(types).zip(counts)
                {
                    let scalar = Scalar::from_type_and_size(&kind, size).ok_or_else(|| {
                        DatasetError::parse(
                            path,
                            type_line,
                            format!("field {name:?}: unknown PCD type {kind} of size {size}"),
                        )
                    })?;
                    if count == 0 {
                        return Err(DatasetError::format(
                            path,
                            format!("field {name:?} has COUNT 0"),
                        ));
                    }
                    fields.push(Field {
                        name,
                        scalar,
                        count,
                        offset,
                        column,
                    });
                    offset += size * count;
                    column += count;
                }
                return Ok(Header {
                    fields,
                    points: points.unwrap_or(width * height),
                    data,
                    data_start: start,
                    data_line: line_no,
                });
            }
            _ => {
                return Err(DatasetError::parse(
                    path,
                    line_no,
                    format!("not a PCD header line: {:?}", truncate(line)),
                ));
            }
        }
    }
    Err(DatasetError::format(
        path,
        "PCD header has no DATA line (not a PCD file, or truncated)",
    ))
}

/// At most 40 characters of a line, for error messages.
fn truncate(line: &str) -> &str {
    line.char_indices()
        .nth(40)
        .map_or(line, |(i, _)| &line[..i])
}

fn read_binary(path: &Path, header: &Header, data: &[u8]) -> Result<Vec<Point>, DatasetError> {
    let record = header.record_size();
    let need = header.points * record;
    if data.len() < need {
        return Err(DatasetError::format(
            path,
            format!(
                "truncated: POINTS {} x {record} bytes needs {need} bytes of data, the file has {}",
                header.points,
                data.len()
            ),
        ));
    }
    let data = &data[..need];
    if header.is_packed_xyzi() {
        // One copy: the records are `Point`s already.
        return Ok(points_from_le_bytes(data).unwrap_or_default());
    }
    let fields = header.xyzi(path)?;
    Ok(data
        .chunks_exact(record)
        .map(|r| {
            let [x, y, z, i] = fields.map(|f| f.map_or(0.0, |f| f.scalar.read(&r[f.offset..])));
            Point::new(x, y, z, i)
        })
        .collect())
}

fn read_compressed(path: &Path, header: &Header, data: &[u8]) -> Result<Vec<Point>, DatasetError> {
    let word = |at: usize| -> Result<usize, DatasetError> {
        data.get(at..at + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
            .ok_or_else(|| {
                DatasetError::format(path, "truncated: binary_compressed data has no size words")
            })
    };
    let (compressed_size, size) = (word(0)?, word(4)?);
    let need = header.points * header.record_size();
    if size != need {
        return Err(DatasetError::format(
            path,
            format!(
                "binary_compressed: uncompressed size {size} bytes, POINTS and FIELDS say {need}"
            ),
        ));
    }
    if need == 0 {
        return Ok(Vec::new());
    }
    let compressed = data.get(8..8 + compressed_size).ok_or_else(|| {
        DatasetError::format(
            path,
            format!(
                "truncated: binary_compressed block of {compressed_size} bytes, the file has {}",
                data.len().saturating_sub(8)
            ),
        )
    })?;
    let columns = lzf::decompress(compressed, size)
        .map_err(|e| DatasetError::format(path, format!("binary_compressed: LZF: {e}")))?;
    if columns.len() != size {
        return Err(DatasetError::format(
            path,
            format!(
                "binary_compressed: LZF gave {} bytes, expected {size}",
                columns.len()
            ),
        ));
    }
    let fields = header.xyzi(path)?;
    // Field f's values for all points start at points * (its offset in a record).
    let value = |f: Option<&Field>, i: usize| {
        f.map_or(0.0, |f| {
            let at = header.points * f.offset + i * f.scalar.size() * f.count;
            f.scalar.read(&columns[at..])
        })
    };
    Ok((0..header.points)
        .map(|i| {
            let [x, y, z, intensity] = fields.map(|f| value(f, i));
            Point::new(x, y, z, intensity)
        })
        .collect())
}

fn read_ascii(path: &Path, header: &Header, data: &[u8]) -> Result<Vec<Point>, DatasetError> {
    let text = std::str::from_utf8(data).map_err(|_| {
        DatasetError::parse(path, header.data_line + 1, "ascii PCD data is not text")
    })?;
    let fields = header.xyzi(path)?;
    let columns = header.columns();
    let mut points = Vec::with_capacity(header.points);
    for (k, line) in text.lines().enumerate() {
        if points.len() == header.points {
            break;
        }
        let line_no = header.data_line + 1 + k;
        let tokens: Vec<&str> = line.split_whitespace().collect();
        if tokens.is_empty() {
            continue;
        }
        if tokens.len() != columns {
            return Err(DatasetError::parse(
                path,
                line_no,
                format!("{} values, FIELDS and COUNT say {columns}", tokens.len()),
            ));
        }
        let mut xyzi = [0.0f32; 4];
        for (v, f) in xyzi.iter_mut().zip(fields) {
            if let Some(f) = f {
                let token = tokens[f.column];
                *v = token.parse::<f64>().map_err(|_| {
                    DatasetError::parse(
                        path,
                        line_no,
                        format!("field {}: {token:?} is not a number", f.name),
                    )
                })? as f32;
            }
        }
        points.push(Point::new(xyzi[0], xyzi[1], xyzi[2], xyzi[3]));
    }
    if points.len() < header.points {
        return Err(DatasetError::format(
            path,
            format!(
                "truncated: POINTS {} but the ascii data holds {}",
                header.points,
                points.len()
            ),
        ));
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shared_data_dir;

    fn sample_points() -> Vec<Point> {
        (0..500)
            .map(|i| {
                let a = i as f32 * 0.05;
                Point::new(
                    10.0 * a.cos(),
                    10.0 * a.sin(),
                    -1.73 + 0.001 * i as f32,
                    (i % 100) as f32 / 100.0,
                )
            })
            .collect()
    }

    fn header(
        fields: &str,
        size: &str,
        kind: &str,
        count: &str,
        points: usize,
        data: &str,
    ) -> Vec<u8> {
        format!(
            "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS {fields}\nSIZE {size}\n\
             TYPE {kind}\nCOUNT {count}\nWIDTH {points}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\n\
             POINTS {points}\nDATA {data}\n"
        )
        .into_bytes()
    }

    fn write_temp(bytes: &[u8]) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cloud.pcd");
        std::fs::write(&path, bytes).unwrap();
        (dir, path)
    }

    #[test]
    fn every_encoding_round_trips() {
        let dir = tempfile::tempdir().unwrap();
        let points = sample_points();
        for data in [PcdData::Ascii, PcdData::Binary, PcdData::BinaryCompressed] {
            let path = dir.path().join(format!("{}.pcd", data.keyword()));
            write_pcd(&path, &points, data).unwrap();
            assert_eq!(read_pcd(&path).unwrap(), points, "{data:?}");
        }
        let path = dir.path().join("b.pcd");
        write_pcd_binary(&path, &points).unwrap();
        let text = std::fs::read(&path).unwrap();
        assert!(text.starts_with(b"# .PCD v0.7"));
        assert_eq!(read_pcd(&path).unwrap(), points);
    }

    #[test]
    fn compressed_writer_stores_incompressible_and_tiny_clouds() {
        let dir = tempfile::tempdir().unwrap();
        for points in [
            vec![],
            vec![Point::new(1.0, 2.0, 3.0, 0.25)],
            vec![Point::new(-7.5, 1e-3, 42.0, 0.9); 3],
        ] {
            let path = dir.path().join("c.pcd");
            write_pcd(&path, &points, PcdData::BinaryCompressed).unwrap();
            assert_eq!(read_pcd(&path).unwrap(), points);
        }
    }

    #[test]
    fn ascii_with_fields_in_any_order_extra_fields_nan_and_padding() {
        let mut bytes = header(
            "intensity z rgb x y normal",
            "4 4 4 4 4 4",
            "F F U F F F",
            "1 1 1 1 1 3",
            3,
            "ascii",
        );
        bytes.extend_from_slice(
            b"0.5 -1.5 4278190080 10.25 -3 0 0 1\n\n\
              0 nan 0 1 2 0 0 1\n\
              1 3 7 -0.5 1e2 0.1 0.2 0.3\n\
              9 9 9 9 9 9 9 9\n",
        );
        let (_dir, path) = write_temp(&bytes);
        let points = read_pcd(&path).unwrap();
        assert_eq!(points.len(), 3, "the fourth line is past POINTS");
        assert_eq!(points[0], Point::new(10.25, -3.0, -1.5, 0.5));
        assert!(points[1].z.is_nan());
        assert_eq!(points[2], Point::new(-0.5, 100.0, 3.0, 1.0));
    }

    #[test]
    fn binary_with_mixed_types_and_trailing_padding() {
        let mut bytes = header(
            "y rgb x z extra intensity",
            "4 4 8 4 2 1",
            "F U F F I U",
            "1 1 1 1 3 1",
            2,
            "binary",
        );
        for (x, y, z, i) in [(1.5f64, -2.0f32, 0.25f32, 200u8), (-80.0, 3.5, -1.75, 7)] {
            bytes.extend_from_slice(&y.to_le_bytes());
            bytes.extend_from_slice(&0xff00_00ffu32.to_le_bytes());
            bytes.extend_from_slice(&x.to_le_bytes());
            bytes.extend_from_slice(&z.to_le_bytes());
            for e in [1i16, -2, 3] {
                bytes.extend_from_slice(&e.to_le_bytes());
            }
            bytes.push(i);
        }
        bytes.extend_from_slice(&[0u8; 64]);
        let (_dir, path) = write_temp(&bytes);
        assert_eq!(
            read_pcd(&path).unwrap(),
            vec![
                Point::new(1.5, -2.0, 0.25, 200.0),
                Point::new(-80.0, 3.5, -1.75, 7.0)
            ]
        );
    }

    #[test]
    fn binary_compressed_with_other_field_order_and_no_intensity() {
        let points = sample_points();
        let mut bytes = header(
            "z x pad y",
            "4 4 2 4",
            "F F I F",
            "1 1 1 1",
            points.len(),
            "binary_compressed",
        );
        let mut columns = Vec::new();
        for p in &points {
            columns.extend_from_slice(&p.z.to_le_bytes());
        }
        for p in &points {
            columns.extend_from_slice(&p.x.to_le_bytes());
        }
        for i in 0..points.len() {
            columns.extend_from_slice(&(i as i16).to_le_bytes());
        }
        for p in &points {
            columns.extend_from_slice(&p.y.to_le_bytes());
        }
        let compressed = lzf_compress(&columns);
        bytes.extend_from_slice(&(compressed.len() as u32).to_le_bytes());
        bytes.extend_from_slice(&(columns.len() as u32).to_le_bytes());
        bytes.extend_from_slice(&compressed);
        let (_dir, path) = write_temp(&bytes);
        let expected: Vec<Point> = points
            .iter()
            .map(|p| Point::new(p.x, p.y, p.z, 0.0))
            .collect();
        assert_eq!(read_pcd(&path).unwrap(), expected);
    }

    fn error_of(bytes: &[u8]) -> DatasetError {
        let (_dir, path) = write_temp(bytes);
        let err = read_pcd(&path).unwrap_err();
        assert!(err.to_string().contains("cloud.pcd"), "{err}");
        err
    }

    #[test]
    fn unknown_type_is_a_parse_error_on_the_type_line() {
        let err = error_of(&header("x y z", "4 4 4", "F F Q", "1 1 1", 0, "binary"));
        match err {
            DatasetError::Parse {
                line, ref message, ..
            } => {
                assert_eq!(line, 5, "{err}");
                assert!(message.contains("unknown PCD type"), "{err}");
            }
            _ => panic!("{err}"),
        }
        let err = error_of(&header("x y z", "4 4 3", "F F F", "1 1 1", 0, "binary"));
        assert!(
            err.to_string().contains("unknown PCD type F of size 3"),
            "{err}"
        );
    }

    #[test]
    fn truncated_binary_and_compressed_data_are_format_errors() {
        let mut bytes = header(
            "x y z intensity",
            "4 4 4 4",
            "F F F F",
            "1 1 1 1",
            10,
            "binary",
        );
        bytes.extend_from_slice(&[0u8; 16 * 9 + 3]);
        assert!(matches!(error_of(&bytes), DatasetError::Format { .. }));

        let mut bytes = header(
            "x y z intensity",
            "4 4 4 4",
            "F F F F",
            "1 1 1 1",
            10,
            "binary_compressed",
        );
        bytes.extend_from_slice(&100u32.to_le_bytes());
        bytes.extend_from_slice(&160u32.to_le_bytes());
        bytes.extend_from_slice(&[0u8; 50]);
        let err = error_of(&bytes);
        assert!(err.to_string().contains("truncated"), "{err}");

        let mut bytes = header(
            "x y z intensity",
            "4 4 4 4",
            "F F F F",
            "1 1 1 1",
            10,
            "binary_compressed",
        );
        bytes.extend_from_slice(&4u32.to_le_bytes());
        bytes.extend_from_slice(&160u32.to_le_bytes());
        bytes.extend_from_slice(&[0xe0, 0xff, 0xff, 0xff]);
        let err = error_of(&bytes);
        assert!(err.to_string().contains("LZF"), "{err}");

        let mut bytes = header("x y z", "4 4 4", "F F F", "1 1 1", 2, "ascii");
        bytes.extend_from_slice(b"1 2 3\n");
        assert!(error_of(&bytes).to_string().contains("truncated"));
    }

    #[test]
    fn bad_ascii_lines_name_their_line() {
        let mut bytes = header("x y z", "4 4 4", "F F F", "1 1 1", 2, "ascii");
        bytes.extend_from_slice(b"1 2 3\n1 2\n");
        match error_of(&bytes) {
            DatasetError::Parse { line, message, .. } => {
                assert_eq!(line, 13);
                assert!(message.contains("2 values"), "{message}");
            }
            err => panic!("{err}"),
        }
        let mut bytes = header("x y z", "4 4 4", "F F F", "1 1 1", 2, "ascii");
        bytes.extend_from_slice(b"1 2 3\n1 two 3\n");
        assert!(matches!(
            error_of(&bytes),
            DatasetError::Parse { line: 13, .. }
        ));
    }

    #[test]
    fn malformed_headers_are_errors() {
        assert!(matches!(
            error_of(&header("x y", "4 4", "F F", "1 1", 0, "binary")),
            DatasetError::Format { .. }
        ));
        assert!(
            error_of(&header("x y z", "4 4", "F F F", "1 1 1", 0, "binary"))
                .to_string()
                .contains("same number")
        );
        assert!(
            error_of(&header("x y z", "4 4 4", "F F F", "1 1 1", 0, "zip"))
                .to_string()
                .contains("DATA")
        );
        assert!(
            error_of(b"VERSION 0.7\nFIELDS x y z\n")
                .to_string()
                .contains("no DATA")
        );
        assert!(matches!(
            error_of(b"\x00\x01binary junk\n"),
            DatasetError::Parse { line: 1, .. }
        ));
        assert!(
            error_of(&header("x y z", "4 4 4", "F F F", "1 0 1", 0, "binary"))
                .to_string()
                .contains("COUNT 0")
        );
    }

    #[test]
    fn reads_real_kitti_pcd_frames_ignoring_padding() {
        let Some(data) = shared_data_dir("pcd::reads_real_kitti_pcd_frames_ignoring_padding")
        else {
            return;
        };
        let path = data.join("kitti-raw-22/0000000000.pcd");
        let bytes = std::fs::read(&path).unwrap();
        let header = parse_header(&path, &bytes).unwrap();
        assert_eq!(header.points, 119_978);
        assert!(header.is_packed_xyzi());
        assert!(
            bytes.len() > header.data_start + header.points * 16,
            "the file has padding"
        );
        let points = read_pcd(&path).unwrap();
        assert_eq!(points.len(), 119_978);
        assert!(
            points
                .iter()
                .all(|p| p.is_finite() && p.norm_squared() < 130.0f32.powi(2))
        );
        // Round trip through every writer keeps every point bit for bit.
        let dir = tempfile::tempdir().unwrap();
        for encoding in [PcdData::Binary, PcdData::BinaryCompressed, PcdData::Ascii] {
            let out = dir.path().join("copy.pcd");
            write_pcd(&out, &points, encoding).unwrap();
            assert_eq!(read_pcd(&out).unwrap(), points, "{encoding:?}");
        }
    }
}
