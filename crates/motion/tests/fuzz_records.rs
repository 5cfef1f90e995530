//! Fuzzing of the record readers with proptest (cargo-fuzz needs a nightly
//! toolchain; these properties run on stable in `cargo test`).
//!
//! Fuzzed: [`parse_at2`], [`parse_two_column`], [`parse_one_column`],
//! [`parse_sequence`], [`parse_esm`], [`parse_knet`], [`parse_cosmos`] and
//! [`load_record_from_str`] (every [`Format`], random specs) on
//! - arbitrary bytes, made text with `String::from_utf8_lossy` as
//!   [`quakejoint_motion::load_record`] does;
//! - "token soup": lines of tokens a record file is made of (numbers in
//!   every spelling, NaN, infinity, header words, separators, BOM, CR);
//! - valid PEER AT2 files (checked to read back exactly), valid ESM,
//!   K-NET and COSMOS files, and the same files after 1 to 4 structured
//!   mutations: truncation at a byte, a line
//!   deleted, duplicated or replaced, a token replaced or inserted
//!   (`nan`, `inf`, `1e400`, `-0`, `1.2.3`, `NPTS= -3`, `DT= 0`, ...),
//!   header line 4 rewritten (NPTS off by a few, negative, zero, huge up
//!   to 2⁶⁴, DT zero, negative, NaN, subnormal), raw bytes inserted
//!   (invalid UTF-8, BOM, NUL, CR, LF).
//!
//! "No panic" means every call returns, `Ok` or `Err`. On top of that,
//! an `Ok` record has at least one sample, finite samples and a finite
//! dt > 0 (an AT2 record exactly the NPTS its header declares), and an
//! error names the file: a reader's message starts with the file name,
//! [`load_record_from_str`]'s contains it.
//!
//! Found by this fuzzer and fixed: a header's NPTS of 10¹¹ or more made
//! `parse_at2` allocate for that many values up front (an abort, or a
//! capacity-overflow panic at `u64::MAX`); the allocation is now bounded by
//! the text's length, and [`huge_npts_is_an_error`] keeps it so.
//!
//! Inputs tried: each of the 5 properties runs `QUAKEJOINT_FUZZ_CASES`
//! cases (default 20 000), so a default run tries 100 000 inputs, each
//! through every reader. A long run:
//!
//! ```text
//! QUAKEJOINT_FUZZ_CASES=1200000 cargo test --release -p quakejoint-motion --test fuzz_records
//! ```
//!
//! tries 6 million inputs.
//!
//! Failures are not persisted (no regression files in the source tree);
//! proptest prints the shrunk input of a failing case.

#[path = "../../../tests/support/fuzz.rs"]
mod fuzz;
#[path = "fuzz_support/other_formats.rs"]
mod other_formats;

use proptest::collection::vec;
use proptest::prelude::*;
use proptest::sample::{select, Index};
use quakejoint_motion::{
    load_record_from_str, parse_at2, parse_cosmos, parse_csmip, parse_esm, parse_knet, parse_one_column,
    parse_sequence, parse_two_column, ChannelChoice, Format, RawRecord, RecordError, RecordSpec, Units, G,
};

/// Every format.
const FORMATS: [Format; 9] = [
    Format::Auto,
    Format::At2,
    Format::TwoColumn,
    Format::OneColumn,
    Format::Esm,
    Format::Knet,
    Format::Cosmos,
    Format::Csmip,
    Format::Sequence,
];

/// Cases per property without `QUAKEJOINT_FUZZ_CASES`: a few seconds per
/// property in `cargo test`.
const DEFAULT_CASES: u32 = 20_000;

fn fuzz_config() -> ProptestConfig {
    fuzz::config(DEFAULT_CASES)
}

/// The AT2 file name used throughout.
const AT2_FILE: &str = "f.AT2";

