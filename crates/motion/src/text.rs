//! Plain-text records: two-column (time, acceleration) text or CSV and
//! one-column text with a given time step, plus the number reader shared
//! with the AT2 parser.
//!
//! Text rules: blank lines and lines starting with `#`, `%` or `!` are
//! skipped; the first remaining line is taken as a column header (and
//! skipped) if none of its fields reads as a number. A line holding a comma
//! or semicolon is split there (CSV; an empty field is an error), any other
//! line at white space. Numbers may omit the leading zero (`-.83E-03`) and
//! use a Fortran `D` exponent (`1.0D-03`).

use crate::error::RecordError;
use crate::record::RawRecord;
use crate::spec::HeaderUnits;

/// Why a token is not accepted as a number.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NumberError {
    /// It does not read as a number.
    NotANumber,
    /// It reads as NaN or infinity (or overflows to infinity).
    NotFinite,
}

/// Read one number: Rust float syntax plus a Fortran `D`/`d` exponent;
/// NaN and infinity are rejected.
pub fn parse_number(token: &str) -> Result<f64, NumberError> {
    let parsed = match token.parse::<f64>() {
        Ok(x) => x,
        Err(_) => {
            if token.contains(['d', 'D']) && !token.contains(['e', 'E']) {
                let t: String = token.chars().map(|c| if c == 'd' || c == 'D' { 'E' } else { c }).collect();
                t.parse::<f64>().map_err(|_| NumberError::NotANumber)?
            } else {
                return Err(NumberError::NotANumber);
            }
        }
    };
    if parsed.is_finite() {
        Ok(parsed)
    } else {
        Err(NumberError::NotFinite)
    }
}

/// At most `max` characters of `text`, with how much was left out: error
/// messages quote user input, but never megabytes of it.
pub fn excerpt(text: &str, max: usize) -> String {
    match text.char_indices().nth(max) {
        None => text.to_string(),
        Some((cut, _)) => format!("{}... ({} more bytes)", &text[..cut], text.len() - cut),
    }
}

/// A number for a message: plain where that reads well, else in exponent
/// form (`1e-300`, not three hundred zeros).
pub fn number(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-3..1e6).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// Read `token` found on `line` of `file`, with the error that names both.
pub(crate) fn number_at(token: &str, file: &str, line: usize) -> Result<f64, RecordError> {
    parse_number(token).map_err(|e| match e {
        NumberError::NotANumber => RecordError::NotANumber { file: file.into(), line, token: excerpt(token, 40) },
        NumberError::NotFinite => RecordError::NotFinite { file: file.into(), line, token: excerpt(token, 40) },
    })
}

/// A data line of a text file: its 1-based number and its fields.
struct DataLine<'a> {
    line: usize,
    fields: Vec<&'a str>,
}

fn is_comment(trimmed: &str) -> bool {
    trimmed.starts_with(['#', '%', '!'])
}

fn split_fields<'a>(trimmed: &'a str, file: &str, line: usize) -> Result<Vec<&'a str>, RecordError> {
    if trimmed.contains([',', ';']) {
        let fields: Vec<&str> = trimmed.split([',', ';']).map(str::trim).collect();
        // a trailing separator ("1.0, 2.0,") is tolerated
        let used = match fields.last() {
            Some(last) if last.is_empty() && fields.len() > 1 => &fields[..fields.len() - 1],
            _ => &fields[..],
        };
        if used.iter().any(|f| f.is_empty()) {
            return Err(RecordError::Columns { file: file.into(), line, message: "empty field in CSV line".into() });
        }
        Ok(used.to_vec())
    } else {
        Ok(trimmed.split_whitespace().collect())
    }
}

/// The data lines of a text file (header and comments skipped).
fn data_lines<'a>(text: &'a str, file: &str) -> Result<Vec<DataLine<'a>>, RecordError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim().is_empty() {
        return Err(RecordError::Empty { file: file.into() });
    }
    let mut out = Vec::new();
    let mut first = true;
    for (i, raw) in text.lines().enumerate() {
        let trimmed = raw.trim();
        if trimmed.is_empty() || is_comment(trimmed) {
            continue;
        }
        let fields = split_fields(trimmed, file, i + 1)?;
        if first {
            first = false;
            if fields.iter().all(|f| parse_number(f).is_err()) {
                continue; // a column header such as "time,accel"
            }
        }
        out.push(DataLine { line: i + 1, fields });
    }
    if out.is_empty() {
        return Err(RecordError::TooShort { file: file.into(), message: "the file holds no data lines".into() });
    }
    Ok(out)
}

/// Largest allowed drift of a time-column entry from the uniform grid,
/// as a fraction of dt.
pub const TIME_TOLERANCE: f64 = 0.01;

