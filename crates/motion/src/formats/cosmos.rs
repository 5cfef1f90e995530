//! COSMOS Strong Motion Data Format v1.20 (CESMD, CSMIP, USGS `.V1`,
//! `.V2`, `.V2c` files): uncorrected (V1) and corrected (V2) acceleration.
//!
//! Layout of a channel:
//!
//! ```text
//! Corrected acceleration  (Format v01.20 with 13 text lines) ...   text header (13 lines)
//! ...
//! Values used when parameter or data value is unknown/unspecified:  -999, -999.0
//!  100 Integer-header values follow on 10 lines, Format= (10I8)
//! ...
//!  100 Real-header values follow on 20 lines, Format= (5F15.6)
//! ...
//!    1 Comment line(s) follow, each starting with a "|":
//! | ...
//!     7999 acceleration pts, approx   40 secs, units=cm/sec2 (04), Format=(8F10.5)
//!    1.73141   1.73161 ...
//! End-of-data for Chan  1 acceleration
//! ```
//!
//! Header values used (numbered from 1 as in the format's tables):
//!
//! | value | use |
//! |---|---|
//! | real 62 | sampling interval \[ms\] (required: unknown, zero or negative is refused; the data line's "approx 40 secs" is not precise enough to derive it) |
//! | real 63 | record length \[s\] = NPTS × dt: a warning if it disagrees |
//! | real 64 | peak value of the data: a warning beyond 1 % |
//! | integer 2 | physical parameter: 1 (acceleration), else refused |
//! | integer 3 | units code: 2 = g, 4 = cm/s², 10 = gal; checked against the code in the data line (`units=cm/sec2 (04)`); another code is unknown units (then `units` is required) |
//! | integer 54 | orientation, where text line 9 (`Sta Chan   1: 90 deg`) does not give it: 0-360 azimuth, 400-402 vertical |
//!
//! The positions are those of the COSMOS v1.20 tables as the USGS readers
//! use them (gmprocess `io/cosmos/core.py`: sampling interval = real 62 in
//! ms, length = real 63; PRISM `VFileConstants`: DELTA_T = real 62,
//! SERIES_LENGTH = real 63, units code = integer 3, code 4 = cm/sec2), and
//! agree on a CESMD file (42000 pts × 5 ms = 210 s = real 63, real 64 =
//! the `Max =` of text line 11). A file holds one channel or several, each
//! opening with its `(Format v01.20 ...)` line; `channel` or `azimuth`
//! choose one ([`crate::formats::channel`]), and the text header's `Sta
//! Chan   N: 90 deg` gives each one's number and orientation.

use crate::error::RecordError;
use crate::formats::channel::{choose, Channel, ChannelChoice, Orientation};
use crate::formats::fortran::{fortran_format, fortran_tokens};
use crate::formats::{peak, peak_warning};
use crate::record::RawRecord;
use crate::spec::{HeaderUnits, Units};
use crate::text::{excerpt, number, number_at, parse_number};

/// Units of a COSMOS units code: 2 = g, 4 = cm/s², 10 = gal.
fn units_of_code(code: i64) -> Option<Units> {
    match code {
        2 => Some(Units::G),
        4 | 10 => Some(Units::CentimetersPerSecond2),
        _ => None,
    }
}

/// A block's first line: `100 Integer-header values follow on 10 lines,
/// Format= (10I8)` or `7999 acceleration pts, ...`: the count, its line.
struct Block {
    count: usize,
    line: usize,
    width: Option<usize>,
}

/// The file's lines and what reading them needs.
struct Reader<'a> {
    lines: Vec<&'a str>,
    file: &'a str,
}

