//! Fuzzing of the config parser and the model generator with proptest
//! (cargo-fuzz needs a nightly toolchain; these properties run on stable in
//! `cargo test`).
//!
//! Fuzzed: [`Config::from_toml`] on
//! - arbitrary strings;
//! - "TOML soup": lines made of table headers, keys of the config, `=`,
//!   values, brackets, quotes and comments;
//! - `configs/small.toml` after one mutation: a value replaced by an
//!   adversarial one (`0`, `-1`, `1e308`, `nan`, `inf`, `"text"`, `[]`,
//!   `{}`, `true`, `1e-300`, `89.999`, `90`, `1000000`, ...), a line
//!   deleted or duplicated, or a key of any config table (or an unknown
//!   one) inserted with an adversarial value;
//!
//! and every config it accepts through [`build`] (`Drive::None`, as
//! `quakejoint model` does). One mutation keeps the model small: with the
//! shipped joists and pitch, the bearings of center beam 64 and beyond lie
//! outside their beam, so a large `center_beams` is a geometry error.
//!
//! "No panic" means every call returns, `Ok` or `Err`. On top of that, a
//! parser error's message is non-empty and names the file (`c.toml`) or a
//! dotted field (holds `.` or `=`), and a generator error's message is
//! non-empty.
//!
//! Found by this fuzzer and fixed: a `center_beams` of 2³² made the
//! generator allocate every beam's position (34 GB) before it checked the
//! geometry, which aborted the process; the config check now refuses more
//! than `MAX_CENTER_BEAMS` (1000), and [`huge_center_beam_count_is_an_error`]
//! keeps it so.
//!
//! Inputs tried: each of the 3 properties runs `QUAKEJOINT_FUZZ_CASES`
//! cases (default 100 000), so a default run tries 300 000 inputs. A long run:
//!
//! ```text
//! QUAKEJOINT_FUZZ_CASES=10000000 cargo test --release -p quakejoint-model --test fuzz_config
//! ```
//!
//! tries 30 million inputs in about 4 minutes on 2 cores.
//!
//! Failures are not persisted (no regression files in the source tree);
//! proptest prints the shrunk input of a failing case.

#[path = "../../../tests/support/fuzz.rs"]
mod fuzz;

use std::sync::LazyLock;

use proptest::collection::vec;
use proptest::prelude::*;
use proptest::sample::{select, Index};
use quakejoint_model::generator::{build, Drive};
use quakejoint_model::Config;

/// Cases per property without `QUAKEJOINT_FUZZ_CASES`: a few seconds per
/// property in `cargo test`.
const DEFAULT_CASES: u32 = 100_000;

fn fuzz_config() -> ProptestConfig {
    fuzz::config(DEFAULT_CASES)
}

/// The config file name given to the parser.
const SOURCE: &str = "c.toml";

/// The text of `configs/small.toml`, read once.
fn small_toml() -> &'static str {
    static TEXT: LazyLock<String> = LazyLock::new(|| {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../configs/small.toml");
        std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"))
    });
    &TEXT
}

/// Values that a config must judge, as TOML.
const VALUES: &[&str] = &[
    "0",
    "-1",
    "1e308",
    "-1e308",
    "nan",
    "inf",
    "-inf",
    "\"text\"",
    "[]",
    "{}",
    "true",
    "1e-300",
    "89.999",
    "90",
    "1000000",
    "4294967296",
    "9223372036854775807",
    "-0.0",
    "0.5",
    "2",
    "-90",
    "-9223372036854775808",
    "\"guide\"",
    "\"joist\"",
    "\"smooth\"",
    "\"faer\"",
    "\"\"",
    "[1, 2]",
    "{ file = \"x.AT2\" }",
    "1979-05-27",
];