/// Parse a text or CSV file with the time \[s\] in column 1 and the
/// acceleration (in file units) in column `column` (1-based, >= 2).
///
/// dt = (t_last - t_first) / (n - 1); every time must lie within
/// [`TIME_TOLERANCE`] · dt of t_first + i·dt. Columns other than these
/// two are not read.
pub fn parse_two_column(text: &str, file: &str, column: usize) -> Result<RawRecord, RecordError> {
    if column < 2 {
        return Err(RecordError::Spec {
            file: file.into(),
            field: "column",
            message: format!("column {column}: the acceleration column is 2 or more (time is column 1)"),
        });
    }
    let lines = data_lines(text, file)?;
    let mut times = Vec::with_capacity(lines.len());
    let mut values = Vec::with_capacity(lines.len());
    for dl in &lines {
        if dl.fields.len() < column {
            return Err(RecordError::Columns {
                file: file.into(),
                line: dl.line,
                message: format!(
                    "the line has {} field(s) but the acceleration is read from column {column}",
                    dl.fields.len()
                ),
            });
        }
        times.push(number_at(dl.fields[0], file, dl.line)?);
        values.push(number_at(dl.fields[column - 1], file, dl.line)?);
    }
    let n = values.len();
    let last_line = lines.last().map_or(1, |l| l.line);
    if n < 2 {
        return Err(RecordError::TooShort {
            file: file.into(),
            message: format!("a two-column file needs at least 2 samples to give dt, found {n}"),
        });
    }
    let t0 = times[0];
    let dt = (times[n - 1] - t0) / (n - 1) as f64;
    if !(dt.is_finite() && dt > 0.0) {
        return Err(RecordError::BadDt { file: file.into(), line: last_line, dt });
    }
    for (i, (t, dl)) in times.iter().zip(&lines).enumerate() {
        let expected = t0 + i as f64 * dt;
        if (t - expected).abs() > TIME_TOLERANCE * dt {
            return Err(RecordError::NonUniformTime { file: file.into(), line: dl.line, expected, found: *t, dt });
        }
    }
    Ok(RawRecord { dt, values, header: Vec::new(), first_time: Some(t0), header_units: HeaderUnits::NotInFormat })
}

/// Parse a text file of accelerations (in file units) at time step `dt`
/// \[s\]: one value per line, or, with `column` (1-based), that column of
/// each line.
pub fn parse_one_column(text: &str, file: &str, dt: f64, column: Option<usize>) -> Result<RawRecord, RecordError> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(RecordError::Spec { file: file.into(), field: "dt", message: format!("dt = {dt} s must be > 0") });
    }
    if column == Some(0) {
        return Err(RecordError::Spec { file: file.into(), field: "column", message: "columns count from 1".into() });
    }
    let lines = data_lines(text, file)?;
    let mut values = Vec::with_capacity(lines.len());
    for dl in &lines {
        let token = match column {
            None if dl.fields.len() == 1 => dl.fields[0],
            None => {
                return Err(RecordError::Columns {
                    file: file.into(),
                    line: dl.line,
                    message: format!(
                        "the line has {} fields; a one-column file holds one value per line \
                         (set `column` to pick one)",
                        dl.fields.len()
                    ),
                })
            }
            Some(c) if dl.fields.len() >= c => dl.fields[c - 1],
            Some(c) => {
                return Err(RecordError::Columns {
                    file: file.into(),
                    line: dl.line,
                    message: format!("the line has {} field(s) but column {c} is read", dl.fields.len()),
                })
            }
        };
        values.push(number_at(token, file, dl.line)?);
    }
    Ok(RawRecord { dt, values, header: Vec::new(), first_time: None, header_units: HeaderUnits::NotInFormat })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        assert_eq!(parse_number("-.8338791E-03"), Ok(-0.8338791e-3));
        assert_eq!(parse_number(".5"), Ok(0.5));
        assert_eq!(parse_number("1.5D+02"), Ok(150.0));
        assert_eq!(parse_number("+2"), Ok(2.0));
        assert_eq!(parse_number("NaN"), Err(NumberError::NotFinite));
        assert_eq!(parse_number("inf"), Err(NumberError::NotFinite));
        assert_eq!(parse_number("1e999"), Err(NumberError::NotFinite));
        assert_eq!(parse_number("1.2.3"), Err(NumberError::NotANumber));
        assert_eq!(parse_number("SEC"), Err(NumberError::NotANumber));
        assert_eq!(parse_number(""), Err(NumberError::NotANumber));
    }

    #[test]
    fn header_and_comments_skipped() {
        let r = parse_two_column("# comment\ntime,acc\n0,1\n0.5,2\n\n1.0,3\n", "f.csv", 2).unwrap();
        assert_eq!(r.values, vec![1.0, 2.0, 3.0]);
        assert_eq!(r.dt, 0.5);
    }

    #[test]
    fn csv_empty_field() {
        let e = parse_two_column("0,,1\n1,2,3\n", "f.csv", 2).unwrap_err().to_string();
        assert!(e.starts_with("f.csv:1:"), "{e}");
    }
}