/// Tokens a record file is made of, good and bad.
const TOKENS: &[&str] = &[
    "0",
    "-0",
    "+0",
    "1",
    "-1",
    ".1",
    "-.8338791E-03",
    "1.765551E-02",
    "1.0D-03",
    "1d3",
    "1.5E+02",
    "5e-324",
    "1e-400",
    "1.7976931348623157e308",
    "1e400",
    "-1e400",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "Infinity",
    "1.2.3",
    "--3",
    "+-1",
    "0x10",
    "1_000",
    ".",
    "E5",
    "e",
    "D",
    "",
    "18446744073709551616",
    "\u{661}",
    "\u{221e}",
    "NPTS=",
    "NPTS",
    "DT=",
    "DT",
    "SEC",
    "NPTS= -3",
    "DT= 0",
    "NPTS= 0",
    "NPTS= 3, DT= .01",
    "NPTS=1,DT=1",
    "npts:2 dt:.5",
    ",",
    ";",
    ",,",
    "#",
    "%",
    "!",
    "time,acc",
    "\t",
    " ",
    "\r",
    "\u{feff}",
    "\u{0}",
    "\u{fffd}",
    "ACCELERATION TIME SERIES IN UNITS OF G",
    "VELOCITY",
    "DISPLACEMENT",
    "UNITS OF G",
    "Uncorrected Accelerogram Data",
    "Corrected accelerogram",
    "/&  ----------  End of Data for Station Channel   1",
    "Chan  1:  90 Deg",
    "Chan  2:  Up",
    " 3 Accelerogram points at 100 pts/sec in units of g.       Format: (8f9.6)",
    " 3 points of accel data equally spaced at 0.005 sec, in cm/sec2. (8f10.6)",
    "  36032080",
];

/// A random spec for `file`: any format, units, dt, column, scale and
/// target PGA, many of them invalid.
fn spec_strategy(file: &'static str) -> impl Strategy<Value = RecordSpec> {
    let dt = prop_oneof![
        Just(None),
        select(vec![0.0, -0.01, 0.01, 0.005, 1e-300, 5e-324, 1e308, f64::NAN, f64::INFINITY]).prop_map(Some),
    ];
    let column = prop_oneof![Just(None), select(vec![0usize, 1, 2, 3, 4, usize::MAX]).prop_map(Some)];
    let scale = select(vec![1.0, -1.0, 2.0, 0.0, 1e-308, 1e308, -1e308, f64::NAN, f64::INFINITY]);
    let target = prop_oneof![Just(None), select(vec![0.3, 0.0, -0.3, 1e-320, 1e308, f64::NAN]).prop_map(Some)];
    let format = select(FORMATS.to_vec());
    let units = select(vec![None, Some(Units::G), Some(Units::MetersPerSecond2), Some(Units::CentimetersPerSecond2)]);
    let channel = (
        select(vec![None, Some(0u32), Some(1), Some(2), Some(u32::MAX)]),
        select(vec![None, Some(90.0), Some(-1.0), Some(f64::NAN)]),
        any::<bool>(),
    );
    (format, units, dt, column, scale, target, channel).prop_map(
        move |(format, units, dt, column, scale, target_pga_g, (channel, azimuth, allow_vertical))| {
            let mut spec = RecordSpec::new(file);
            (spec.channel, spec.azimuth, spec.allow_vertical) = (channel, azimuth, allow_vertical);
            spec.format = format;
            spec.units = units;
            spec.dt = dt;
            spec.column = column;
            spec.scale = scale;
            spec.target_pga_g = target_pga_g;
            spec
        },
    )
}

/// A file name for [`load_record_from_str`] (the extension decides the
/// format under [`Format::Auto`]).
fn file_strategy() -> impl Strategy<Value = &'static str> {
    select(vec![AT2_FILE, "f.at2", "f.txt", "f.csv", "dir/f.AT2", "f", "f.ASC", "f.EW", "f.V2", "f.v1", "f.RAW"])
}

/// Checks a reader's result: a usable record, or an error whose message
/// starts with the file name.
fn check_raw(result: Result<RawRecord, RecordError>, file: &str) -> Result<(), TestCaseError> {
    match result {
        Ok(raw) => {
            prop_assert!(raw.dt.is_finite() && raw.dt > 0.0, "{file}: dt = {}", raw.dt);
            prop_assert!(!raw.values.is_empty(), "{file}: no samples");
            prop_assert!(raw.values.iter().all(|v| v.is_finite()), "{file}: a sample is not finite");
        }
        Err(e) => {
            let msg = e.to_string();
            prop_assert!(msg.starts_with(file), "the error does not start with `{file}`: {msg}");
        }
    }
    Ok(())
}