/// Every table of a config and its keys, plus an unknown key in each.
const KEYS: &[(&str, &[&str])] = &[
    ("", &["title"]),
    ("joint", &["enabled", "center_beams", "pitch", "nonsense"]),
    ("joint.center_beam", &["length", "width", "mass", "inertia", "nonsense"]),
    ("joint.support_beam", &["length", "mass", "inertia", "nonsense"]),
    ("joint.bearing", &["mass", "inertia", "nonsense"]),
    ("joint.bushing", &["kx", "ky", "cx", "cy", "nonsense"]),
    ("joint.friction", &["mu", "normal_force", "surfaces", "v_eps", "law", "nonsense"]),
    ("bridge", &["mass", "w0", "period", "damping", "nonsense"]),
    ("record", &["format", "units", "dt", "column", "scale", "target_pga_g", "name", "nonsense"]),
    ("record_y", &["file", "format", "units", "dt", "column", "scale", "target_pga_g", "name", "nonsense"]),
    (
        "simulation",
        &[
            "extra_time",
            "duration",
            "rtol",
            "atol",
            "atol_rotation",
            "bearing_atol_factor",
            "h_max",
            "max_wall_time",
            "max_steps",
            "linear_solver",
            "finite_difference_jacobian",
            "nonsense",
        ],
    ),
    ("service", &["speed", "amplitude", "cycles", "blend", "nonsense"]),
    ("sweep", &["periods", "damping", "anything"]),
    ("nonsense", &["key"]),
];

/// A table of [`KEYS`] and one of its keys.
fn table_key() -> impl Strategy<Value = (&'static str, &'static str)> {
    select(KEYS.to_vec()).prop_flat_map(|(table, keys)| select(keys.to_vec()).prop_map(move |k| (table, k)))
}