impl Reader<'_> {
    fn err(&self, line: usize, message: String) -> RecordError {
        RecordError::Header { file: self.file.into(), line, message }
    }

    /// The block starting at index `i`, whose first line must contain `what`.
    fn block(&self, i: usize, what: &str, example: &str) -> Result<Block, RecordError> {
        let Some(line) = self.lines.get(i) else {
            return Err(self.err(self.lines.len(), format!("the file ends where `{example}` was expected")));
        };
        let count = line.split_whitespace().next().and_then(|t| t.parse::<usize>().ok());
        match count {
            Some(count) if line.to_ascii_lowercase().contains(what) => {
                Ok(Block { count, line: i + 1, width: fortran_format(line).map(|f| f.1) })
            }
            _ => {
                Err(self
                    .err(i + 1, format!("`{}` is not the expected COSMOS line `{example}`", excerpt(line.trim(), 60))))
            }
        }
    }

    /// The `block.count` numbers after `block`'s line, with the 1-based
    /// line of each, and the index of the line after them.
    fn numbers(&self, block: &Block) -> Result<(Vec<f64>, Vec<usize>, usize), RecordError> {
        let (mut values, mut at) = (Vec::with_capacity(block.count.min(self.lines.len() * 16)), Vec::new());
        let mut i = block.line;
        while values.len() < block.count {
            let Some(line) = self.lines.get(i) else {
                return Err(self.err(
                    self.lines.len(),
                    format!(
                        "line {} announces {} values but the file ends after {}",
                        block.line,
                        block.count,
                        values.len()
                    ),
                ));
            };
            if line.trim_start().starts_with(|c: char| c.is_alphabetic()) {
                return Err(self.err(
                    i + 1,
                    format!(
                        "line {} announces {} values but `{}` ends them after {}",
                        block.line,
                        block.count,
                        excerpt(line.trim(), 40),
                        values.len()
                    ),
                ));
            }
            for token in fortran_tokens(line, block.width) {
                if values.len() == block.count {
                    return Err(self
                        .err(i + 1, format!("more values than the {} announced on line {}", block.count, block.line)));
                }
                values.push(number_at(token, self.file, i + 1)?);
                at.push(i + 1);
            }
            i += 1;
        }
        Ok((values, at, i))
    }
}

/// Parse the text of a COSMOS V1/V2 file; `file` names it in errors. The
/// first channel's acceleration is read, in the file's units.
pub fn parse_cosmos(text: &str, file: &str, choice: ChannelChoice) -> Result<RawRecord, RecordError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim().is_empty() {
        return Err(RecordError::Empty { file: file.into() });
    }
    let r = Reader { lines: text.lines().collect(), file };
    let first = r.lines.iter().position(|l| !l.trim().is_empty()).unwrap_or(0);
    // each channel's acceleration opens with its `... acceleration (Format
    // v01.20 ...)` line; a file of corrected data may follow it with the
    // channel's velocity and displacement, which are not channels of their own
    let starts: Vec<usize> = (first..r.lines.len())
        .filter(|&i| {
            let l = r.lines[i].to_ascii_lowercase();
            l.find("(format v").is_some_and(|at| l[..at].contains("acceleration"))
        })
        .collect();
    if starts.first() != Some(&first) {
        return parse_channel(&r, first).map(|(raw, _)| raw);
    }
    let channels: Vec<Channel> = starts
        .iter()
        .enumerate()
        .map(|(k, &s)| {
            let chan = r.lines[s..r.lines.len().min(s + 13)].iter().find_map(|l| sta_chan(l));
            let (number, orientation) = chan.unwrap_or((k as u32 + 1, Orientation::Unknown));
            Channel { number, of: starts.len() as u32, orientation }
        })
        .collect();
    let (pick, warning) = choose(file, &channels, choice)?;
    let (mut raw, code) = parse_channel(&r, starts[pick])?;
    let mut channel = channels[pick].clone();
    if channel.orientation == Orientation::Unknown {
        channel.orientation = match code {
            Some(c) if (0.0..=360.0).contains(&c) => Orientation::Azimuth { degrees: c },
            Some(c) if (400.0..=402.0).contains(&c) => Orientation::Vertical { label: format!("code {c}") },
            _ => Orientation::Unknown,
        };
    }
    raw.warnings.splice(0..0, warning);
    raw.channel = Some(channel);
    Ok(raw)
}

/// `Sta Chan   1: 90 deg ( Rcrd Chan  1)`: the station channel's number
/// and orientation.
fn sta_chan(line: &str) -> Option<(u32, Orientation)> {
    let lower = line.to_ascii_lowercase();
    let rest = &line[lower.find("chan")? + 4..];
    let (num, after) = rest.split_once(':')?;
    let number = num.trim().parse().ok()?;
    let label = after.trim_start().split(['(', ' ']).take(2).collect::<Vec<_>>().join(" ");
    Some((number, Orientation::from_label(&label)))
}

