//! PEER NGA `.AT2` records.
//!
//! Layout: 4 header lines (1: database, 2: event, date, station,
//! component, 3: `ACCELERATION TIME SERIES IN UNITS OF G`, 4: NPTS and DT),
//! then NPTS values in g, usually 5 per line in Fortran E format, the last
//! line possibly shorter. Line 4 is read in any of these spellings:
//!
//! ```text
//! NPTS=   7997, DT=   .0050 SEC,     (NGA-West2)
//! NPTS=   1000, DT=   .0200 SEC      (no comma after SEC)
//! NPTS= 7997 DT= 0.005               (no commas, no unit)
//! 7997   .0050   NPTS, DT            (older NGA files: numbers first)
//! ```
//!
//! Windows (CRLF) and Unix line ends, a byte-order mark, trailing blank
//! lines and values without a leading zero (`-.8338791E-03`) are accepted.
//! The component is the last field of line 2 (`..., Corralitos, 90`): an
//! azimuth, or `UP`/`DWN` (vertical, refused unless `allow_vertical`, as
//! is any `.VT2` file).

use crate::error::RecordError;
use crate::formats::channel::{Channel, Orientation};
use crate::record::RawRecord;
use crate::spec::{HeaderUnits, Units};
use crate::text::{number_at, parse_number};

/// Number of header lines of an AT2 file.
pub const HEADER_LINES: usize = 4;

/// Byte range of the token after `key` followed by `=` or `:` in `upper`
/// (an upper-case header line), if any. `key` must not be preceded by a
/// letter or digit.
fn keyed_range(upper: &str, key: &str) -> Option<std::ops::Range<usize>> {
    let mut from = 0;
    while let Some(pos) = upper[from..].find(key) {
        let start = from + pos;
        from = start + key.len();
        let boundary = upper[..start].chars().next_back().is_none_or(|c| !c.is_ascii_alphanumeric());
        if !boundary {
            continue;
        }
        let rest = upper[from..].trim_start();
        let Some(rest) = rest.strip_prefix(['=', ':']) else {
            continue;
        };
        let rest = rest.trim_start();
        let begin = upper.len() - rest.len();
        let end = rest.find(|c: char| c.is_whitespace() || c == ',' || c == ';').unwrap_or(rest.len());
        return Some(begin..begin + end);
    }
    None
}

/// NPTS and DT tokens of header line 4.
fn header_tokens(line: &str) -> (Option<&str>, Option<&str>) {
    // ASCII upper-casing keeps byte offsets, so ranges apply to `line`
    let upper = line.to_ascii_uppercase();
    let npts = keyed_range(&upper, "NPTS");
    let dt = keyed_range(&upper, "DT");
    if npts.is_some() || dt.is_some() {
        return (npts.map(|r| &line[r]), dt.map(|r| &line[r]));
    }
    // older NGA layout: "  7997   .0050    NPTS, DT"
    if upper.contains("NPTS") && upper.contains("DT") {
        let mut it = line.split(|c: char| c.is_whitespace() || c == ',').filter(|s| !s.is_empty());
        let a = it.next();
        let b = it.next();
        if let (Some(a), Some(b)) = (a, b) {
            if parse_number(a).is_ok() && parse_number(b).is_ok() {
                return (Some(a), Some(b));
            }
        }
    }
    (None, None)
}

/// The units stated in header line 3: the words after `UNITS` (and an
/// optional `OF`, `IN`, `:` or `=`), e.g. `ACCELERATION TIME SERIES IN
/// UNITS OF G`, `... IN UNITS OF CM/SEC/SEC`.
fn units_of_line3(line: &str) -> HeaderUnits {
    let upper = line.to_ascii_uppercase();
    let Some(at) = upper.find("UNITS") else { return HeaderUnits::Missing };
    let mut rest = upper[at + "UNITS".len()..].trim_start();
    for word in ["OF ", "IN ", ":", "="] {
        if let Some(r) = rest.strip_prefix(word) {
            rest = r.trim_start();
            break;
        }
    }
    let text = rest.trim();
    match Units::from_header(text) {
        Some(u) => HeaderUnits::Stated(u),
        None => HeaderUnits::Unrecognised(crate::text::excerpt(line[line.len() - rest.len()..].trim(), 40)),
    }
}