/// Checks [`load_record_from_str`]: a usable record whose warnings name
/// the file, or an error that names the file.
fn check_load(spec: &RecordSpec, text: &str) -> Result<(), TestCaseError> {
    let file = spec.file.display().to_string();
    match load_record_from_str(spec, text) {
        Ok(loaded) => {
            let rec = &loaded.record;
            prop_assert!(rec.dt.is_finite() && rec.dt > 0.0, "{file}: dt = {}", rec.dt);
            prop_assert!(!rec.acceleration.is_empty(), "{file}: no samples");
            prop_assert!(rec.acceleration.iter().all(|a| a.is_finite()), "{file}: a sample is not finite");
            for w in &loaded.warnings {
                prop_assert!(w.starts_with(&file), "the warning does not start with `{file}`: {w}");
            }
        }
        Err(e) => {
            let msg = e.to_string();
            prop_assert!(msg.contains(&file), "the error does not name `{file}`: {msg}");
        }
    }
    Ok(())
}

/// Every reader on `text`, with the given spec and reader arguments.
fn all_readers(text: &str, spec: &RecordSpec, column: usize, dt: f64) -> Result<(), TestCaseError> {
    check_raw(parse_at2(text, AT2_FILE), AT2_FILE)?;
    check_raw(parse_two_column(text, "f.csv", column), "f.csv")?;
    check_raw(parse_one_column(text, "f.txt", dt, None), "f.txt")?;
    check_raw(parse_one_column(text, "f.txt", dt, Some(column)), "f.txt")?;
    check_raw(parse_sequence(text, "f.txt", dt), "f.txt")?;
    check_raw(parse_esm(text, "f.ASC"), "f.ASC")?;
    check_raw(parse_knet(text, "f.EW"), "f.EW")?;
    check_raw(parse_cosmos(text, "f.V2", ChannelChoice::default()), "f.V2")?;
    for choice in [ChannelChoice::default(), ChannelChoice { number: Some(2), azimuth: None }] {
        check_raw(parse_csmip(text, "f.v1", choice), "f.v1")?;
    }
    check_load(spec, text)?;
    for format in FORMATS {
        let mut s = spec.clone();
        s.format = format;
        check_load(&s, text)?;
        // the same spec with only what the format requires, so that the
        // text is parsed rather than the spec refused
        let mut s = RecordSpec::new(spec.file.clone());
        s.format = format;
        if matches!(s.resolved_format(), Format::OneColumn | Format::Sequence) {
            s.dt = Some(0.01);
        }
        check_load(&s, text)?;
    }
    Ok(())
}

/// [`TOKENS`] and the header words of ESM, K-NET and COSMOS files.
fn tokens() -> Vec<&'static str> {
    TOKENS.iter().chain(other_formats::TOKENS).copied().collect()
}

/// Lines of tokens joined by random separators and line ends.
fn token_soup() -> impl Strategy<Value = String> {
    let token = select(tokens());
    let sep = select(vec![" ", "   ", ",", ", ", ";", "\t"]);
    let line =
        vec((token, sep), 0..8).prop_map(|parts| parts.into_iter().flat_map(|(t, s)| [t, s]).collect::<String>());
    let end = select(vec!["\n", "\r\n", "\r", ""]);
    vec((line, end), 0..12).prop_map(|lines| lines.into_iter().flat_map(|(l, e)| [l, e.to_string()]).collect())
}

/// A valid AT2 file: its text, the values it holds and its dt.
#[derive(Debug, Clone)]
struct ValidAt2 {
    text: String,
    values: Vec<f64>,
    dt: f64,
}

/// `x` in the Fortran layout of PEER files: `-.8338791E-03`.
fn fortran(x: f64) -> String {
    if x == 0.0 {
        return ".0000000E+00".to_string();
    }
    let exponent = x.abs().log10().floor() as i32 + 1;
    let mantissa = x.abs() / 10f64.powi(exponent);
    // rounding may carry the mantissa to 1.0
    let (mantissa, exponent) =
        if mantissa >= 0.99999995 { (mantissa / 10.0, exponent + 1) } else { (mantissa, exponent) };
    let digits = format!("{mantissa:.7}");
    let sign = if x < 0.0 { "-" } else { "" };
    format!("{sign}{}E{}{:02}", &digits[1..], if exponent < 0 { '-' } else { '+' }, exponent.abs())
}