/// One change to `configs/small.toml`.
#[derive(Debug, Clone)]
enum Mutation {
    /// Replace the value of a `key = value` line.
    ReplaceValue(Index, &'static str),
    /// Delete a line.
    DeleteLine(Index),
    /// Duplicate a line.
    DuplicateLine(Index),
    /// Set `key = value` in a table: after the table's header if the file
    /// has one (or at the top for the root table), else in a new table at
    /// the end.
    InsertKey(&'static str, &'static str, &'static str),
    /// Insert `key = value` at a line, whichever table that is in.
    InsertLine(Index, &'static str, &'static str),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let value = || select(VALUES.to_vec());
    prop_oneof![
        3 => (any::<Index>(), value()).prop_map(|(l, v)| Mutation::ReplaceValue(l, v)),
        1 => any::<Index>().prop_map(Mutation::DeleteLine),
        1 => any::<Index>().prop_map(Mutation::DuplicateLine),
        3 => (table_key(), value()).prop_map(|((t, k), v)| Mutation::InsertKey(t, k, v)),
        1 => (any::<Index>(), table_key(), value()).prop_map(|(l, (_, k), v)| Mutation::InsertLine(l, k, v)),
    ]
}

impl Mutation {
    fn apply(&self, text: &str) -> String {
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        match *self {
            Mutation::ReplaceValue(l, value) => {
                let assignments: Vec<usize> = (0..lines.len())
                    .filter(|&i| !lines[i].trim_start().starts_with('#') && lines[i].contains('='))
                    .collect();
                let i = assignments[l.index(assignments.len())];
                let key = lines[i].split('=').next().unwrap_or_default().trim().to_string();
                lines[i] = format!("{key} = {value}");
            }
            Mutation::DeleteLine(l) => {
                lines.remove(l.index(lines.len()));
            }
            Mutation::DuplicateLine(l) => {
                let i = l.index(lines.len());
                lines.insert(i, lines[i].clone());
            }
            Mutation::InsertKey(table, key, value) => {
                let line = format!("{key} = {value}");
                let header = format!("[{table}]");
                if table.is_empty() {
                    lines.insert(0, line);
                } else if let Some(i) = lines.iter().position(|l| l.trim() == header) {
                    lines.insert(i + 1, line);
                } else {
                    lines.push(header);
                    lines.push(line);
                }
            }
            Mutation::InsertLine(l, key, value) => {
                let i = l.index(lines.len() + 1);
                lines.insert(i, format!("{key} = {value}"));
            }
        }
        lines.join("\n") + "\n"
    }
}

/// Lines of TOML pieces: table headers and keys of the config, values,
/// brackets, quotes, comments.
fn toml_soup() -> impl Strategy<Value = String> {
    let mut pieces: Vec<&'static str> = vec![
        "[",
        "]",
        "[[",
        "]]",
        "{",
        "}",
        "=",
        ",",
        ".",
        "\"",
        "'",
        "\"\"\"",
        "#",
        " ",
        "\\",
        "\\u",
        "-",
        "+",
        "_",
        "e",
        "inf",
        "nan",
        "true",
        "0x1F",
        "1_000",
        "07",
        "1979-05-27T07:32:00Z",
        "\u{feff}",
        "\u{0}",
        "\t",
        "\r",
    ];
    for &(table, keys) in KEYS {
        pieces.push(table);
        pieces.extend_from_slice(keys);
    }
    pieces.extend_from_slice(VALUES);
    let line = vec(select(pieces), 0..10).prop_map(|p| p.concat());
    vec(line, 0..16).prop_map(|lines| lines.join("\n"))
}

/// Parses `text`; errors must name the file or a field. Returns the config
/// if it was accepted.
fn parse(text: &str) -> Result<Option<Config>, TestCaseError> {
    match Config::from_toml(text, SOURCE) {
        Ok(config) => Ok(Some(config)),
        Err(e) => {
            let msg = e.to_string();
            prop_assert!(!msg.trim().is_empty(), "empty error message");
            prop_assert!(
                msg.contains(SOURCE) || msg.contains('.') || msg.contains('='),
                "the error names neither the file nor a field: {msg}"
            );
            Ok(None)
        }
    }
}

/// Parses `text` and builds every config accepted.
fn parse_and_build(text: &str) -> Result<(), TestCaseError> {
    if let Some(config) = parse(text)? {
        if let Err(e) = build(&config, None, Drive::None) {
            prop_assert!(!e.to_string().trim().is_empty(), "empty error message");
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(fuzz_config())]

    /// Arbitrary strings.
    #[test]
    fn arbitrary_text_never_panics(text in any::<String>()) {
        parse_and_build(&text)?;
    }

    /// Lines of TOML pieces.
    #[test]
    fn toml_soup_never_panics(text in toml_soup()) {
        parse_and_build(&text)?;
    }

    /// `configs/small.toml` with one mutation, through the parser and the
    /// generator.
    #[test]
    fn mutated_small_config_never_panics(m in mutation()) {
        parse_and_build(&m.apply(small_toml()))?;
    }
}

/// The unmutated base parses and builds (else the mutations test nothing).
#[test]
fn small_config_builds() {
    let config = Config::from_toml(small_toml(), SOURCE).expect("configs/small.toml parses");
    let model = build(&config, None, Drive::None).expect("configs/small.toml builds");
    assert_eq!(model.counts.bodies, 15);
}

/// Deeply nested arrays, inline tables and dotted keys are errors (the
/// TOML parser's recursion limit), not a stack overflow.
#[test]
fn deep_nesting_is_an_error() {
    let n = 100_000;
    let texts = [
        format!("a = {}1{}", "[".repeat(n), "]".repeat(n)),
        format!("a = {}1{}", "{a = ".repeat(n), "}".repeat(n)),
        format!("{} = 1", vec!["a"; n].join(".")),
        format!("[{}]", vec!["a"; n].join(".")),
    ];
    for text in texts {
        let msg = Config::from_toml(&text, SOURCE).expect_err("deep nesting").to_string();
        assert!(msg.starts_with(SOURCE), "{msg}");
    }
}

/// `configs/small.toml` with a center-beam count whose positions could not
/// be allocated (10¹² would need 8 TB; `i64::MAX` overflows the capacity) is
/// refused by the config check, naming the key, before anything is built.
#[test]
fn huge_center_beam_count_is_an_error() {
    for n in ["1001", "4294967296", "1000000000000", "9223372036854775807"] {
        let text = small_toml().replace("center_beams = 3", &format!("center_beams = {n}"));
        let err = Config::from_toml(&text, SOURCE).expect_err(n).to_string();
        assert!(err.contains("joint.center_beams"), "{err}");
    }
}
