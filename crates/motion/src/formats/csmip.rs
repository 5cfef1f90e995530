//! CSMIP/DMG Volume 1 (uncorrected) and Volume 2 (corrected) files: the
//! format in which the Center for Engineering Strong Motion Data (CESMD)
//! and the California Strong Motion Instrumentation Program distribute
//! their records (`.v1`, `.RAW`, `.V2`; Shakal and Huang 1985, "Standard
//! tape format for CSMIP strong-motion data tapes", CSMIP OSMS 85-03).
//!
//! A file holds one or more channels, each ending with a line that starts
//! with `/&` (`/&  ----------  End of Data for Station Channel   1`).
//! A channel is
//!
//! ```text
//! Uncorrected Accelerogram Data  ...            text header: 13 lines (V1), 25 (V2)
//! Chan  1:  90 Deg                              (line 7 of a V1, 8 of a V2 header)
//!     1  100    1    3 ...                      100 integers, (16I5), 7 lines
//!   .0050000  .7071000 319.32000 ...            50 (V1) or 100 (V2) reals, (8F10.x)
//!  31932 Accelerogram points at 100 pts/sec in units of g.   Format: (8f9.6)
//!  -.000011 -.000011  .000001 ...               the acceleration
//! ```
//!
//! and in a V2, after the acceleration, the velocity and the displacement
//! in sections of the same form (` 13000 points of veloc data equally
//! spaced at 0.005 sec, in cm/sec.  (8f10.7)`), which are not read.
//!
//! | what | where |
//! |---|---|
//! | number of samples | the acceleration line's first number |
//! | time step | V1: `at 100 pts/sec` on the acceleration line (dt = 1/100 s); V2: `spaced at 0.005 sec` there, checked against real-header value 61 (1-based) when that is stated |
//! | units | the acceleration line: `in units of g`, `in cm/sec2`, `(UNITS: CM/SEC/SEC)` |
//! | channel | `Chan  N:` in the text header; its orientation after the colon (`90 Deg`, `Up`, `Long`), else integer-header value 27 (0-360 azimuth, 500 up, 600 down, 800 long, 900 transverse) |
//! | peak | V2 `Peak acceleration =`, V1 `Max  =`: a warning beyond 1 % of the data's |
//!
//! Numbers are read in their fixed-width fields, since Fortran runs them
//! together (`  36032080` is 360 and 32080 in `(16I5)`). The layout
//! follows the USGS reader (gmprocess `io/dmg/core.py`: 13 and 25 text
//! lines, 100 integers, 50 and 100 reals) and was checked on real files:
//! `ground_motions/cesmd/` (`PROVENANCE.md` there).

use crate::error::RecordError;
use crate::formats::channel::{choose, Channel, ChannelChoice, Orientation};
use crate::formats::fortran::{any_fortran_format, fixed_fields};
use crate::formats::{peak, peak_warning};
use crate::record::RawRecord;
use crate::spec::{HeaderUnits, Units};
use crate::text::{excerpt, number, number_at, parse_number};

/// Volume 1 (uncorrected) or 2 (corrected).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Volume {
    One,
    Two,
}

impl Volume {
    /// Lines of text header, reals in the real header, and the data's
    /// default (values per line, width) when the data line names no format.
    fn layout(self) -> (usize, usize, (usize, usize)) {
        match self {
            Volume::One => (13, 50, (8, 9)),
            Volume::Two => (25, 100, (8, 10)),
        }
    }
}

/// Whether `line` opens a CSMIP channel (`Uncorrected Accelerogram Data`,
/// `Corrected accelerogram`), and which volume.
fn volume_of(line: &str) -> Option<Volume> {
    let l = line.trim_start().to_ascii_lowercase();
    if l.starts_with("uncorrected accelerogram") {
        Some(Volume::One)
    } else if l.starts_with("corrected accelerogram") {
        Some(Volume::Two)
    } else {
        None
    }
}

