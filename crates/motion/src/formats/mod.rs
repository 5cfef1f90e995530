//! Record formats of other databases than PEER, and how
//! [`Format::Auto`] tells them apart.
//!
//! - [`esm`]: ESM (Engineering Strong Motion database, ORFEUS) ASCII;
//! - [`knet`]: K-NET / KiK-net (NIED) ASCII;
//! - [`cosmos`]: COSMOS Strong-Motion Data Format v1.20, V1/V2
//!   acceleration;
//! - [`csmip`]: CSMIP/DMG Volume 1 and 2, the format CESMD distributes;
//! - [`channel`]: choosing a channel of a file that holds several.
//!
//! [`detect_format`] resolves [`Format::Auto`] from the spec and the
//! file's content: an `.at2` extension means AT2 (as before); else the
//! first non-blank line names ESM (`EVENT_NAME:`), K-NET (`Origin Time`),
//! COSMOS (`(Format v`) or CSMIP (`Uncorrected Accelerogram Data`,
//! `Corrected accelerogram`); else plain text, one-column if `dt` is
//! given, two-column if not.

pub mod channel;
pub mod cosmos;
pub mod csmip;
pub mod esm;
pub(crate) mod fortran;
pub mod knet;

use crate::error::RecordError;
use crate::spec::{Format, RecordSpec};
use crate::text::{excerpt, parse_number};

/// The format a file of this content has, from its first non-blank line:
/// ESM (`EVENT_NAME:`), K-NET/KiK-net (`Origin Time`), COSMOS (a line
/// holding `(Format v`), CSMIP (`Uncorrected Accelerogram Data`,
/// `Corrected accelerogram`), else `None` (AT2 is told by its extension).
pub fn sniff_format(text: &str) -> Option<Format> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let first = text.lines().map(str::trim).find(|l| !l.is_empty())?;
    // the first 200 bytes are enough, and a megabyte line is not copied
    let head: String = first.chars().take(200).collect::<String>().to_ascii_uppercase();
    if head.starts_with("EVENT_NAME:") {
        Some(Format::Esm)
    } else if head.starts_with("ORIGIN TIME") {
        Some(Format::Knet)
    } else if head.contains("(FORMAT V") {
        Some(Format::Cosmos)
    } else if csmip::looks_like_csmip(first) {
        Some(Format::Csmip)
    } else {
        None
    }
}

/// The format `spec` reads `text` as: `spec.format` unless it is
/// [`Format::Auto`]; then an `.at2` extension (any case) means
/// [`Format::At2`], else [`sniff_format`] decides, else
/// [`Format::OneColumn`] if `dt` is given, else [`Format::TwoColumn`].
pub fn detect_format(spec: &RecordSpec, text: &str) -> Format {
    match spec.format {
        Format::Auto if spec.has_at2_extension() => Format::At2,
        Format::Auto => {
            sniff_format(text).unwrap_or(if spec.dt.is_some() { Format::OneColumn } else { Format::TwoColumn })
        }
        f => f,
    }
}

/// The formats read, for refusals.
pub const FORMATS_READ: &str = "Formats read: PEER NGA `.AT2`; ESM ASCII (first line `EVENT_NAME:`); K-NET/KiK-net \
                                ASCII (first line `Origin Time`); COSMOS V1/V2 (first line `... (Format v01.20 ...)`); \
                                CSMIP/DMG Volume 1/2 from CESMD (first line `Uncorrected Accelerogram Data` or \
                                `Corrected accelerogram`); plain numeric text or CSV with at most one column-header \
                                line.";

/// What to do with a file of another format, for refusals.
pub const OTHER_FORMAT: &str = "For another format, remove the header and read the values with \
                                `format = \"sequence\"`, `dt` and `units` (`--format sequence --dt S --units U`), or \
                                convert the file to a two-column CSV (time [s], acceleration).";

/// Whether `text` looks like a PEER AT2 file: line 4 names NPTS and DT.
fn looks_like_at2(text: &str) -> bool {
    text.lines().nth(3).is_some_and(|l| {
        let u: String = l.chars().take(200).collect::<String>().to_ascii_uppercase();
        u.contains("NPTS") && u.contains("DT")
    })
}

/// Whether `line` looks like an ESM header line: `KEY_IN_CAPITALS: value`.
fn looks_like_esm_key(line: &str) -> bool {
    line.split_once(':').is_some_and(|(k, _)| {
        !k.is_empty() && k.chars().all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || "_/^".contains(c))
    })
}

