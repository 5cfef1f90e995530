//! The lines of a plain-text record: comments and the column header
//! skipped, fields split at `;`, `,` or white space, decimal commas and
//! text lines refused.

use crate::error::RecordError;
use crate::label::label_units;
use crate::spec::{Format, HeaderUnits};
use crate::text::{excerpt, parse_number, NumberError};

/// How the fields of a line are separated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Sep {
    /// `;` (CSV)
    Semicolon,
    /// `,` (CSV)
    Comma,
    /// spaces and tabs
    White,
}

/// A data line of a text file: its 1-based number, its fields and how
/// they are separated.
pub(crate) struct DataLine<'a> {
    pub(crate) line: usize,
    pub(crate) fields: Vec<&'a str>,
    pub(crate) sep: Sep,
}

/// A text file's column-header line: its 1-based number and its labels
/// (`time [s]` kept together in a white-space separated header).
pub(crate) struct HeaderLine {
    pub(crate) line: usize,
    pub(crate) labels: Vec<String>,
}

/// The lines of a text file: the column header, if any, and the data lines.
pub(crate) struct Table<'a> {
    pub(crate) header: Option<HeaderLine>,
    pub(crate) lines: Vec<DataLine<'a>>,
}

fn is_comment(trimmed: &str) -> bool {
    trimmed.starts_with(['#', '%', '!'])
}

/// Whether `s` holds a digit, a comma and a digit in a row (`0,5`).
fn has_digit_comma_digit(s: &str) -> bool {
    s.as_bytes().windows(3).any(|w| w[0].is_ascii_digit() && w[1] == b',' && w[2].is_ascii_digit())
}

/// Whether `s` is a whole number: digits with an optional sign.
fn is_integer(s: &str) -> bool {
    let d = s.strip_prefix(['+', '-']).unwrap_or(s);
    !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit())
}

/// Fields of a CSV line split at `sep`: a trailing separator is tolerated,
/// an empty field is an error.
fn csv_fields<'a>(trimmed: &'a str, sep: char, file: &str, line: usize) -> Result<Vec<&'a str>, RecordError> {
    let mut fields: Vec<&str> = trimmed.split(sep).map(str::trim).collect();
    // a trailing separator ("1.0, 2.0,") is tolerated
    if fields.len() > 1 && fields.last().is_some_and(|l| l.is_empty()) {
        fields.pop();
    }
    if fields.iter().any(|f| f.is_empty()) {
        return Err(RecordError::Columns { file: file.into(), line, message: "empty field in CSV line".into() });
    }
    Ok(fields)
}

/// The fields of a (trimmed, non-comment) line and their separator, with
/// decimal commas refused: a field with `0,5` in a `;` line; white-space
/// separated tokens with commas only inside them (`0,005\t0,0173`); a
/// comma line whose split leaves a field of digits with a leading zero
/// after a field of digits (`0,000,0,0173` is `0,000` and `0,0173`).
pub(crate) fn split_fields<'a>(trimmed: &'a str, file: &str, line: usize) -> Result<(Vec<&'a str>, Sep), RecordError> {
    let decimal = |token: &str| RecordError::DecimalComma { file: file.into(), line, token: excerpt(token, 40) };
    if trimmed.contains(';') {
        let fields = csv_fields(trimmed, ';', file, line)?;
        if let Some(f) = fields.iter().find(|f| has_digit_comma_digit(f)) {
            return Err(decimal(f));
        }
        return Ok((fields, Sep::Semicolon));
    }
    if trimmed.contains(',') {
        let words: Vec<&str> = trimmed.split_whitespace().collect();
        if words.len() >= 2 && words.iter().all(|w| !w.starts_with(',') && !w.ends_with(',')) {
            if let Some(w) = words.iter().find(|w| has_digit_comma_digit(w)) {
                return Err(decimal(w));
            }
        }
        let fields = csv_fields(trimmed, ',', file, line)?;
        for pair in fields.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            if is_integer(a) && b.len() > 1 && b.starts_with('0') && b.bytes().all(|c| c.is_ascii_digit()) {
                return Err(decimal(&format!("{a},{b}")));
            }
        }
        return Ok((fields, Sep::Comma));
    }
    Ok((trimmed.split_whitespace().collect(), Sep::White))
}

/// Column labels of a header line: its fields, with a white-space
/// separated `[s]` or `(m/s2)` kept with the word before it.
fn header_labels(fields: &[&str], sep: Sep) -> Vec<String> {
    if sep != Sep::White {
        return fields.iter().map(|f| f.to_string()).collect();
    }
    let mut labels: Vec<String> = Vec::new();
    let mut open = false;
    for f in fields {
        let starts = f.starts_with(['[', '(']);
        match labels.last_mut() {
            Some(last) if open || starts => {
                last.push(' ');
                last.push_str(f);
            }
            _ => labels.push(f.to_string()),
        }
        if starts || open {
            open = !f.contains([']', ')']);
        }
    }
    labels
}