/// Whether a file's first non-blank line is that of a CSMIP file.
pub fn looks_like_csmip(first_line: &str) -> bool {
    volume_of(first_line).is_some()
}

/// One channel's headers.
struct Header {
    volume: Volume,
    /// index of the channel's first line
    start: usize,
    /// the channel as the file states it
    channel: Channel,
    /// real-header values
    reals: Vec<f64>,
    /// index of the acceleration line
    data: usize,
    /// index past the channel's last line
    end: usize,
}

/// The file's lines, for errors that name the line.
struct Reader<'a> {
    lines: Vec<&'a str>,
    file: &'a str,
}

impl Reader<'_> {
    fn err(&self, index: usize, message: String) -> RecordError {
        RecordError::Header { file: self.file.into(), line: index + 1, message }
    }

    /// `count` numbers in fields of `width` from line `at`, before line
    /// `end` (the channel's end); the numbers and the index after them.
    fn block(
        &self,
        at: usize,
        end: usize,
        count: usize,
        width: usize,
        what: &str,
    ) -> Result<(Vec<f64>, usize), RecordError> {
        let mut values = Vec::with_capacity(count);
        let mut i = at;
        while values.len() < count {
            let line = self.lines.get(i).filter(|_| i < end).ok_or_else(|| {
                self.err(i.min(self.lines.len()).saturating_sub(1), format!("the channel ends inside the {what}"))
            })?;
            for field in fixed_fields(line, width) {
                if values.len() == count {
                    break;
                }
                let v = parse_number(field)
                    .map_err(|_| self.err(i, format!("`{}` in the {what} is not a number", excerpt(field, 20))))?;
                values.push(v);
            }
            i += 1;
        }
        Ok((values, i))
    }

    /// The headers of the channel starting at `start` and ending before
    /// `end` (its `/&` line included).
    fn header(&self, start: usize, end: usize) -> Result<Header, RecordError> {
        let volume = volume_of(self.lines[start]).ok_or_else(|| {
            self.err(
                start,
                format!(
                    "`{}` does not open a CSMIP channel (`Uncorrected Accelerogram Data` or `Corrected accelerogram`)",
                    excerpt(self.lines[start].trim(), 60)
                ),
            )
        })?;
        let (n_text, n_reals, _) = volume.layout();
        if start + n_text >= end {
            return Err(
                self.err(end.saturating_sub(1), format!("the channel ends inside its {n_text}-line text header"))
            );
        }
        let (ints, next) = self.block(start + n_text, end, 100, 5, "integer header")?;
        let (reals, data) = self.block(next, end, n_reals, 10, "real header")?;
        let data_line = self.lines.get(data).copied().unwrap_or("");
        let count = data_line.split_whitespace().next().and_then(|t| t.parse::<usize>().ok());
        if count.is_none() || !data_line.to_ascii_lowercase().contains("accel") {
            return Err(self.err(
                data,
                format!(
                    "`{}` is not the acceleration line expected after the headers (e.g. ` 31932 Accelerogram points \
                     at 100 pts/sec in units of g.`)",
                    excerpt(data_line.trim(), 60)
                ),
            ));
        }
        let text = &self.lines[start..start + n_text];
        let chan = text.iter().find_map(|l| chan_line(l));
        let code = ints.get(26).map(|&c| c as i64).filter(|&c| c != -999);
        let orientation = match (&chan, code) {
            (Some((_, o)), _) if *o != Orientation::Unknown => o.clone(),
            (_, Some(c)) => orientation_code(c),
            _ => Orientation::Unknown,
        };
        let number = chan.map(|(n, _)| n).unwrap_or(0);
        Ok(Header { volume, start, channel: Channel { number, of: 0, orientation }, reals, data, end })
    }
}