/// A valid PEER AT2 file: 1 to 300 values, each spelt `1.5E-3`,
/// `1.5000000E-3`, `.1500000E-02`, `1.5D-3` or `0.0015`, 1 to 8 per line, header line 4 in one of the spellings the
/// reader accepts, CRLF or LF line ends.
fn valid_at2() -> impl Strategy<Value = ValidAt2> {
    let value = prop_oneof![-2.0f64..2.0, Just(0.0), Just(-0.0), -1e-6f64..1e-6];
    let spelling = 0usize..5;
    let dt = select(vec![(".0050", 0.005), (".0100", 0.01), ("0.02", 0.02), ("1.0D-03", 0.001), ("5E-3", 0.005)]);
    let layout = 0usize..4;
    let crlf = any::<bool>();
    (vec((value, spelling), 2..300), 1usize..=8, dt, layout, crlf).prop_map(
        |(values, per_line, (dt_tok, dt), layout, crlf)| {
            let eol = if crlf { "\r\n" } else { "\n" };
            let n = values.len();
            let line4 = match layout {
                0 => format!("NPTS= {n:6}, DT= {dt_tok:>7} SEC,"),
                1 => format!("NPTS= {n} DT= {dt_tok}"),
                2 => format!("npts={n},dt={dt_tok}"),
                _ => format!("  {n}   {dt_tok}    NPTS, DT"),
            };
            let mut text = format!(
                "PEER NGA STRONG MOTION DATABASE RECORD{eol}Loma Prieta, 10/18/1989, Corralitos, 90{eol}\
                 ACCELERATION TIME SERIES IN UNITS OF G{eol}{line4}{eol}"
            );
            let mut parsed = Vec::with_capacity(n);
            for chunk in values.chunks(per_line) {
                for &(x, spelling) in chunk {
                    let token = match spelling {
                        0 => format!("{x:E}"),
                        1 => format!("{x:.7E}"),
                        2 => fortran(x),
                        3 => format!("{x:e}").replace('e', "D"),
                        _ => format!("{x}"),
                    };
                    parsed.push(token.replace('D', "E").parse::<f64>().expect("a formatted number"));
                    text.push_str("  ");
                    text.push_str(&token);
                }
                text.push_str(eol);
            }
            ValidAt2 { text, values: parsed, dt }
        },
    )
}

/// Header lines 4 that the reader must judge: `{n}` is replaced by the
/// file's value count plus an offset.
const HEADERS: &[&str] = &[
    "NPTS= {n}, DT= .0050 SEC",
    "NPTS= -3, DT= .0050 SEC",
    "NPTS= 0, DT= .0050 SEC",
    "NPTS= {n}, DT= 0",
    "NPTS= {n}, DT= -0",
    "NPTS= {n}, DT= -.005",
    "NPTS= {n}, DT= nan",
    "NPTS= {n}, DT= inf",
    "NPTS= {n}, DT= 1e400",
    "NPTS= {n}, DT= 5e-324",
    "NPTS= {n}, DT= 1e308",
    "NPTS= {n}, DT= 1.2.3",
    "NPTS= {n}.0, DT= .005",
    "NPTS= +{n}, DT= .005",
    "NPTS= 000{n}, DT= .005",
    "NPTS= 1000000, DT= .005",
    "NPTS= 99999999999, DT= .005",
    "NPTS= 9223372036854775807, DT= .005",
    "NPTS= 18446744073709551615, DT= .005",
    "NPTS= 18446744073709551616, DT= .005",
    "NPTS= {n}",
    "DT= .005",
    "",
    "NPTS=, DT=",
    "NPTS: {n} DT: .005",
    "DT= .005 NPTS= {n}",
    "XNPTS= {n}, XDT= .005",
    "NPTS= {n}, DT= .005, NPTS= 1",
    "{n} .005 NPTS, DT",
    "{n} 0 NPTS, DT",
    "-{n} .005 NPTS, DT",
    "NPTS= {n}; DT= .005;",
    "\u{feff}NPTS= {n}, DT= .005",
    "NPTS=\u{a0}{n}, DT=\u{a0}.005",
];

/// Raw byte sequences to insert: invalid UTF-8, BOM, NUL, line ends.
const BYTES: &[&[u8]] =
    &[b"\xff", b"\xc3", b"\x80\x80", b"\xef\xbb\xbf", b"\0", b"\r", b"\n", b"\r\n", b"\xf0\x9f", b" ", b","];

