//! KITTI OXTS text: one packet of 30 values per line (`oxts/data/<frame>.txt` in raw drives,
//! `oxts/<seq>.txt` with one line per frame in the tracking layout), and `dataformat.txt`.

use std::path::Path;

use trackd_perception::oxts::Oxts;

use crate::error::{DatasetError, parse_f64, read_text, write_bytes};
use crate::numfmt::c_general;

/// The 30 field names in `dataformat.txt` order.
pub const FIELD_NAMES: [&str; Oxts::FIELDS] = [
    "lat",
    "lon",
    "alt",
    "roll",
    "pitch",
    "yaw",
    "vn",
    "ve",
    "vf",
    "vl",
    "vu",
    "ax",
    "ay",
    "az",
    "af",
    "al",
    "au",
    "wx",
    "wy",
    "wz",
    "wf",
    "wl",
    "wu",
    "pos_accuracy",
    "vel_accuracy",
    "navstat",
    "numsats",
    "posmode",
    "velmode",
    "orimode",
];

/// KITTI's `oxts/dataformat.txt`, word for word (its typos included).
pub const DATAFORMAT: &str = "\
lat:   latitude of the oxts-unit (deg)
lon:   longitude of the oxts-unit (deg)
alt:   altitude of the oxts-unit (m)
roll:  roll angle (rad),    0 = level, positive = left side up,      range: -pi   .. +pi
pitch: pitch angle (rad),   0 = level, positive = front down,        range: -pi/2 .. +pi/2
yaw:   heading (rad),       0 = east,  positive = counter clockwise, range: -pi   .. +pi
vn:    velocity towards north (m/s)
ve:    velocity towards east (m/s)
vf:    forward velocity, i.e. parallel to earth-surface (m/s)
vl:    leftward velocity, i.e. parallel to earth-surface (m/s)
vu:    upward velocity, i.e. perpendicular to earth-surface (m/s)
ax:    acceleration in x, i.e. in direction of vehicle front (m/s^2)
ay:    acceleration in y, i.e. in direction of vehicle left (m/s^2)
ay:    acceleration in z, i.e. in direction of vehicle top (m/s^2)
af:    forward acceleration (m/s^2)
al:    leftward acceleration (m/s^2)
au:    upward acceleration (m/s^2)
wx:    angular rate around x (rad/s)
wy:    angular rate around y (rad/s)
wz:    angular rate around z (rad/s)
wf:    angular rate around forward axis (rad/s)
wl:    angular rate around leftward axis (rad/s)
wu:    angular rate around upward axis (rad/s)
pos_accuracy:  velocity accuracy (north/east in m)
vel_accuracy:  velocity accuracy (north/east in m/s)
navstat:       navigation status (see navstat_to_string)
numsats:       number of satellites tracked by primary GPS receiver
posmode:       position mode of primary GPS receiver (see gps_mode_to_string)
velmode:       velocity mode of primary GPS receiver (see gps_mode_to_string)
orimode:       orientation mode of primary GPS receiver (see gps_mode_to_string)
";

/// Index of the first integer field (`navstat`); the five from there on are integers.
const FIRST_INTEGER: usize = 25;

/// Reads one raw-drive packet file (`oxts/data/<frame>.txt`: one line of 30 values).
pub fn read_oxts(path: &Path) -> Result<Oxts, DatasetError> {
    let text = read_text(path)?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let (index, line) = lines
        .next()
        .ok_or_else(|| DatasetError::format(path, "empty OXTS file"))?;
    if let Some((extra, _)) = lines.next() {
        return Err(DatasetError::parse(
            path,
            extra + 1,
            "a raw-drive OXTS file holds one packet (one line)",
        ));
    }
    parse_oxts_line(path, index + 1, line)
}

/// Reads a tracking-layout OXTS file (`oxts/<seq>.txt`): one packet per line, line i = frame i.
pub fn read_oxts_lines(path: &Path) -> Result<Vec<Oxts>, DatasetError> {
    let text = read_text(path)?;
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, line)| parse_oxts_line(path, i + 1, line))
        .collect()
}

/// Parses one line of 30 whitespace-separated values (`line` is its 1-based number, for
/// errors).
pub fn parse_oxts_line(path: &Path, line: usize, text: &str) -> Result<Oxts, DatasetError> {
    let tokens: Vec<&str> = text.split_whitespace().collect();
    if tokens.len() != Oxts::FIELDS {
        return Err(DatasetError::parse(
            path,
            line,
            format!(
                "{} values, an OXTS packet has {}",
                tokens.len(),
                Oxts::FIELDS
            ),
        ));
    }
    let mut values = [0.0; Oxts::FIELDS];
    for (i, (v, token)) in values.iter_mut().zip(tokens).enumerate() {
        *v = parse_f64(path, line, FIELD_NAMES[i], token)?;
        if i >= FIRST_INTEGER && v.fract() != 0.0 {
            return Err(DatasetError::parse(
                path,
                line,
                format!("{}: {token:?} is not an integer", FIELD_NAMES[i]),
            ));
        }
    }
    Ok(Oxts::from_values(&values))
}