/// A channel's units: integer-header value 3 (`header_code`) and the data
/// line's `units=cm/sec2 (04)` (line `data_line_number`), which must agree;
/// with the data line's unit text.
fn units_of_channel<'a>(
    r: &Reader,
    data_line_number: usize,
    data_line: &'a str,
    header_code: Option<i64>,
) -> Result<(HeaderUnits, &'a str), RecordError> {
    let data_lower = data_line.to_ascii_lowercase();
    let segment = data_lower.find("units=").map(|p| data_line[p + 6..].split(',').next().unwrap_or("").trim());
    let (unit_text, line_code) = match segment.map(|s| s.split_once('(').unwrap_or((s, ""))) {
        Some((u, c)) => (u.trim(), c.trim_end_matches(')').trim().parse::<i64>().ok()),
        None => ("", None),
    };
    if let (Some(h), Some(l)) = (header_code, line_code) {
        if h != l {
            return Err(r.err(
                data_line_number,
                format!("the data line's units code {l} (`{unit_text}`) differs from integer-header value 3 ({h})"),
            ));
        }
    }
    let header_units = match header_code.or(line_code) {
        Some(code) => match (units_of_code(code), Units::from_header(unit_text)) {
            (Some(u), Some(t)) if u != t => {
                return Err(r.err(
                    data_line_number,
                    format!("units code {code} means {} but the data line says `{unit_text}`", u.name()),
                ))
            }
            (Some(u), _) => HeaderUnits::Stated(u),
            (None, _) => HeaderUnits::Unrecognised(format!("code {code} ({})", excerpt(unit_text, 20))),
        },
        None => match Units::from_header(unit_text) {
            Some(u) => HeaderUnits::Stated(u),
            None if unit_text.is_empty() => HeaderUnits::Missing,
            None => HeaderUnits::Unrecognised(excerpt(unit_text, 40)),
        },
    };
    Ok((header_units, unit_text))
}

/// The values that stand for "unknown" in the integer and real headers
/// (text line 13, `... unknown: -999, -999.0`), -999 if not stated.
fn unknown_values(r: &Reader, first: usize, n_text: usize) -> (f64, f64) {
    r.lines
        .get(first + 12)
        .filter(|l| n_text >= 13 && l.to_ascii_lowercase().contains("unknown"))
        .and_then(|l| l.split_once(':'))
        .and_then(|(_, v)| {
            let mut it = v.split(',').map(|t| parse_number(t.trim()));
            Some((it.next()?.ok()?, it.next()?.ok()?))
        })
        .unwrap_or((-999.0, -999.0))
}

