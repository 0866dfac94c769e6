//! C `printf` number formats (`%.*e`, `%.*g`), as KITTI's own tools wrote its text files.

/// `printf("%.{precision}e", v)`: one digit, `precision` decimals, a signed exponent of at
/// least two digits (`9.999976e-01`).
pub(crate) fn c_exp(v: f64, precision: usize) -> String {
    if !v.is_finite() {
        return c_special(v);
    }
    let rust = format!("{v:.precision$e}");
    let (mantissa, exponent) = rust.split_once('e').unwrap_or((&rust, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    let sign = if exponent < 0 { '-' } else { '+' };
    format!("{mantissa}e{sign}{:02}", exponent.unsigned_abs())
}

/// `printf("%.{precision}g", v)`: `precision` significant digits, trailing zeros removed,
/// exponent form only for very small or large magnitudes (`0.0090951755733632`, `4`).
pub(crate) fn c_general(v: f64, precision: usize) -> String {
    if !v.is_finite() {
        return c_special(v);
    }
    let precision = precision.max(1);
    if v == 0.0 {
        return if v.is_sign_negative() { "-0" } else { "0" }.to_string();
    }
    // The exponent after rounding to `precision` digits decides the style, as C does.
    let rounded = format!("{v:.prec$e}", prec = precision - 1);
    let exponent: i32 = rounded
        .split_once('e')
        .map_or(0, |(_, e)| e.parse().unwrap_or(0));
    if exponent < -4 || exponent >= precision as i32 {
        let (mantissa, _) = rounded.split_once('e').unwrap_or((&rounded, ""));
        let sign = if exponent < 0 { '-' } else { '+' };
        format!(
            "{}e{sign}{:02}",
            strip_zeros(mantissa),
            exponent.unsigned_abs()
        )
    } else {
        let decimals = (precision as i32 - 1 - exponent).max(0) as usize;
        strip_zeros(&format!("{v:.decimals$}")).to_string()
    }
}

/// C's spelling of infinities and NaN.
fn c_special(v: f64) -> String {
    if v.is_nan() {
        "nan".into()
    } else if v > 0.0 {
        "inf".into()
    } else {
        "-inf".into()
    }
}

/// Removes trailing zeros after a decimal point, and the point if nothing follows it.
fn strip_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exp_matches_printf() {
        assert_eq!(c_exp(0.9999976, 6), "9.999976e-01");
        assert_eq!(c_exp(721.5377, 6), "7.215377e+02");
        assert_eq!(c_exp(0.0, 6), "0.000000e+00");
        assert_eq!(c_exp(-387.5744, 12), "-3.875744000000e+02");
        assert_eq!(c_exp(1e-100, 2), "1.00e-100");
    }

    #[test]
    fn general_matches_printf() {
        assert_eq!(c_general(49.015003823272, 14), "49.015003823272");
        assert_eq!(c_general(-6.811441479104, 14), "-6.811441479104");
        assert_eq!(c_general(0.0090951755733632, 14), "0.0090951755733632");
        assert_eq!(c_general(0.035752, 14), "0.035752");
        assert_eq!(c_general(4.0, 14), "4");
        assert_eq!(c_general(-0.5, 14), "-0.5");
        assert_eq!(c_general(1.5e-7, 14), "1.5e-07");
        assert_eq!(c_general(123456789012346.0, 14), "1.2345678901235e+14");
        assert_eq!(c_general(99999.99999999999, 5), "1e+05");
        assert_eq!(c_general(0.0001, 3), "0.0001");
        assert_eq!(c_general(f64::NAN, 3), "nan");
    }
}