/// Whether a line is text rather than data: its first field starts with a
/// letter and is not a number (`EVENT_ID: X`, `Lat. 37.0`, but not `NaN`).
fn is_text_line(fields: &[&str]) -> bool {
    fields
        .first()
        .is_some_and(|f| f.starts_with(|c: char| c.is_alphabetic()) && parse_number(f) == Err(NumberError::NotANumber))
}

/// The data lines of a text file (header and comments skipped).
pub(crate) fn data_lines<'a>(text: &'a str, file: &str, reading: Format) -> Result<Table<'a>, RecordError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim().is_empty() {
        return Err(RecordError::Empty { file: file.into() });
    }
    let mut header = None;
    let mut lines: Vec<DataLine> = Vec::new();
    let mut first = true;
    for (i, raw) in text.lines().enumerate() {
        let trimmed = raw.trim();
        if trimmed.is_empty() || is_comment(trimmed) {
            continue;
        }
        let (fields, sep) = split_fields(trimmed, file, i + 1)?;
        if first {
            first = false;
            if fields.iter().all(|f| parse_number(f) == Err(NumberError::NotANumber)) {
                // a column header such as "time,acc" (a number beyond a
                // double, `1e400`, is a number: refused with its line below)
                header = Some(HeaderLine { line: i + 1, labels: header_labels(&fields, sep) });
                continue;
            }
        }
        if is_text_line(&fields) {
            let header_line = header.as_ref().map(|h: &HeaderLine| h.line);
            return Err(crate::formats::not_numeric_data(file, i + 1, trimmed, text, header_line, reading));
        }
        if sep != Sep::White {
            if let Some(f) = lines.iter().find(|l| l.sep != Sep::White) {
                if f.fields.len() != fields.len() {
                    let hint = if sep == Sep::Comma {
                        "; if the file writes decimal commas (`0,5`), they are not read: convert them to points"
                    } else {
                        ""
                    };
                    return Err(RecordError::Columns {
                        file: file.into(),
                        line: i + 1,
                        message: format!(
                            "the line has {} fields where line {} has {}: every line of a CSV file has the same \
                             columns{hint}",
                            fields.len(),
                            f.line,
                            f.fields.len()
                        ),
                    });
                }
            }
        }
        lines.push(DataLine { line: i + 1, fields, sep });
    }
    if lines.is_empty() {
        return Err(RecordError::TooShort { file: file.into(), message: "the file holds no data lines".into() });
    }
    Ok(Table { header, lines })
}

impl Table<'_> {
    /// What the label of column `column` (1-based) says about its units.
    pub(crate) fn units_of_column(&self, column: usize) -> HeaderUnits {
        match self.header.as_ref().and_then(|h| h.labels.get(column - 1)) {
            Some(label) => label_units(label),
            None => HeaderUnits::NotInFormat,
        }
    }

    /// A hint for a two-column file whose time column is not a time axis:
    /// lines of 3 or more values may be samples in reading order; commas
    /// may be decimal commas.
    pub(crate) fn layout_hint(&self) -> Option<String> {
        let k = self.lines[0].fields.len();
        let mut hints = Vec::new();
        if k >= 3 {
            hints.push(format!(
                "line {} holds {k} values: if the values on a line are successive samples (the body of a K-NET, \
                 COSMOS or PEER file), read them with `format = \"sequence\"`, `dt` and `units`",
                self.lines[0].line
            ));
        }
        if self.lines[0].sep == Sep::Comma && k >= 3 {
            hints.push(
                "if the file writes decimal commas (`0,005,0,0173`), they are not read: convert them to points \
                        (`0.005,0.0173`)"
                    .to_string(),
            );
        }
        (!hints.is_empty()).then(|| hints.join("; "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn separators_and_decimal_commas() {
        let split = |line: &str| split_fields(line, "f", 1).map(|(f, s)| (f.join("|"), s));
        assert_eq!(split("0.1;0.2").unwrap(), ("0.1|0.2".into(), Sep::Semicolon));
        assert_eq!(split("0.1, 0.2,").unwrap(), ("0.1|0.2".into(), Sep::Comma));
        assert_eq!(split("0.1\t0.2").unwrap(), ("0.1|0.2".into(), Sep::White));
        for line in ["0,000;0,0173", "0,000\t0,0173", "0,000 0,0173", "0,000,0,01731414", "-0,05,1"] {
            let e = split(line).unwrap_err().to_string();
            assert!(e.starts_with("f:1: decimal commas are not read: convert `"), "{line}: {e}");
        }
        assert!(split("0,000;0,0173").unwrap_err().to_string().contains("convert `0,000` to `0.000`"));
        assert!(split("1,234.5;2").unwrap_err().to_string().contains("remove thousands separators"));
    }

    #[test]
    fn bracketed_header_labels_stay_whole() {
        assert_eq!(header_labels(&["time", "[s]", "acc", "(m/s2)"], Sep::White), vec!["time [s]", "acc (m/s2)"]);
        assert_eq!(header_labels(&["t", "(", "s", ")", "a"], Sep::White), vec!["t ( s )", "a"]);
        assert_eq!(header_labels(&["time [s]", "acc"], Sep::Comma), vec!["time [s]", "acc"]);
    }
}
