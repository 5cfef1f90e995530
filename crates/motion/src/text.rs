//! Plain-text records: two-column (time, acceleration) text or CSV,
//! one-column text with a given time step and a sequence of values in
//! reading order, plus the number reader shared with the other parsers.
//!
//! Text rules: blank lines and lines starting with `#`, `%` or `!` are
//! skipped; the first remaining line is taken as a column header (and
//! skipped) if none of its fields reads as a number; a later line that
//! starts with a word is not numeric data, and the error names the formats
//! read. A line holding a semicolon is split there, else a line holding a
//! comma is split there (CSV; an empty field is an error, and every line
//! of a CSV file must have as many fields as the first), any other line at
//! white space. Decimal commas (`0,005;0,0173`, `0,005\t0,0173`) are
//! refused, never read: a comma also separates values. Numbers may omit the
//! leading zero (`-.83E-03`) and use a Fortran `D` exponent (`1.0D-03`).

mod lines;

pub(crate) use lines::{data_lines, Table};

use crate::error::RecordError;
use crate::label::time_label_unit;
use crate::record::RawRecord;
use crate::spec::{Format, HeaderUnits};

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

/// Refuse a two-column file whose time column's header says it is not in
/// seconds (`time_ms`).
fn check_time_label(table: &Table, file: &str) -> Result<(), RecordError> {
    let Some(h) = &table.header else { return Ok(()) };
    let Some(label) = h.labels.first() else { return Ok(()) };
    match time_label_unit(label) {
        Some(unit) => Err(RecordError::Header {
            file: file.into(),
            line: h.line,
            message: format!(
                "the time column's header `{}` says {unit}: the time column must be in seconds (convert it, or read \
                 the acceleration alone with `format = \"one-column\"`, `column` and `dt`)",
                excerpt(label, 40)
            ),
        }),
        None => Ok(()),
    }
}

/// Largest allowed drift of a time-column entry from the uniform grid,
/// as a fraction of dt.
pub const TIME_TOLERANCE: f64 = 0.01;

