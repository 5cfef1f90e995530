//! ESM (Engineering Strong Motion database, ORFEUS) ASCII records.
//!
//! Layout: header lines `KEY: value` (the first is `EVENT_NAME:`; the
//! standard has 64, but keys are read up to the first line that starts
//! with a number rather than counted), then the values, one per line (any
//! number per line is accepted; only their count matters). Keys used:
//!
//! | key | use |
//! |---|---|
//! | `SAMPLING_INTERVAL_S` | the time step \[s\] (required) |
//! | `NDATA` | the number of values: an error if the data disagree |
//! | `UNITS` | the units (`cm/s^2`, read by [`crate::Units::from_header`]); missing or unknown: `units` is required, as for AT2 |
//! | `DATA_TYPE` | must be `ACCELERATION` (velocity, displacement and spectra files are refused) |
//! | `PGA_CM/S^2` | checked against the data: a warning if they differ by more than 1 % |
//! | `STREAM` | the component: a code ending in `Z` is vertical (refused unless `allow_vertical`), `N` north (0°), `E` east (90°) |

use crate::error::RecordError;
use crate::formats::channel::{Channel, Orientation};
use crate::formats::{peak, peak_warning, starts_with_number};
use crate::record::RawRecord;
use crate::spec::{HeaderUnits, Units};
use crate::text::{excerpt, number_at, parse_number};

/// One `KEY: value` header line: 1-based line number, key (upper case),
/// value (trimmed).
struct Entry<'a> {
    line: usize,
    key: String,
    value: &'a str,
}

/// Parse the text of an ESM ASCII file; `file` names it in errors. Values
/// stay in the file's units (those of `UNITS`).
pub fn parse_esm(text: &str, file: &str) -> Result<RawRecord, RecordError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim().is_empty() {
        return Err(RecordError::Empty { file: file.into() });
    }
    let header_err = |line: usize, message: String| RecordError::Header { file: file.into(), line, message };
    let lines: Vec<&str> = text.lines().collect();
    let mut entries = Vec::new();
    let mut header = Vec::new();
    let mut data_start = lines.len();
    for (i, raw) in lines.iter().enumerate() {
        let t = raw.trim();
        if t.is_empty() {
            continue;
        }
        if starts_with_number(t) {
            data_start = i;
            break;
        }
        let Some((key, value)) = t.split_once(':') else {
            return Err(header_err(
                i + 1,
                format!(
                    "`{}` is neither a `KEY: value` header line nor a number (an ESM file holds `KEY: value` lines, \
                     then the values)",
                    excerpt(t, 60)
                ),
            ));
        };
        header.push(raw.trim_end().to_string());
        entries.push(Entry { line: i + 1, key: key.trim().to_ascii_uppercase(), value: value.trim() });
    }
    let get = |key: &str| entries.iter().find(|e| e.key == key && !e.value.is_empty());
    let last_header_line = entries.last().map_or(1, |e| e.line);

    check_data_type(get("DATA_TYPE"), last_header_line, file)?;
    let Some(dt_entry) = get("SAMPLING_INTERVAL_S") else {
        return Err(header_err(
            last_header_line,
            "the header has no `SAMPLING_INTERVAL_S:` line: the time step is not stated".into(),
        ));
    };
    let dt = number_at(dt_entry.value, file, dt_entry.line)?;
    if dt <= 0.0 {
        return Err(RecordError::BadDt { file: file.into(), line: dt_entry.line, dt });
    }
    let ndata = match get("NDATA") {
        Some(e) => Some((
            e.line,
            e.value.parse::<usize>().map_err(|_| {
                header_err(e.line, format!("NDATA `{}` is not a whole number >= 0", excerpt(e.value, 40)))
            })?,
        )),
        None => None,
    };
    let header_units = match get("UNITS") {
        Some(e) => match Units::from_header(e.value) {
            Some(u) => HeaderUnits::Stated(u),
            None => HeaderUnits::Unrecognised(excerpt(e.value, 40)),
        },
        None => HeaderUnits::Missing,
    };

    let values = read_values(&lines, data_start, ndata, file)?;

    let mut warnings = Vec::new();
    if let (Some(e), HeaderUnits::Stated(u)) = (get("PGA_CM/S^2"), &header_units) {
        if let Ok(pga) = parse_number(e.value) {
            let data = peak(&values) * u.to_si() * 100.0;
            warnings.extend(peak_warning(file, "PGA_CM/S^2", pga, data, "cm/s²"));
        }
    }
    // the stream's last letter is its component (SEED: Z vertical, N
    // north, E east)
    let orientation = match get("STREAM").map(|e| e.value.trim()) {
        Some(s) if s.ends_with(['Z', 'z']) => Orientation::Vertical { label: excerpt(s, 20) },
        Some(s) if s.ends_with(['N', 'n']) => Orientation::Azimuth { degrees: 0.0 },
        Some(s) if s.ends_with(['E', 'e']) => Orientation::Azimuth { degrees: 90.0 },
        _ => Orientation::Unknown,
    };
    let channel = Some(Channel { number: 1, of: 1, orientation });
    Ok(RawRecord { dt, values, header, first_time: None, header_units, warnings, channel })
}