/// The refusal of a text line found where a plain-text record holds
/// numbers: it quotes the line (shortened), says which format the file
/// looks like if any, names the formats read and what to do for another.
/// The guidance comes on lines of its own after the cause, so that every
/// line stays short. `reading` is the format the file was read as: a
/// sequence is not advised to one that is read as a sequence already.
pub(crate) fn not_numeric_data(
    file: &str,
    line: usize,
    content: &str,
    text: &str,
    header_line: Option<usize>,
    reading: Format,
) -> RecordError {
    let mut message = format!("`{}` is not numeric data", excerpt(content, 60));
    if let Some(h) = header_line {
        message += &format!(" (line {h} was taken as the column header; a text record has one header line at most)");
    }
    message += ".";
    if let Some(f) = sniff_format(text) {
        message += &format!(
            "\nThe file looks like {}: read it with `format = \"auto\"` (`--format auto`, the default) or \
             `\"{}\"` (`--format {}`).",
            f.description(),
            f.name(),
            f.name()
        );
    } else if looks_like_at2(text) {
        message +=
            "\nThe file looks like a PEER NGA AT2 file: name it `.AT2` or set `format = \"at2\"` (`--format at2`).";
    } else if looks_like_esm_key(content) {
        message += "\n`KEY: value` lines look like an ESM header, but an ESM file starts with `EVENT_NAME:`: read the \
                    whole ESM file.";
    }
    message += "\n";
    message += FORMATS_READ;
    message += "\n";
    message += if reading == Format::Sequence {
        "A sequence holds numbers only, in reading order: remove every line before the first value (a header) \
         and after the last (a trailer) from a copy of the file."
    } else {
        OTHER_FORMAT
    };
    RecordError::Header { file: file.into(), line, message }
}

/// The warning for a header's peak that differs from the data's by more
/// than 1 %.
pub(crate) fn peak_warning(file: &str, key: &str, header: f64, data: f64, unit: &str) -> Option<String> {
    let apart = (data - header).abs() / header.abs().max(f64::MIN_POSITIVE);
    (apart > 0.01).then(|| {
        format!(
            "{file}: the header's {key} = {header} {unit} but the data peak at {data:.4} {unit} ({:.1} % apart): \
             the file may be cut or its header may belong to another record",
            100.0 * apart
        )
    })
}

/// Largest |value|.
pub(crate) fn peak(values: &[f64]) -> f64 {
    values.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// Whether the first token of `line` reads as a number (NaN and infinity
/// included: they are data, refused later by name).
pub(crate) fn starts_with_number(line: &str) -> bool {
    line.split_whitespace().next().is_some_and(|t| parse_number(t) != Err(crate::text::NumberError::NotANumber))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sniffing() {
        assert_eq!(sniff_format("EVENT_NAME: X\nEVENT_ID: Y\n"), Some(Format::Esm));
        assert_eq!(sniff_format("\u{feff}\n\nOrigin Time       2011/03/11 14:46:00\n"), Some(Format::Knet));
        let cosmos = "Corrected acceleration  (Format v01.20 with 13 text lines) Src: X\n";
        assert_eq!(sniff_format(cosmos), Some(Format::Cosmos));
        for text in ["time,acc\n0,0\n", "PEER NGA STRONG MOTION DATABASE RECORD\n", "", "0.1\n"] {
            assert_eq!(sniff_format(text), None, "{text}");
        }
        let spec = |file: &str, dt: Option<f64>| {
            let mut s = RecordSpec::new(file);
            s.dt = dt;
            s
        };
        assert_eq!(detect_format(&spec("x.AT2", None), "EVENT_NAME: X\n"), Format::At2, "the extension rules AT2");
        assert_eq!(detect_format(&spec("x.asc", None), "EVENT_NAME: X\n"), Format::Esm);
        assert_eq!(detect_format(&spec("x.asc", Some(0.01)), "EVENT_NAME: X\n"), Format::Esm);
        assert_eq!(detect_format(&spec("x.txt", Some(0.01)), "0.1\n"), Format::OneColumn);
        assert_eq!(detect_format(&spec("x.txt", None), "0 0.1\n"), Format::TwoColumn);
        let mut s = spec("x.txt", None);
        s.format = Format::Sequence;
        assert_eq!(detect_format(&s, "EVENT_NAME: X\n"), Format::Sequence, "an explicit format is kept");
    }
}
