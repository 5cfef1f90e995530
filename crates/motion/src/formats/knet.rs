//! K-NET / KiK-net (NIED, Japan) ASCII records.
//!
//! Layout: header lines `Key   value` (the first `Origin Time`) up to the
//! line `Memo.`, then integer counts, 8 per line, in reading order. Keys
//! used:
//!
//! | key | use |
//! |---|---|
//! | `Sampling Freq(Hz)` | `100Hz`: dt = 1/f (required) |
//! | `Scale Factor` | `3920(gal)/6182761`: gal per count (required; a numerator in another unit than gal is refused) |
//! | `Max. Acc. (gal)` | checked against the PGA after the mean is removed: a warning beyond 1 % |
//! | `Dir.` | `N-S` (0°), `E-W` (90°), `U-D`, or KiK-net `1`..`6` (1-3 borehole, 4-6 surface; 3 and 6 vertical): a vertical component is refused unless `allow_vertical`, a borehole sensor gives a warning |
//! | `Duration Time(s)` | checked against the number of samples: a warning beyond 1 s + 1 % |
//!
//! Acceleration \[gal\] = counts × factor, then the mean of the whole
//! record is removed (K-NET data carry an offset); a warning names the
//! mean removed.

use crate::error::RecordError;
use crate::formats::channel::{Channel, Orientation};
use crate::formats::{peak, peak_warning};
use crate::record::RawRecord;
use crate::spec::{HeaderUnits, Units};
use crate::text::{excerpt, number, number_at, parse_number};

/// Largest number of header lines searched for `Memo.`.
const MAX_HEADER_LINES: usize = 100;

/// The value after `key` on the header line that starts with it, and the
/// line's 1-based number.
fn field<'a>(header: &[&'a str], key: &str) -> Option<(usize, &'a str)> {
    header.iter().enumerate().find_map(|(i, l)| l.trim_start().strip_prefix(key).map(|v| (i + 1, v.trim())))
}

/// Parse the text of a K-NET or KiK-net ASCII file; `file` names it in
/// errors. Values are returned in gal with the record's mean removed.
pub fn parse_knet(text: &str, file: &str) -> Result<RawRecord, RecordError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim().is_empty() {
        return Err(RecordError::Empty { file: file.into() });
    }
    let header_err = |line: usize, message: String| RecordError::Header { file: file.into(), line, message };
    let lines: Vec<&str> = text.lines().collect();
    let Some(memo) = lines.iter().take(MAX_HEADER_LINES).position(|l| l.trim_start().starts_with("Memo.")) else {
        return Err(header_err(
            lines.len().min(MAX_HEADER_LINES),
            "no `Memo.` line: a K-NET/KiK-net header (from `Origin Time`) ends with it".into(),
        ));
    };
    let head = &lines[..memo];

    let Some((freq_line, freq)) = field(head, "Sampling Freq(Hz)") else {
        return Err(header_err(
            memo + 1,
            "the header has no `Sampling Freq(Hz)` line: the time step is not stated".into(),
        ));
    };
    let f_token = freq.strip_suffix("Hz").or_else(|| freq.strip_suffix("HZ")).unwrap_or(freq).trim();
    let f = number_at(f_token, file, freq_line)?;
    let dt = 1.0 / f;
    if f <= 0.0 || !dt.is_finite() {
        return Err(header_err(freq_line, format!("sampling frequency `{}` must be > 0", excerpt(freq, 40))));
    }

    let factor = scale_factor(head, memo, file)?;

    let counts = counts(&lines, memo, factor, file)?;
    if counts.is_empty() {
        return Err(RecordError::TooShort { file: file.into(), message: "no counts after the `Memo.` line".into() });
    }
    let n = counts.len();
    // a running mean: no sum to overflow
    let mean_counts = counts.iter().enumerate().fold(0.0, |m, (k, c)| m + (c - m) / (k + 1) as f64);
    let mean = mean_counts * factor;
    let values: Vec<f64> = counts.iter().map(|c| c * factor - mean).collect();
    if values.iter().any(|v| !v.is_finite()) {
        return Err(header_err(memo + 2, "the counts are too large: their differences from the mean overflow".into()));
    }

    let mut warnings = vec![format!(
        "{file}: the record's mean, {mean:.4} gal ({mean_counts:.2} counts), was removed (K-NET/KiK-net data carry an \
         offset)"
    )];
    if let Some((_, max)) = field(head, "Max. Acc. (gal)") {
        if let Ok(max) = parse_number(max) {
            warnings.extend(peak_warning(file, "Max. Acc. (gal)", max, peak(&values), "gal"));
        }
    }
    if let Some((_, d)) = field(head, "Duration Time(s)") {
        if let Ok(d) = parse_number(d) {
            let length = n as f64 * dt;
            if (length - d).abs() > 1.0 + 0.01 * d {
                warnings.push(format!(
                    "{file}: the header's Duration Time(s) = {d} s but {n} samples at {f} Hz last {} s: check \
                     `Sampling Freq(Hz)`",
                    number(length)
                ));
            }
        }
    }
    let orientation = orientation(head, file, &mut warnings);
    let header = lines[..=memo].iter().map(|l| l.trim_end().to_string()).collect();
    Ok(RawRecord {
        dt,
        values,
        header,
        first_time: None,
        header_units: HeaderUnits::Stated(Units::CentimetersPerSecond2),
        warnings,
        channel: Some(Channel { number: 1, of: 1, orientation }),
    })
}