/// Parse the text of an AT2 file; `file` names it in errors. Values stay in
/// the file's units (those of header line 3).
pub fn parse_at2(text: &str, file: &str) -> Result<RawRecord, RecordError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim().is_empty() {
        return Err(RecordError::Empty { file: file.into() });
    }
    let lines: Vec<&str> = text.lines().collect();
    if lines.len() < HEADER_LINES {
        return Err(RecordError::Header {
            file: file.into(),
            line: lines.len(),
            message: format!(
                "an AT2 file has {HEADER_LINES} header lines (NPTS and DT on line 4); the file ends at line {}",
                lines.len()
            ),
        });
    }
    let header: Vec<String> = lines[..HEADER_LINES].iter().map(|l| l.trim_end().to_string()).collect();
    let kind = header[2].to_ascii_uppercase();
    if kind.contains("VELOCITY") || kind.contains("DISPLACEMENT") {
        return Err(RecordError::Header {
            file: file.into(),
            line: 3,
            message: format!("not an acceleration record: `{}`", crate::text::excerpt(header[2].trim(), 80)),
        });
    }
    let header_units = units_of_line3(&header[2]);

    let line4 = lines[3];
    let (npts_tok, dt_tok) = header_tokens(line4);
    let example = "expected e.g. `NPTS=   7997, DT=   .0050 SEC`";
    let Some(npts_tok) = npts_tok else {
        return Err(RecordError::Header {
            file: file.into(),
            line: 4,
            message: format!("no NPTS in header line `{}` ({example})", crate::text::excerpt(line4.trim(), 80)),
        });
    };
    let Some(dt_tok) = dt_tok else {
        return Err(RecordError::Header {
            file: file.into(),
            line: 4,
            message: format!("no DT in header line `{}` ({example})", crate::text::excerpt(line4.trim(), 80)),
        });
    };
    let npts: usize = npts_tok.parse().map_err(|_| RecordError::Header {
        file: file.into(),
        line: 4,
        message: format!("NPTS `{}` is not a whole number >= 0", crate::text::excerpt(npts_tok, 40)),
    })?;
    if npts == 0 {
        return Err(RecordError::Header { file: file.into(), line: 4, message: "NPTS = 0: no samples".into() });
    }
    let dt = number_at(dt_tok, file, 4)?;
    if dt <= 0.0 {
        return Err(RecordError::BadDt { file: file.into(), line: 4, dt });
    }

    // the header's NPTS is not trusted for the allocation: a value needs at
    // least two bytes (a digit and a separator), so the text bounds the count
    let mut values = Vec::with_capacity(npts.min(text.len() / 2 + 1));
    for (i, line) in lines.iter().enumerate().skip(HEADER_LINES) {
        let line_no = i + 1;
        for token in line.split(|c: char| c.is_whitespace() || c == ',').filter(|s| !s.is_empty()) {
            if values.len() == npts {
                return Err(RecordError::TooManyValues { file: file.into(), line: line_no, expected: npts });
            }
            values.push(number_at(token, file, line_no)?);
        }
    }
    if values.len() < npts {
        return Err(RecordError::TooFewValues {
            file: file.into(),
            line: lines.len(),
            expected: npts,
            found: values.len(),
        });
    }
    let channel = Some(Channel { number: 1, of: 1, orientation: component(&header[1], file) });
    Ok(RawRecord { dt, values, header, first_time: None, header_units, warnings: Vec::new(), channel })
}

/// The component of header line 2 (`Loma Prieta, 10/18/1989, Corralitos,
/// 90`: its last field, an azimuth or `UP`/`DWN`), vertical for a `.VT2`
/// file (PEER's name for the vertical component) whatever it says.
fn component(line2: &str, file: &str) -> Orientation {
    if file.to_ascii_lowercase().ends_with(".vt2") {
        return Orientation::Vertical { label: "VT2".into() };
    }
    let field = line2.rsplit(',').next().unwrap_or("").trim();
    // a trailing word after the azimuth (`90 deg`) is fine; a station name
    // in a line without commas is not a component
    if line2.contains(',') {
        Orientation::from_label(field)
    } else {
        Orientation::Unknown
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_spellings() {
        for (line, n, d) in [
            ("NPTS=   7997, DT=   .0050 SEC,      ", "7997", ".0050"),
            ("NPTS=   1000, DT=   .0200 SEC", "1000", ".0200"),
            ("NPTS= 7997 DT= 0.005", "7997", "0.005"),
            ("npts=12,dt=0.01", "12", "0.01"),
            ("  7997   .0050    NPTS, DT", "7997", ".0050"),
        ] {
            assert_eq!(header_tokens(line), (Some(n), Some(d)), "{line}");
        }
        assert_eq!(header_tokens("DT= 0.01 SEC"), (None, Some("0.01")));
        assert_eq!(header_tokens("NPTS= 10"), (Some("10"), None));
        assert_eq!(header_tokens("nothing here"), (None, None));
    }

    #[test]
    fn units_of_header_line_3() {
        use HeaderUnits::*;
        for (line, units) in [
            ("ACCELERATION TIME SERIES IN UNITS OF G", Stated(Units::G)),
            ("Acceleration time series in units of g", Stated(Units::G)),
            ("ACCELERATION IN UNITS OF GAL", Stated(Units::CentimetersPerSecond2)),
            ("ACCELERATION TIME HISTORY IN UNITS OF CM/SEC/SEC", Stated(Units::CentimetersPerSecond2)),
            ("ACCELERATION, UNITS: CM/S/S", Stated(Units::CentimetersPerSecond2)),
            ("UNITS OF CM/S^2", Stated(Units::CentimetersPerSecond2)),
            ("UNITS OF CM/SEC2", Stated(Units::CentimetersPerSecond2)),
            ("UNITS OF M/S/S", Stated(Units::MetersPerSecond2)),
            ("UNITS = M/SEC**2", Stated(Units::MetersPerSecond2)),
            ("ACCELERATION TIME SERIES", Missing),
            ("ACCELERATION IN UNITS OF FURLONGS/FORTNIGHT", Unrecognised("FURLONGS/FORTNIGHT".into())),
            ("ACCELERATION IN UNITS OF MM/S/S", Unrecognised("MM/S/S".into())),
        ] {
            assert_eq!(units_of_line3(line), units, "{line}");
        }
    }
}