/// One packet as KITTI writes it: 30 values separated by spaces, reals as `%.14g`, the last
/// five as integers; no newline.
pub fn format_oxts(oxts: &Oxts) -> String {
    let values = oxts.to_values();
    let mut out = String::with_capacity(Oxts::FIELDS * 18);
    for (i, v) in values.iter().enumerate() {
        if i > 0 {
            out.push(' ');
        }
        if i >= FIRST_INTEGER {
            out.push_str(&(*v as i64).to_string());
        } else {
            out.push_str(&c_general(*v, 14));
        }
    }
    out
}

/// Writes one raw-drive packet file (`oxts/data/<frame>.txt`): one line, KITTI formatting.
pub fn write_oxts(path: &Path, oxts: &Oxts) -> Result<(), DatasetError> {
    write_bytes(path, format!("{}\n", format_oxts(oxts)).as_bytes())
}

/// Writes a tracking-layout OXTS file (`oxts/<seq>.txt`): one packet per line.
pub fn write_oxts_lines(path: &Path, packets: &[Oxts]) -> Result<(), DatasetError> {
    let text: String = packets.iter().map(|o| format_oxts(o) + "\n").collect();
    write_bytes(path, text.as_bytes())
}

/// Writes KITTI's `oxts/dataformat.txt`.
pub fn write_dataformat(path: &Path) -> Result<(), DatasetError> {
    write_bytes(path, DATAFORMAT.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shared_data_dir;

    fn packet() -> Oxts {
        let mut v = [0.0; Oxts::FIELDS];
        for (i, x) in v.iter_mut().enumerate() {
            *x = if i >= FIRST_INTEGER {
                i as f64
            } else {
                (i as f64 + 0.123456789) * 1.7 - 20.0
            };
        }
        v[0] = 49.015003823272;
        v[1] = 8.4342971002335;
        Oxts::from_values(&v)
    }

    #[test]
    fn write_then_read_round_trips_to_14_digits() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("0000000000.txt");
        let o = packet();
        write_oxts(&path, &o).unwrap();
        let back = read_oxts(&path).unwrap();
        for (a, b) in o.to_values().iter().zip(back.to_values()) {
            assert!((a - b).abs() <= 1e-12 * a.abs().max(1.0), "{a} vs {b}");
        }
        let lines = dir.path().join("0000.txt");
        write_oxts_lines(&lines, &[o, back, o]).unwrap();
        let all = read_oxts_lines(&lines).unwrap();
        assert_eq!(all.len(), 3);
        assert_eq!(all[1], back);
    }

    #[test]
    fn real_packet_is_read_and_written_back_identically() {
        let Some(data) = shared_data_dir("oxts::real_packet_is_read_and_written_back_identically")
        else {
            return;
        };
        let drive =
            data.join("kitti-format-samples/raw/2011_09_26/2011_09_26_drive_0001_sync/oxts");
        let path = drive.join("data/0000000000.txt");
        let o = read_oxts(&path).unwrap();
        assert_eq!(o.lat, 49.015003823272);
        assert_eq!(o.yaw, -2.6087069803847);
        assert_eq!((o.navstat, o.numsats, o.orimode), (4, 11, 6));
        let original = std::fs::read_to_string(&path).unwrap();
        assert_eq!(format_oxts(&o), original.trim_end());
        let dataformat = std::fs::read_to_string(drive.join("dataformat.txt")).unwrap();
        assert_eq!(DATAFORMAT, dataformat);
        for (line, name) in dataformat.lines().zip(FIELD_NAMES) {
            // The file itself misnames az as "ay"; every other line starts with its name.
            if name != "az" {
                assert!(line.starts_with(&format!("{name}:")), "{line}");
            }
        }
    }

    #[test]
    fn wrong_field_count_names_file_and_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("0000.txt");
        let good = format_oxts(&packet());
        std::fs::write(&path, format!("{good}\n{good} 7\n")).unwrap();
        let err = read_oxts_lines(&path).unwrap_err();
        assert!(matches!(err, DatasetError::Parse { line: 2, .. }), "{err}");
        assert!(err.to_string().contains("0000.txt:2: 31 values"), "{err}");
    }

    #[test]
    fn non_numeric_and_fractional_integer_fields_are_errors() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.txt");
        let mut tokens: Vec<String> = format_oxts(&packet())
            .split(' ')
            .map(String::from)
            .collect();
        tokens[5] = "north".into();
        std::fs::write(&path, tokens.join(" ")).unwrap();
        let err = read_oxts(&path).unwrap_err();
        assert!(
            err.to_string().contains("yaw: \"north\" is not a number"),
            "{err}"
        );
        tokens[5] = "0.1".into();
        tokens[26] = "11.5".into();
        std::fs::write(&path, tokens.join(" ")).unwrap();
        let err = read_oxts(&path).unwrap_err();
        assert!(err.to_string().contains("numsats"), "{err}");
        std::fs::write(&path, "").unwrap();
        assert!(matches!(
            read_oxts(&path).unwrap_err(),
            DatasetError::Format { .. }
        ));
        let good = format_oxts(&packet());
        std::fs::write(&path, format!("{good}\n{good}\n")).unwrap();
        assert!(matches!(
            read_oxts(&path).unwrap_err(),
            DatasetError::Parse { line: 2, .. }
        ));
    }
}