/// `Chan  1:  90 Deg   Location: ...`: the number and the orientation.
fn chan_line(line: &str) -> Option<(u32, Orientation)> {
    let t = line.trim_start();
    if !t.get(..4)?.eq_ignore_ascii_case("chan") {
        return None;
    }
    let (num, rest) = t[4..].split_once(':')?;
    let number = num.trim().parse().ok()?;
    let rest = rest.trim_start();
    let label = rest.split("  ").next().unwrap_or("");
    Some((number, Orientation::from_label(label)))
}

/// Integer-header value 27: 0-360 azimuth, 500 up, 600 down, 800
/// longitudinal, 900 transverse.
fn orientation_code(code: i64) -> Orientation {
    match code {
        0..=360 => Orientation::Azimuth { degrees: code as f64 },
        500 => Orientation::Vertical { label: "Up".into() },
        600 => Orientation::Vertical { label: "Down".into() },
        800 => Orientation::Axis { label: "Long".into() },
        900 => Orientation::Axis { label: "Tran".into() },
        _ => Orientation::Unknown,
    }
}

/// The number after `key` on `line` (`spaced at  .010 sec` -> 0.01).
fn number_after(line: &str, key: &str) -> Option<f64> {
    let lower = line.to_ascii_lowercase();
    let rest = &line[lower.find(key)? + key.len()..];
    rest.split_whitespace().next().and_then(|t| parse_number(t.trim_end_matches([',', '.'])).ok())
}

/// The number before `key` on `line` (`at 100 pts/sec` -> 100).
fn number_before(line: &str, key: &str) -> Option<f64> {
    let lower = line.to_ascii_lowercase();
    line[..lower.find(key)?].split_whitespace().last().and_then(|t| parse_number(t).ok())
}

/// The units of the acceleration line: `in units of g.`, `(UNITS:
/// CM/SEC/SEC)`, `in cm/sec2.`.
fn units_of(line: &str) -> HeaderUnits {
    let lower = line.to_ascii_lowercase();
    let after = |key: &str| lower.find(key).map(|p| &line[p + key.len()..]);
    let text = after("units of").or_else(|| after("units:")).or_else(|| after(" in "));
    let Some(word) = text.and_then(|t| t.split_whitespace().next()) else { return HeaderUnits::Missing };
    let word = word.trim_end_matches([')', ',', '.']);
    match Units::from_header(word) {
        Some(u) => HeaderUnits::Stated(u),
        None => HeaderUnits::Unrecognised(excerpt(word, 20)),
    }
}

/// The channels of a file: (first line, past the `/&` line) of each.
fn channel_spans(lines: &[&str]) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut start = None;
    for (i, line) in lines.iter().enumerate() {
        if start.is_none() && !line.trim().is_empty() {
            start = Some(i);
        }
        if line.trim_start().starts_with("/&") {
            if let Some(s) = start.take() {
                spans.push((s, i + 1));
            }
        }
    }
    if let Some(s) = start {
        spans.push((s, lines.len()));
    }
    spans
}