/// The channel whose `(Format v...` line is `first`, and its orientation
/// code (integer-header value 54), if stated.
fn parse_channel(r: &Reader, first: usize) -> Result<(RawRecord, Option<f64>), RecordError> {
    let file = r.file;
    let line1 = r.lines[first];
    let lower1 = line1.to_ascii_lowercase();
    let example = "Corrected acceleration  (Format v01.20 with 13 text lines)";
    let Some(at) = lower1.find("(format v") else {
        return Err(r.err(first + 1, format!("not a COSMOS header line (expected e.g. `{example}`)")));
    };
    let kind = line1[..at].trim();
    let kind_lower = kind.to_ascii_lowercase();
    if !kind_lower.contains("acceleration") || kind_lower.contains("raw") || kind_lower.contains("count") {
        return Err(r.err(
            first + 1,
            format!(
                "`{}`: not an acceleration record (COSMOS V1 uncorrected and V2 corrected acceleration are read; raw \
                 counts, velocity, displacement and spectra are not)",
                excerpt(kind, 40)
            ),
        ));
    }
    let n_text = lower1[at..]
        .split("with")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .and_then(|t| t.parse::<usize>().ok())
        .filter(|&n| n >= 1)
        .ok_or_else(|| r.err(first + 1, format!("no text-line count (expected e.g. `{example}`)")))?;
    if n_text >= r.lines.len() - first {
        return Err(r.err(
            r.lines.len(),
            format!("line {} announces {n_text} text lines but the file ends before the headers", first + 1),
        ));
    }
    let (unknown_int, unknown_real) = unknown_values(r, first, n_text);
    let known_int = |v: f64| v != unknown_int;
    let known_real = |v: f64| (v - unknown_real).abs() > 1e-6 * unknown_real.abs().max(1.0);

    let int_block = r.block(first + n_text, "integer-header", "100 Integer-header values follow on 10 lines")?;
    let (ints, int_at, next) = r.numbers(&int_block)?;
    let real_block = r.block(next, "real-header", "100 Real-header values follow on 17 lines")?;
    let (reals, real_at, next) = r.numbers(&real_block)?;
    let comments = r.block(next, "comment", "1 Comment line(s) follow, each starting with a \"|\":")?;
    let data_index = next.saturating_add(1).saturating_add(comments.count);
    let data = r.block(data_index, "pts", "7999 acceleration pts, approx 40 secs, units=cm/sec2 (04)")?;
    let data_line = r.lines[data_index];

    // real 62: the sampling interval in ms
    let Some(&dt_ms) = reals.get(61) else {
        return Err(r.err(
            real_block.line,
            format!("the real header holds {} values; the sampling interval is value 62", reals.len()),
        ));
    };
    if !known_real(dt_ms) || dt_ms.is_nan() || dt_ms / 1000.0 <= 0.0 {
        return Err(r.err(
            real_at[61],
            format!(
                "the sampling interval (real-header value 62) is {} ms: the file does not state its time step (the \
                 data line's `approx ... secs` is not precise enough to derive it). If the time step is known from \
                 elsewhere, remove the header and read the values with `format = \"sequence\"`, `dt` and `units`",
                number(dt_ms)
            ),
        ));
    }
    let dt = dt_ms / 1000.0;
    if data_line.split_whitespace().nth(1).is_none_or(|w| !w.eq_ignore_ascii_case("acceleration")) {
        return Err(r.err(data.line, format!("`{}`: not acceleration data", excerpt(data_line.trim(), 60))));
    }
    if let Some(&p) = ints.get(1).filter(|v| known_int(**v)) {
        if p != 1.0 {
            return Err(
                r.err(int_at[1], format!("integer-header value 2 (physical parameter) is {p}, not 1 (acceleration)"))
            );
        }
    }

    // units: integer 3 and the data line's `units=cm/sec2 (04)`
    let header_code = ints.get(2).copied().filter(|v| known_int(*v)).map(|v| v as i64);
    let (header_units, unit_text) = units_of_channel(r, data.line, data_line, header_code)?;

    let (values, _, _) = r.numbers(&data)?;
    if values.is_empty() {
        return Err(RecordError::TooShort { file: file.into(), message: "0 acceleration points".into() });
    }
    let mut warnings = Vec::new();
    if kind_lower.contains("uncorrected") {
        warnings.push(format!(
            "{file}: `{}` (V1): not baseline-corrected or filtered; a V2 (corrected) file is usually what is wanted",
            excerpt(kind, 40)
        ));
    }
    if let Some(&length) = reals.get(62).filter(|v| known_real(**v) && **v > 0.0) {
        let n = values.len() as f64;
        if (n * dt - length).abs() > dt
            && ((n - 1.0) * dt - length).abs() > dt
            && (n * dt - length).abs() > 0.01 * length
        {
            warnings.push(format!(
                "{file}: the header's record length (real-header value 63) is {length} s but {} points at {} s last {} \
                 s: check the time step",
                values.len(),
                number(dt),
                number(n * dt)
            ));
        }
    }
    if let Some(&max) = reals.get(63).filter(|v| known_real(**v) && **v != 0.0) {
        warnings.extend(peak_warning(file, "peak (real-header value 64)", max.abs(), peak(&values), unit_text));
    }
    let header = r.lines[first..first + n_text].iter().map(|l| l.trim_end().to_string()).collect();
    let code = ints.get(53).copied().filter(|v| known_int(*v));
    Ok((RawRecord { dt, values, header, first_time: None, header_units, warnings, channel: None }, code))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str, file: &str) -> Result<RawRecord, RecordError> {
        parse_cosmos(text, file, ChannelChoice::default())
    }

    /// A COSMOS file with 100 integer and 100 real header values, -999
    /// (unknown) except those given.
    fn cosmos(ints: &[(usize, i64)], reals: &[(usize, f64)], data_line: &str, data: &str) -> String {
        let mut text = String::from("Corrected acceleration  (Format v01.20 with 13 text lines) Src: test\n");
        for i in 2..=12 {
            text += &format!("text line {i}\n");
        }
        text += "Values used when parameter or data value is unknown/unspecified:   -999, -999.0\n";
        text += " 100 Integer-header values follow on 10 lines, Format= (10I8)\n";
        let mut iv = [-999i64; 100];
        for &(k, v) in ints {
            iv[k - 1] = v;
        }
        for row in iv.chunks(10) {
            text += &row.iter().map(|v| format!("{v:8}")).collect::<String>();
            text += "\n";
        }
        text += " 100 Real-header values follow on 20 lines, Format= (5F15.6)\n";
        let mut rv = [-999.0f64; 100];
        for &(k, v) in reals {
            rv[k - 1] = v;
        }
        for row in rv.chunks(5) {
            text += &row.iter().map(|v| format!("{v:15.6}")).collect::<String>();
            text += "\n";
        }
        text += "   1 Comment line(s) follow, each starting with a \"|\":\n| a comment\n";
        format!("{text}{data_line}\n{data}End-of-data for Chan  1 acceleration\n")
    }

    const LINE: &str = "       5 acceleration pts, approx    0 secs, units=cm/sec2 (04), Format=(5F10.5)";

    #[test]
    fn reads_time_step_units_and_fixed_width_values() {
        let body = "   1.00000-123.45000   2.00000\n   3.00000   4.00000\n";
        let text = cosmos(&[(2, 1), (3, 4)], &[(62, 10.0), (63, 0.05), (64, -123.45)], LINE, body);
        let r = parse(&text, "c.V2").unwrap();
        assert_eq!(r.dt, 0.01);
        assert_eq!(r.values, vec![1.0, -123.45, 2.0, 3.0, 4.0]);
        assert_eq!(r.header_units, HeaderUnits::Stated(Units::CentimetersPerSecond2));
        assert_eq!(r.header.len(), 13);
        assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    }

    #[test]
    fn refusals() {
        let data = "1 2 3 4 5\n";
        // no sampling interval: never derived from "approx ... secs"
        for dt in [-999.0, 0.0, 5e-324] {
            let e = parse(&cosmos(&[], &[(62, dt)], LINE, data), "c.V2").unwrap_err().to_string();
            assert!(e.starts_with("c.V2:38: the sampling interval (real-header value 62) is"), "{e}");
            assert!(e.contains("format = \"sequence\""), "{e}");
        }
        let e = parse(&cosmos(&[(2, 2)], &[(62, 5.0)], LINE, data), "c.V2").unwrap_err().to_string();
        assert!(e.contains("physical parameter) is 2, not 1"), "{e}");
        let e = parse(&cosmos(&[(3, 2)], &[(62, 5.0)], LINE, data), "c.V2").unwrap_err().to_string();
        assert!(e.contains("units code 4 (`cm/sec2`) differs from integer-header value 3 (2)"), "{e}");
        let vel = cosmos(&[], &[(62, 5.0)], LINE, data).replace("Corrected acceleration", "Velocity data");
        assert!(parse(&vel, "v.V2").unwrap_err().to_string().contains("`Velocity data`: not an acceleration"));
        for count in ["18446744073709551615", "99"] {
            let huge = cosmos(&[], &[(62, 5.0)], LINE, data).replace("with 13 text", &format!("with {count} text"));
            let e = parse(&huge, "c.V2").unwrap_err().to_string();
            assert!(e.contains(&format!("announces {count} text lines")), "{e}");
            let huge = cosmos(&[], &[(62, 5.0)], LINE, data).replace("   1 Comment", &format!("{count} Comment"));
            assert!(parse(&huge, "c.V2").is_err());
        }
        let short = parse(&cosmos(&[], &[(62, 5.0)], LINE, "1 2\n"), "c.V2").unwrap_err().to_string();
        assert!(short.contains("announces 5 values"), "{short}");
        // an unknown units code: units not recognised (then `units` is required)
        let mg = LINE.replace("cm/sec2 (04)", "mg (11)");
        let r = parse(&cosmos(&[], &[(62, 5.0)], &mg, data), "c.V2").unwrap();
        assert_eq!(r.header_units, HeaderUnits::Unrecognised("code 11 (mg)".into()));
        // uncorrected, wrong length and peak warn; orientation code 400 is
        // vertical where the text header does not say
        let text = cosmos(&[(54, 400)], &[(62, 5.0), (63, 99.0), (64, 7.0)], LINE, data)
            .replace("Corrected acceleration", "Uncorrected acceleration");
        let r = parse(&text, "c.V1").unwrap();
        assert_eq!(r.warnings.len(), 3, "{:?}", r.warnings);
        assert!(r.channel.unwrap().orientation.is_vertical());
    }
}