/// One structured change to a file's bytes.
#[derive(Debug, Clone)]
enum Mutation {
    /// Cut the file at a byte.
    Truncate(Index),
    /// Delete a line.
    DeleteLine(Index),
    /// Duplicate a line.
    DuplicateLine(Index),
    /// Replace a line by a token.
    ReplaceLine(Index, &'static str),
    /// Replace a token of a line (or append it to a line without tokens).
    ReplaceToken(Index, Index, &'static str),
    /// Insert a token before a token of a line.
    InsertToken(Index, Index, &'static str),
    /// Rewrite header line 4 from [`HEADERS`] with NPTS = count + offset.
    Header(&'static str, i64),
    /// Insert raw bytes at a byte position.
    InsertBytes(Index, &'static [u8]),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let token = || select(tokens());
    prop_oneof![
        any::<Index>().prop_map(Mutation::Truncate),
        any::<Index>().prop_map(Mutation::DeleteLine),
        any::<Index>().prop_map(Mutation::DuplicateLine),
        (any::<Index>(), token()).prop_map(|(l, t)| Mutation::ReplaceLine(l, t)),
        (any::<Index>(), any::<Index>(), token()).prop_map(|(l, k, t)| Mutation::ReplaceToken(l, k, t)),
        (any::<Index>(), any::<Index>(), token()).prop_map(|(l, k, t)| Mutation::InsertToken(l, k, t)),
        (select(HEADERS.to_vec()), -2i64..=2).prop_map(|(h, d)| Mutation::Header(h, d)),
        (any::<Index>(), select(BYTES.to_vec())).prop_map(|(at, b)| Mutation::InsertBytes(at, b)),
    ]
}

/// Byte ranges of the tokens of a line (runs without white space or comma).
fn token_spans(line: &[u8]) -> Vec<std::ops::Range<usize>> {
    let mut spans = Vec::new();
    let mut start = None;
    for (i, &b) in line.iter().enumerate() {
        let sep = b.is_ascii_whitespace() || b == b',';
        match (sep, start) {
            (false, None) => start = Some(i),
            (true, Some(s)) => {
                spans.push(s..i);
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        spans.push(s..line.len());
    }
    spans
}

impl Mutation {
    /// Applies the change to `bytes`; `count` is the valid file's number of
    /// values (for [`Mutation::Header`]).
    fn apply(&self, bytes: &mut Vec<u8>, count: usize) {
        let mut lines: Vec<Vec<u8>> = bytes.split(|&b| b == b'\n').map(<[u8]>::to_vec).collect();
        match self {
            Mutation::Truncate(at) => {
                bytes.truncate(at.index(bytes.len() + 1));
                return;
            }
            Mutation::InsertBytes(at, new) => {
                let at = at.index(bytes.len() + 1);
                bytes.splice(at..at, new.iter().copied());
                return;
            }
            Mutation::DeleteLine(l) => {
                lines.remove(l.index(lines.len()));
            }
            Mutation::DuplicateLine(l) => {
                let i = l.index(lines.len());
                lines.insert(i, lines[i].clone());
            }
            Mutation::ReplaceLine(l, token) => {
                let i = l.index(lines.len());
                lines[i] = token.as_bytes().to_vec();
            }
            Mutation::ReplaceToken(l, k, token) | Mutation::InsertToken(l, k, token) => {
                let i = l.index(lines.len());
                let line = &mut lines[i];
                let spans = token_spans(line);
                if spans.is_empty() {
                    line.extend_from_slice(token.as_bytes());
                } else {
                    let span = spans[k.index(spans.len())].clone();
                    let (range, new) = if matches!(self, Mutation::ReplaceToken(..)) {
                        (span, token.to_string())
                    } else {
                        (span.start..span.start, format!("{token} "))
                    };
                    line.splice(range, new.bytes());
                }
            }
            Mutation::Header(template, offset) => {
                if lines.len() > 3 {
                    let n = (count as i64 + offset).max(0);
                    lines[3] = template.replace("{n}", &n.to_string()).into_bytes();
                }
            }
        }
        *bytes = lines.join(&b'\n');
    }
}

/// The number of value tokens after the 4 header lines of an AT2 text.
fn value_tokens(text: &str) -> usize {
    text.lines()
        .skip(4)
        .map(|l| l.split(|c: char| c.is_whitespace() || c == ',').filter(|s| !s.is_empty()).count())
        .sum()
}

proptest! {
    #![proptest_config(fuzz_config())]

    /// Arbitrary bytes (made text like `load_record` does) through every
    /// reader.
    #[test]
    fn arbitrary_bytes_never_panic(
        bytes in vec(any::<u8>(), 0..1024),
        spec in file_strategy().prop_flat_map(spec_strategy),
        column in 0usize..5,
        dt in select(vec![0.01, 0.0, -1.0, f64::NAN, 5e-324]),
    ) {
        all_readers(&String::from_utf8_lossy(&bytes), &spec, column, dt)?;
    }

    /// Lines of record tokens through every reader.
    #[test]
    fn token_soup_never_panics(
        text in token_soup(),
        spec in file_strategy().prop_flat_map(spec_strategy),
        column in 0usize..5,
        dt in select(vec![0.01, 0.0, -1.0, f64::NAN, 5e-324]),
    ) {
        all_readers(&text, &spec, column, dt)?;
    }

    /// A valid AT2 file reads back exactly (the base of the mutations).
    #[test]
    fn valid_at2_reads_back(at2 in valid_at2()) {
        let raw = parse_at2(&at2.text, AT2_FILE).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(raw.dt, at2.dt);
        prop_assert_eq!(raw.header_units, quakejoint_motion::HeaderUnits::Stated(Units::G));
        prop_assert_eq!(&raw.values, &at2.values);
        let loaded = load_record_from_str(&RecordSpec::new(AT2_FILE), &at2.text)
            .map_err(|e| TestCaseError::fail(e.to_string()))?;
        let expected: Vec<f64> = at2.values.iter().map(|v| v * G).collect();
        prop_assert_eq!(loaded.record.acceleration, expected);
    }

    /// A valid AT2 file after 1 to 4 mutations: no panic; an `Ok` record
    /// has the NPTS of its header, finite samples and dt > 0; an error
    /// starts with the file name.
    #[test]
    fn mutated_at2_never_panics(
        at2 in valid_at2(),
        mutations in vec(mutation(), 1..=4),
        spec in spec_strategy(AT2_FILE),
    ) {
        let mut bytes = at2.text.clone().into_bytes();
        for m in &mutations {
            m.apply(&mut bytes, at2.values.len());
        }
        let text = String::from_utf8_lossy(&bytes);
        match parse_at2(&text, AT2_FILE) {
            Ok(raw) => {
                prop_assert!(raw.dt.is_finite() && raw.dt > 0.0, "dt = {}", raw.dt);
                prop_assert!(raw.values.iter().all(|v| v.is_finite()));
                let n = raw.values.len();
                prop_assert!(n > 0);
                prop_assert_eq!(n, value_tokens(&text), "values read and value tokens differ");
                prop_assert!(raw.header[3].contains(&n.to_string()), "{} values, header `{}`", n, raw.header[3]);
            }
            Err(e) => {
                let msg = e.to_string();
                prop_assert!(msg.starts_with(AT2_FILE), "the error does not start with `{}`: {}", AT2_FILE, msg);
            }
        }
        all_readers(&text, &spec, 2, 0.01)?;
    }
}

proptest! {
    #![proptest_config(fuzz_config())]

    /// A valid ESM, K-NET or COSMOS file reads (auto-detected) with its
    /// count of values; after 1 to 4 mutations no reader panics, an `Ok`
    /// record is usable and an error names the file.
    #[test]
    fn mutated_other_formats_never_panic(
        valid in other_formats::valid_other(),
        mutations in vec(mutation(), 0..=4),
        spec in file_strategy().prop_flat_map(spec_strategy),
    ) {
        if mutations.is_empty() {
            let loaded = load_record_from_str(&RecordSpec::new(valid.file), &valid.text)
                .map_err(|e| TestCaseError::fail(format!("{}: {e}", valid.file)))?;
            prop_assert_eq!(loaded.record.acceleration.len(), valid.count);
            let want_dt = if valid.file == "f.EW" { 0.01 } else { 0.005 };
            prop_assert_eq!(loaded.record.dt, want_dt);
        }
        let mut bytes = valid.text.clone().into_bytes();
        for m in &mutations {
            m.apply(&mut bytes, valid.count);
        }
        let text = String::from_utf8_lossy(&bytes);
        check_load(&RecordSpec::new(valid.file), &text)?;
        all_readers(&text, &spec, 2, 0.01)?;
    }
}

/// A header declaring a huge NPTS over a few values is an error naming the
/// file, not a panic or a failed allocation (`parse_at2` once reserved
/// NPTS samples up front).
#[test]
fn huge_npts_is_an_error() {
    for npts in ["99999999999", "2305843009213693951", "18446744073709551615"] {
        let text = format!(
            "PEER NGA STRONG MOTION DATABASE RECORD\r\nev\r\nACCELERATION TIME SERIES IN UNITS OF G\r\n\
             NPTS= {npts}, DT= .0050 SEC\r\n .1 .2 .3\r\n"
        );
        let msg = parse_at2(&text, AT2_FILE).expect_err("3 values for a huge NPTS").to_string();
        assert!(msg.starts_with("f.AT2:5: ") && msg.contains("after 3 values"), "{msg}");
    }
}