/// Parse the text of a CSMIP Volume 1 or 2 file; `file` names it in
/// errors; `choice` picks the channel (module doc). The acceleration is in
/// the file's units.
pub fn parse_csmip(text: &str, file: &str, choice: ChannelChoice) -> Result<RawRecord, RecordError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim().is_empty() {
        return Err(RecordError::Empty { file: file.into() });
    }
    let r = Reader { lines: text.lines().collect(), file };
    let spans = channel_spans(&r.lines);
    let mut headers = spans.iter().map(|&(s, e)| r.header(s, e)).collect::<Result<Vec<_>, _>>()?;
    let of = headers.len() as u32;
    for (k, h) in headers.iter_mut().enumerate() {
        h.channel.of = of;
        if h.channel.number == 0 {
            h.channel.number = k as u32 + 1;
        }
    }
    let channels: Vec<Channel> = headers.iter().map(|h| h.channel.clone()).collect();
    let (pick, choice_warning) = choose(file, &channels, choice)?;
    let h = &headers[pick];
    let (_, _, default_format) = h.volume.layout();
    let line = r.lines[h.data];
    let n: usize = line.split_whitespace().next().and_then(|t| t.parse().ok()).unwrap_or(0);
    let (_, width) = any_fortran_format(line).unwrap_or(default_format);
    let dt = match h.volume {
        Volume::One => {
            let rate = number_before(line, "pts/sec").or_else(|| number_before(line, "samples/sec"));
            rate.filter(|&f| f > 0.0).map(|f| 1.0 / f)
        }
        Volume::Two => number_after(line, "spaced at"),
    };
    let Some(dt) = dt.filter(|d| d.is_finite() && *d > 0.0) else {
        return Err(r.err(
            h.data,
            format!(
                "`{}` states no time step (`at 100 pts/sec` in a Volume 1, `spaced at 0.005 sec` in a Volume 2)",
                excerpt(line.trim(), 60)
            ),
        ));
    };
    if h.volume == Volume::Two {
        if let Some(&stated) = h.reals.get(60).filter(|v| **v > 0.0) {
            if (stated - dt).abs() > 1e-6 * dt.max(stated) {
                return Err(r.err(
                    h.data,
                    format!(
                        "the acceleration line says dt = {} s but real-header value 61 says {} s",
                        number(dt),
                        number(stated)
                    ),
                ));
            }
        }
    }
    // the count is the file's word: reserve no more than the channel's lines hold
    let mut values = Vec::with_capacity(n.min((h.end - h.data) * (80 / width.max(1) + 1)));
    let mut i = h.data + 1;
    while values.len() < n {
        let Some(&row) = r.lines.get(i).filter(|_| i < h.end) else {
            return Err(r.err(
                i.min(r.lines.len()).saturating_sub(1),
                format!("line {} announces {n} points but the channel ends after {}", h.data + 1, values.len()),
            ));
        };
        // the next section (`  7808 points of veloc data ...`) or the channel's end
        if row.trim_start().starts_with(|c: char| c.is_alphabetic() || c == '/')
            || row.to_ascii_lowercase().contains("points")
        {
            return Err(r.err(
                i,
                format!(
                    "line {} announces {n} points but `{}` ends them after {}",
                    h.data + 1,
                    excerpt(row.trim(), 40),
                    values.len()
                ),
            ));
        }
        for field in fixed_fields(row, width) {
            if values.len() < n && !field.is_empty() {
                values.push(number_at(field, file, i + 1)?);
            }
        }
        i += 1;
    }
    if values.is_empty() {
        return Err(RecordError::TooShort { file: file.into(), message: "0 acceleration points".into() });
    }
    let header_units = units_of(line);
    let (n_text, _, _) = h.volume.layout();
    let header: Vec<String> = r.lines[h.start..h.start + n_text].iter().map(|l| l.trim_end().to_string()).collect();
    let mut warnings: Vec<String> = choice_warning.into_iter().collect();
    if h.volume == Volume::One {
        warnings.push(format!(
            "{file}: a Volume 1 record (uncorrected): not baseline-corrected or filtered; the Volume 2 (corrected) \
             file of the same record is usually what is wanted"
        ));
    }
    let stated_peak = header.iter().find(|l| {
        let l = l.to_ascii_lowercase();
        match h.volume {
            Volume::Two => l.trim_start().starts_with("peak acceleration"),
            Volume::One => l.contains("max  =") || l.contains("max ="),
        }
    });
    if let (Some(l), HeaderUnits::Stated(u)) = (stated_peak, &header_units) {
        if let Some(p) = number_after(l, "=").filter(|p| *p != 0.0) {
            warnings.extend(peak_warning(file, "peak", p.abs(), peak(&values), u.name()));
        }
    }
    Ok(RawRecord { dt, values, header, first_time: None, header_units, warnings, channel: Some(h.channel.clone()) })
}
