//! KITTI raw timestamp files (`velodyne_points/timestamps.txt`, `oxts/timestamps.txt`): one
//! UTC date-time per line, `2011-09-26 13:02:25.964389445`. In memory: seconds since the Unix
//! epoch as `f64` (sub-microsecond precision for dates of this century).

use std::path::Path;

use crate::error::{DatasetError, read_text, write_bytes};

/// Reads a timestamps file: seconds since the Unix epoch, one per non-empty line.
pub fn read_timestamps(path: &Path) -> Result<Vec<f64>, DatasetError> {
    let text = read_text(path)?;
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| {
            parse_timestamp(l.trim()).ok_or_else(|| {
                DatasetError::parse(
                    path,
                    i + 1,
                    format!("{l:?} is not a KITTI timestamp (YYYY-MM-DD hh:mm:ss.fffffffff)"),
                )
            })
        })
        .collect()
}

/// Writes a timestamps file: one KITTI date-time line (nanosecond digits) per value of seconds
/// since the Unix epoch.
pub fn write_timestamps(path: &Path, seconds: &[f64]) -> Result<(), DatasetError> {
    let text: String = seconds
        .iter()
        .map(|&s| format_timestamp(s) + "\n")
        .collect();
    write_bytes(path, text.as_bytes())
}

/// `2011-09-26 13:02:25.964389445` -> seconds since the Unix epoch (UTC); `None` if malformed.
pub fn parse_timestamp(text: &str) -> Option<f64> {
    let (date, time) = text.split_once(' ')?;
    let mut d = date.split('-');
    let (year, month, day) = (
        d.next()?.parse::<i64>().ok()?,
        d.next()?.parse::<u32>().ok()?,
        d.next()?.parse::<u32>().ok()?,
    );
    if d.next().is_some() || !(1..=12).contains(&month) || !(1..=31).contains(&day) {
        return None;
    }
    let mut t = time.trim().split(':');
    let (hour, minute, second) = (
        t.next()?.parse::<u32>().ok()?,
        t.next()?.parse::<u32>().ok()?,
        t.next()?,
    );
    if t.next().is_some() || hour > 23 || minute > 59 {
        return None;
    }
    let (whole, fraction) = second.split_once('.').unwrap_or((second, ""));
    let whole: u32 = whole.parse().ok()?;
    if whole > 60 || !fraction.chars().all(|c| c.is_ascii_digit()) || fraction.len() > 9 {
        return None;
    }
    let fraction = if fraction.is_empty() {
        0.0
    } else {
        format!("0.{fraction}").parse::<f64>().ok()?
    };
    let days = days_from_civil(year, month, day);
    let seconds = days * 86_400 + i64::from(hour * 3600 + minute * 60 + whole);
    Some(seconds as f64 + fraction)
}

/// Seconds since the Unix epoch -> `2011-09-26 13:02:25.964389445` (UTC).
pub fn format_timestamp(seconds: f64) -> String {
    let mut whole = seconds.floor() as i64;
    let mut nanos = ((seconds - seconds.floor()) * 1e9).round() as i64;
    if nanos >= 1_000_000_000 {
        whole += 1;
        nanos -= 1_000_000_000;
    }
    let (days, secs) = (whole.div_euclid(86_400), whole.rem_euclid(86_400));
    let (year, month, day) = civil_from_days(days);
    format!(
        "{year:04}-{month:02}-{day:02} {:02}:{:02}:{:02}.{nanos:09}",
        secs / 3600,
        secs / 60 % 60,
        secs % 60
    )
}

/// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's algorithm).
fn days_from_civil(year: i64, month: u32, day: u32) -> i64 {
    let y = if month <= 2 { year - 1 } else { year };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let m = i64::from(month);
    let doy = (153 * (if m > 2 { m - 3 } else { m + 9 }) + 2) / 5 + i64::from(day) - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

/// The date of a day count since 1970-01-01 (inverse of [`days_from_civil`]).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let month = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let year = yoe + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shared_data_dir;

    #[test]
    fn known_dates() {
        assert_eq!(parse_timestamp("1970-01-01 00:00:00.000000000"), Some(0.0));
        // 2011-09-26 13:02:25 UTC = 1317042145 (date -u -d ... +%s).
        let t = parse_timestamp("2011-09-26 13:02:25.964389445").unwrap();
        assert!((t - 1_317_042_145.0 - 0.964_389_445).abs() < 1e-6, "{t}");
        assert_eq!(parse_timestamp("2000-02-29 23:59:59"), Some(951_868_799.0));
        assert_eq!(
            format_timestamp(951_868_799.0),
            "2000-02-29 23:59:59.000000000"
        );
        assert_eq!(
            format_timestamp(1_317_042_145.5),
            "2011-09-26 13:02:25.500000000"
        );
    }

    #[test]
    fn malformed_timestamps_are_rejected() {
        for bad in [
            "2011-09-26",
            "2011-13-01 00:00:00",
            "2011-09-26 25:00:00",
            "2011-09-26 12:00:00.12x",
            "yesterday noon",
            "2011-09-26 12:00:00.1234567891",
        ] {
            assert_eq!(parse_timestamp(bad), None, "{bad}");
        }
    }

    #[test]
    fn write_then_read_keeps_microseconds() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("timestamps.txt");
        let seconds: Vec<f64> = (0..50)
            .map(|i| 1_317_042_145.964_389 + 0.103_2 * i as f64)
            .collect();
        write_timestamps(&path, &seconds).unwrap();
        let back = read_timestamps(&path).unwrap();
        assert_eq!(back.len(), seconds.len());
        for (a, b) in seconds.iter().zip(&back) {
            assert!((a - b).abs() < 1e-6, "{a} vs {b}");
        }
    }

    #[test]
    fn bad_line_names_file_and_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("timestamps.txt");
        std::fs::write(
            &path,
            "2011-09-26 13:02:25.964389445\n2011-09-26 13:02:26.0x\n",
        )
        .unwrap();
        let err = read_timestamps(&path).unwrap_err();
        assert!(matches!(err, DatasetError::Parse { line: 2, .. }), "{err}");
    }

    #[test]
    fn real_files_are_read_and_written_back_identically() {
        let Some(data) =
            shared_data_dir("timestamps::real_files_are_read_and_written_back_identically")
        else {
            return;
        };
        let path = data.join("kitti-format-samples/raw/2011_09_26/2011_09_26_drive_0001_sync/velodyne_points/timestamps.txt");
        let seconds = read_timestamps(&path).unwrap();
        assert_eq!(seconds.len(), 108);
        let steps: Vec<f64> = seconds.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(
            steps.iter().all(|d| (0.09..0.12).contains(d)),
            "10 Hz: {steps:?}"
        );
        // f64 holds 1.3e9 s to 2.4e-7 s: the text written back is the same instant to that.
        let original = std::fs::read_to_string(&path).unwrap();
        for (line, s) in original.lines().zip(&seconds) {
            let again = format_timestamp(*s);
            assert_eq!(again[..20], line[..20], "{line}");
            let nanos = |t: &str| t[20..].parse::<i64>().unwrap();
            assert!(
                (nanos(&again) - nanos(line)).abs() < 300,
                "{line} vs {again}"
            );
        }
    }
}