/// The header's `Scale Factor` in gal per count (`3920(gal)/6182761`).
fn scale_factor(head: &[&str], memo: usize, file: &str) -> Result<f64, RecordError> {
    let header_err = |line: usize, message: String| RecordError::Header { file: file.into(), line, message };
    let Some((scale_line, scale)) = field(head, "Scale Factor") else {
        return Err(header_err(memo + 1, "the header has no `Scale Factor` line: counts cannot be converted".into()));
    };
    let bad_scale = || {
        header_err(scale_line, format!("scale factor `{}` is not of the form `3920(gal)/6182761`", excerpt(scale, 40)))
    };
    let (numerator, denominator) = scale.rsplit_once('/').ok_or_else(bad_scale)?;
    let (value, unit) = numerator.split_once('(').ok_or_else(bad_scale)?;
    let unit = unit.trim().trim_end_matches(')').trim();
    if !unit.eq_ignore_ascii_case("gal") {
        return Err(header_err(
            scale_line,
            format!(
                "the scale factor `{}` is in `{}` per count, not gal: only a factor in gal per count is read",
                excerpt(scale, 40),
                excerpt(unit, 20)
            ),
        ));
    }
    let (num, den) = (parse_number(value.trim()), parse_number(denominator.trim()));
    match (num, den) {
        (Ok(a), Ok(b)) if a > 0.0 && b > 0.0 && (a / b).is_finite() && a / b > 0.0 => Ok(a / b),
        _ => Err(bad_scale()),
    }
}

/// The whole-number counts after the `Memo.` line, each finite once
/// scaled by `factor`.
fn counts(lines: &[&str], memo: usize, factor: f64, file: &str) -> Result<Vec<f64>, RecordError> {
    let header_err = |line: usize, message: String| RecordError::Header { file: file.into(), line, message };
    let mut counts: Vec<f64> = Vec::new();
    for (i, raw) in lines.iter().enumerate().skip(memo + 1) {
        for token in raw.split_whitespace() {
            let c = number_at(token, file, i + 1)?;
            if c.fract() != 0.0 {
                return Err(header_err(
                    i + 1,
                    format!("`{}` is not a whole number: K-NET/KiK-net data are integer counts", excerpt(token, 40)),
                ));
            }
            if !(c * factor).is_finite() {
                return Err(header_err(i + 1, format!("count `{}` × the scale factor overflows", excerpt(token, 40))));
            }
            counts.push(c);
        }
    }
    Ok(counts)
}