/// Parse a text or CSV file with the time \[s\] in column 1 and the
/// acceleration (in file units) in column `column` (1-based, >= 2).
///
/// dt = (t_last - t_first) / (n - 1); every time must lie within
/// [`TIME_TOLERANCE`] · dt of t_first + i·dt. Columns other than these
/// two are not read. A unit named in the acceleration column's header
/// (`acc_m_s2`, `acc [g]`) is returned as [`HeaderUnits::Label`]; a time
/// column whose header names milliseconds or minutes is refused.
pub fn parse_two_column(text: &str, file: &str, column: usize) -> Result<RawRecord, RecordError> {
    if column < 2 {
        return Err(RecordError::Spec {
            file: file.into(),
            field: "column",
            message: format!("column {column}: the acceleration column is 2 or more (time is column 1)"),
        });
    }
    let table = data_lines(text, file, Format::TwoColumn)?;
    check_time_label(&table, file)?;
    let lines = &table.lines;
    let mut times = Vec::with_capacity(lines.len());
    let mut values = Vec::with_capacity(lines.len());
    for dl in lines {
        if dl.fields.len() < column {
            let message = if lines[0].fields.len() == 1 && column == 2 {
                "the line has 1 field but a two-column file (time, acceleration) is read because no `dt` was given: \
                 a file with one value per line needs the time step `dt` [s] (and `units`)"
                    .to_string()
            } else {
                let hint = table.layout_hint().map(|h| format!("; {h}")).unwrap_or_default();
                format!(
                    "the line has {} field(s) but the acceleration is read from column {column}{hint}",
                    dl.fields.len()
                )
            };
            return Err(RecordError::Columns { file: file.into(), line: dl.line, message });
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
        if let Some(hint) = table.layout_hint() {
            let message = format!("column 1 is not a time axis: it gives a time step dt = {dt} s; {hint}");
            return Err(RecordError::Columns { file: file.into(), line: last_line, message });
        }
        return Err(RecordError::BadDt { file: file.into(), line: last_line, dt });
    }
    for (i, (t, dl)) in times.iter().zip(lines).enumerate() {
        let expected = t0 + i as f64 * dt;
        if (t - expected).abs() > TIME_TOLERANCE * dt {
            if let Some(hint) = table.layout_hint() {
                let message = format!(
                    "the time column is not uniform: t = {t} s where {expected} s was expected (dt = {dt} s from the \
                     first and last times; tolerance 1 % of dt); {hint}"
                );
                return Err(RecordError::Columns { file: file.into(), line: dl.line, message });
            }
            return Err(RecordError::NonUniformTime { file: file.into(), line: dl.line, expected, found: *t, dt });
        }
    }
    Ok(RawRecord {
        dt,
        values,
        header: Vec::new(),
        first_time: Some(t0),
        header_units: table.units_of_column(column),
        warnings: Vec::new(),
        channel: None,
    })
}

/// A warning for a one-column or sequence file of whole numbers only: they
/// may be digitiser counts (a K-NET body), to be read with their header.
fn counts_warning(values: &[f64], file: &str) -> Option<String> {
    let max = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    (values.len() >= 10 && max >= 100.0 && values.iter().all(|v| v.fract() == 0.0)).then(|| {
        format!(
            "{file}: every value is a whole number (up to {max}): if these are digitiser counts (the body of a \
             K-NET/KiK-net file), read the K-NET file itself, whose header gives the factor to gal and whose offset \
             is then removed"
        )
    })
}

/// Refuse `column` with `dt` on a file whose column 1 is a time axis
/// (uniform, increasing, from 0) with a step other than `dt`, or whose
/// lines look like one sequence wrapped k per line (the last one shorter),
/// where `column` would read every k-th sample.
fn check_column_pick(table: &Table, file: &str, dt: f64, column: usize) -> Result<(), RecordError> {
    let lines = &table.lines;
    let spec_err = |field, message| Err(RecordError::Spec { file: file.into(), field, message });
    let counts: Vec<usize> = lines.iter().map(|l| l.fields.len()).collect();
    let (k, last) = (counts[0], counts[counts.len() - 1]);
    if lines.len() >= 2 && k >= 2 && counts[..counts.len() - 1].iter().all(|&c| c == k) && last < k {
        return spec_err(
            "column",
            format!(
                "line {} (the last) holds {last} values where the others hold {k}: the values look like one \
                 sequence written {k} per line, and `column = {column}` would read one sample in {k}: if they are \
                 successive samples, read them with `format = \"sequence\"` (and no `column`)",
                lines[lines.len() - 1].line
            ),
        );
    }
    if lines.len() < 3 || counts.iter().any(|&c| c < 2) {
        return Ok(());
    }
    let Ok(t) = lines.iter().map(|l| parse_number(l.fields[0])).collect::<Result<Vec<f64>, _>>() else {
        return Ok(());
    };
    let n = t.len();
    let step = (t[n - 1] - t[0]) / (n - 1) as f64;
    let uniform = step > 0.0
        && t[0].abs() <= TIME_TOLERANCE * step
        && t.iter().enumerate().all(|(i, x)| (x - (t[0] + i as f64 * step)).abs() <= TIME_TOLERANCE * step);
    if !uniform {
        return Ok(());
    }
    if column == 1 {
        return spec_err(
            "column",
            format!(
                "column 1 is a time axis (0, {}, {} ... s): the acceleration is in another column; better, drop \
                 `dt` and `column` so that the file is read as time and acceleration",
                number(t[1]),
                number(t[2])
            ),
        );
    }
    if (step - dt).abs() > TIME_TOLERANCE * step {
        return spec_err(
            "dt",
            format!(
                "column 1 is a time axis with a step of {} s but `dt = {dt}` s is given: drop `dt` (and \
                 `format = \"one-column\"`) so that the file's time column is used, with `column = {column}` for the \
                 acceleration",
                number(step)
            ),
        );
    }
    Ok(())
}

/// Parse a text file of accelerations (in file units) at time step `dt`
/// \[s\]: one value per line, or, with `column` (1-based), that column of
/// each line. With `column`, a file whose column 1 is a time axis of
/// another step than `dt`, or whose lines look like one sequence wrapped
/// (the last line shorter), is refused.
pub fn parse_one_column(text: &str, file: &str, dt: f64, column: Option<usize>) -> Result<RawRecord, RecordError> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(RecordError::Spec { file: file.into(), field: "dt", message: format!("dt = {dt} s must be > 0") });
    }
    if column == Some(0) {
        return Err(RecordError::Spec { file: file.into(), field: "column", message: "columns count from 1".into() });
    }
    let table = data_lines(text, file, Format::OneColumn)?;
    if let Some(c) = column {
        check_column_pick(&table, file, dt, c)?;
    }
    let mut values = Vec::with_capacity(table.lines.len());
    for dl in &table.lines {
        let token = match column {
            None if dl.fields.len() == 1 => dl.fields[0],
            None => {
                return Err(RecordError::Columns {
                    file: file.into(),
                    line: dl.line,
                    message: format!(
                        "the line has {} fields; a one-column file holds one value per line. If the values on a line \
                         are successive samples (the body of a K-NET, COSMOS or PEER file), read them with \
                         `format = \"sequence\"`; if the columns are different quantities, set `column` to the \
                         acceleration's",
                        dl.fields.len()
                    ),
                });
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
    let header_units = match (column, &table.header) {
        (None, Some(h)) if h.labels.len() == 1 => table.units_of_column(1),
        (Some(c), _) => table.units_of_column(c),
        _ => HeaderUnits::NotInFormat,
    };
    let warnings = counts_warning(&values, file).into_iter().collect();
    Ok(RawRecord { dt, values, header: Vec::new(), first_time: None, header_units, warnings, channel: None })
}

/// `field` cut before every `+` or `-` that follows a digit or a point:
/// Fortran fixed-width fields written without a space between them
/// (`-90.15800-109.02749` is `-90.15800` and `-109.02749`); an exponent's
/// sign follows a letter and is kept.
fn split_glued(field: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut start = 0;
    let bytes = field.as_bytes();
    for i in 1..bytes.len() {
        if matches!(bytes[i], b'+' | b'-') && (bytes[i - 1].is_ascii_digit() || bytes[i - 1] == b'.') {
            out.push(&field[start..i]);
            start = i;
        }
    }
    out.push(&field[start..]);
    out
}

/// Parse a sequence of accelerations (in file units) at time step `dt`
/// \[s\]: every number of every line in reading order, any number per line
/// (the body of a K-NET, COSMOS or PEER file with its header removed).
/// Fortran fields written without a space between them
/// (`-90.15800-109.02749`) are cut at the sign of the second.
pub fn parse_sequence(text: &str, file: &str, dt: f64) -> Result<RawRecord, RecordError> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(RecordError::Spec { file: file.into(), field: "dt", message: format!("dt = {dt} s must be > 0") });
    }
    let table = data_lines(text, file, Format::Sequence)?;
    let mut values = Vec::new();
    for dl in &table.lines {
        for field in &dl.fields {
            for token in split_glued(field) {
                values.push(number_at(token, file, dl.line)?);
            }
        }
    }
    let header_units = match &table.header {
        Some(h) if h.labels.len() == 1 => table.units_of_column(1),
        _ => HeaderUnits::NotInFormat,
    };
    let warnings = counts_warning(&values, file).into_iter().collect();
    Ok(RawRecord { dt, values, header: Vec::new(), first_time: None, header_units, warnings, channel: None })
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
    fn a_first_number_beyond_a_double_is_refused_not_taken_for_a_header() {
        let e = parse_one_column("1e400\n0.1\n0.2\n", "f.txt", 0.01, None).unwrap_err().to_string();
        assert!(e.contains("f.txt") && e.contains("1e400"), "{e}");
    }

    #[test]
    fn csv_empty_field() {
        let e = parse_two_column("0,,1\n1,2,3\n", "f.csv", 2).unwrap_err().to_string();
        assert!(e.starts_with("f.csv:1:"), "{e}");
    }

    #[test]
    fn glued_fortran_fields() {
        assert_eq!(split_glued("-90.15800-109.02749-125.62034"), vec!["-90.15800", "-109.02749", "-125.62034"]);
        assert_eq!(split_glued("1.5E-03"), vec!["1.5E-03"]);
        assert_eq!(split_glued("-.5D+02+1."), vec!["-.5D+02", "+1."]);
        assert_eq!(split_glued("12"), vec!["12"]);
    }
}