/// Refuses a file whose `DATA_TYPE` (`entry`) is not `ACCELERATION` or
/// missing (the header ends on `last_header_line`).
fn check_data_type(entry: Option<&Entry<'_>>, last_header_line: usize, file: &str) -> Result<(), RecordError> {
    let header_err = |line: usize, message: String| RecordError::Header { file: file.into(), line, message };
    match entry {
        Some(e) if e.value.eq_ignore_ascii_case("ACCELERATION") => Ok(()),
        Some(e) => Err(header_err(
            e.line,
            format!(
                "DATA_TYPE is `{}`: not an acceleration record (ESM files of DATA_TYPE `ACCELERATION` are read; \
                     velocity, displacement and response-spectrum files are not)",
                excerpt(e.value, 60)
            ),
        )),
        None => Err(header_err(
            last_header_line,
            "the header has no `DATA_TYPE:` line, so the file may not be an acceleration record (an ESM file of \
                 DATA_TYPE `ACCELERATION` is read)"
                .into(),
        )),
    }
}

/// The values from line `data_start` on, as many as `NDATA` says (its line
/// and number) when it is given.
fn read_values(
    lines: &[&str],
    data_start: usize,
    ndata: Option<(usize, usize)>,
    file: &str,
) -> Result<Vec<f64>, RecordError> {
    let header_err = |line: usize, message: String| RecordError::Header { file: file.into(), line, message };
    let text_len: usize = lines.iter().map(|l| l.len() + 1).sum();
    let mut values = Vec::with_capacity(ndata.map_or(0, |(_, n)| n.min(text_len / 2 + 1)));
    let mut last_line = data_start + 1;
    for (i, raw) in lines.iter().enumerate().skip(data_start) {
        for token in raw.split_whitespace() {
            values.push(number_at(token, file, i + 1)?);
            last_line = i + 1;
        }
    }
    if values.is_empty() {
        return Err(RecordError::TooShort { file: file.into(), message: "no values after the ESM header".into() });
    }
    if let Some((line, n)) = ndata {
        if n != values.len() {
            return Err(header_err(
                line,
                format!(
                    "the header says NDATA = {n} but the file holds {} values (the last on line {last_line}): the \
                     file is cut or its header belongs to another record",
                    values.len()
                ),
            ));
        }
    }

    Ok(values)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn esm(extra: &str, data: &str) -> String {
        format!(
            "EVENT_NAME: TEST\nEVENT_ID: X\nSAMPLING_INTERVAL_S: 0.010000\nNDATA: 4\nSTREAM: HGE\nUNITS: cm/s^2\n\
             PGA_CM/S^2: 2.000000\nDATA_TYPE: ACCELERATION\n{extra}USER5: \n{data}"
        )
    }

    #[test]
    fn reads_keys_until_the_first_number() {
        let r = parse_esm(&esm("", "1.0\n-2.0E+00\n0.5\n0\n"), "a.ASC").unwrap();
        assert_eq!((r.dt, r.values.clone()), (0.01, vec![1.0, -2.0, 0.5, 0.0]));
        assert_eq!(r.header_units, HeaderUnits::Stated(Units::CentimetersPerSecond2));
        assert_eq!(r.header.len(), 9);
        assert!(r.warnings.is_empty(), "{:?}", r.warnings);
        // a header with more keys than the standard's 64 is fine
        let many: String = (0..80).map(|i| format!("USER_{i}: \n")).collect();
        assert_eq!(parse_esm(&esm(&many, "1\n-2\n0\n0\n"), "a.ASC").unwrap().values.len(), 4);
    }

    #[test]
    fn refusals_and_warnings() {
        let e = parse_esm(&esm("", "1\n2\n3\n"), "a.ASC").unwrap_err().to_string();
        assert!(e.starts_with("a.ASC:4: the header says NDATA = 4 but the file holds 3 values"), "{e}");
        let vel = esm("", "1\n-2\n0\n0\n").replace("DATA_TYPE: ACCELERATION", "DATA_TYPE: VELOCITY");
        let e = parse_esm(&vel, "v.ASC").unwrap_err().to_string();
        assert!(e.starts_with("v.ASC:8: DATA_TYPE is `VELOCITY`: not an acceleration record"), "{e}");
        let sa = esm("", "1\n-2\n0\n0\n").replace("ACCELERATION", "ACCELERATION RESPONSE SPECTRUM");
        assert!(parse_esm(&sa, "s.ASC").unwrap_err().to_string().contains("`ACCELERATION RESPONSE SPECTRUM`"));
        let no_units = esm("", "1\n-2\n0\n0\n").replace("UNITS: cm/s^2", "UNITS: ");
        assert_eq!(parse_esm(&no_units, "n.ASC").unwrap().header_units, HeaderUnits::Missing);
        let odd = esm("", "1\n-2\n0\n0\n").replace("cm/s^2\n", "furlong/fortnight^2\n");
        assert_eq!(
            parse_esm(&odd, "o.ASC").unwrap().header_units,
            HeaderUnits::Unrecognised("furlong/fortnight^2".into())
        );
        // a PGA 10 % off warns; a vertical stream is said to be vertical
        let r = parse_esm(&esm("", "1\n-2.2\n0\n0\n").replace("HGE", "HGZ"), "w.ASC").unwrap();
        assert!(r.channel.unwrap().orientation.is_vertical());
        let w = r.warnings;
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].contains("PGA_CM/S^2 = 2 cm/s² but the data peak at 2.2000 cm/s²"), "{w:?}");
        let e = parse_esm("EVENT_NAME: X\nno colon here\n1\n", "x.ASC").unwrap_err().to_string();
        assert!(e.starts_with("x.ASC:2: `no colon here` is neither"), "{e}");
        let e = parse_esm(&esm("", "1\n-2\n0\n0\n").replace("0.010000", "0"), "z.ASC").unwrap_err().to_string();
        assert!(e.starts_with("z.ASC:3: time step dt = 0 s"), "{e}");
    }
}