/// The channel's direction from the header's `Dir.`, warning of a KiK-net
/// borehole sensor.
fn orientation(head: &[&str], file: &str, warnings: &mut Vec<String>) -> Orientation {
    let mut orientation = Orientation::Unknown;
    if let Some((_, dir)) = field(head, "Dir.") {
        let d = dir.to_ascii_uppercase();
        orientation = match d.as_str() {
            "U-D" | "UD" | "3" | "6" => Orientation::Vertical { label: excerpt(dir, 10) },
            "N-S" | "NS" | "1" | "4" => Orientation::Azimuth { degrees: 0.0 },
            "E-W" | "EW" | "2" | "5" => Orientation::Azimuth { degrees: 90.0 },
            _ => Orientation::Unknown,
        };
        if matches!(d.as_str(), "1" | "2" | "3") {
            warnings.push(format!(
                "{file}: Dir. `{dir}` is a KiK-net borehole sensor (1-3), recorded at depth, not at the ground \
                 surface (4-6)"
            ));
        }
    }
    orientation
}

#[cfg(test)]
mod tests {
    use super::*;

    fn knet(dir: &str, max: &str, data: &str) -> String {
        format!(
            "Origin Time       2000/01/01 00:00:00\nLat.              35.000\nStation Code      TST001\n\
             Sampling Freq(Hz) 100Hz\nDuration Time(s)  0\nDir.              {dir}\n\
             Scale Factor      3920(gal)/6182761\nMax. Acc. (gal)   {max}\nMemo.\n{data}"
        )
    }

    #[test]
    fn counts_scaled_and_mean_removed() {
        // counts 100 +- 10: the offset 100 is removed
        let r =
            parse_knet(&knet("N-S", "0.00634", "  100  110   90  100  100  100  100  100\n  100\n"), "k.NS").unwrap();
        assert_eq!(r.dt, 0.01);
        assert_eq!(r.values.len(), 9);
        let factor = 3920.0 / 6182761.0;
        assert!((r.values[1] - 10.0 * factor).abs() < 1e-15 && (r.values[2] + 10.0 * factor).abs() < 1e-15);
        assert_eq!(r.header_units, HeaderUnits::Stated(Units::CentimetersPerSecond2));
        assert_eq!(r.header.last().unwrap(), "Memo.");
        assert_eq!(r.warnings.len(), 1, "{:?}", r.warnings);
        assert!(r.warnings[0].contains("mean, 0.0634 gal (100.00 counts), was removed"), "{:?}", r.warnings);
    }

    #[test]
    fn warnings_and_refusals() {
        let r = parse_knet(&knet("U-D", "1.0", "1 2 3\n"), "k.UD").unwrap();
        assert!(r.warnings.iter().any(|w| w.contains("Max. Acc. (gal) = 1 gal")), "{:?}", r.warnings);
        assert!(r.channel.unwrap().orientation.is_vertical());
        let r = parse_knet(&knet("3", "0.0006", "1 2 3\n"), "k.UD1").unwrap();
        assert!(r.channel.unwrap().orientation.is_vertical() && r.warnings.iter().any(|w| w.contains("borehole")));
        let r = parse_knet(&knet("E-W", "0.0006", "1 2 3\n"), "k.EW").unwrap();
        assert_eq!(r.channel.unwrap().orientation, Orientation::Azimuth { degrees: 90.0 });
        let e = parse_knet(&knet("E-W", "1", "1 2\n").replace("(gal)", "(m/s2)"), "k").unwrap_err().to_string();
        assert!(e.starts_with("k:7: the scale factor `3920(m/s2)/6182761` is in `m/s2` per count, not gal"), "{e}");
        let e = parse_knet(&knet("E-W", "1", "1 2.5\n"), "k").unwrap_err().to_string();
        assert!(e.starts_with("k:10: `2.5` is not a whole number"), "{e}");
        let e = parse_knet("Origin Time  x\n1 2\n", "k").unwrap_err().to_string();
        assert!(e.contains("no `Memo.` line"), "{e}");
        for f in ["0Hz", "5e-324Hz", "-100Hz"] {
            let e = parse_knet(&knet("E-W", "1", "1\n").replace("100Hz", f), "k").unwrap_err().to_string();
            assert!(e.starts_with(&format!("k:4: sampling frequency `{f}` must be > 0")), "{e}");
        }
    }
}
