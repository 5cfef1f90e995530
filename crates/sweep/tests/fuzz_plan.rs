//! Fuzzing of the sweep plan reader with proptest (cargo-fuzz needs a
//! nightly toolchain; these properties run on stable in `cargo test`).
//!
//! Fuzzed: [`Plan::new`] on `configs/small.toml` followed by a random
//! `[sweep]` table, record paths resolved against `configs/` as for a
//! config there. Each key is, 4 times in 5, missing or usable, else
//! adversarial, so that most inputs get past the first keys checked:
//! - `periods`: a list of numbers and non-numbers (zero, negative, NaN,
//!   infinity, subnormal, strings, nested lists), a scalar, or a range
//!   table with random `from`, `to`, `count` (negative, zero, one, up to
//!   `i64::MAX`, float, string), `spacing` and unknown keys;
//! - `damping`, `histories`: lists or scalars of good and bad values;
//! - `records`: 1 or 2 usable records (the Corralitos records, one twice,
//!   named, flipped, scaled to a PGA), a bad entry among them (a missing
//!   file, a directory, a TOML file read as a record, an invalid spec, a
//!   table without `file`, not a table), an empty list, or not a list;
//! - `cases`: not a list, or up to 3 `[[sweep.cases]]` with a name (missing,
//!   empty, blank, duplicated, not a string) and up to 3 overrides of any
//!   key (joint, bridge, simulation parameters, the swept ones, tables that
//!   may not be overridden, unknown keys) with adversarial values;
//! - `checkpoint_seconds` and an unknown key.
//!
//! "No panic" means every call returns, `Ok` or `Err`. On top of that, an
//! error's message is non-empty, and an accepted plan is consistent:
//! periods finite and > 0, damping ratios in [0, 1), at least one case and
//! one record, unique case names, history indices among the periods, a
//! finite checkpoint interval > 0, and job indices that round-trip.
//!
//! Found by this fuzzer and fixed: a period `count` of 10¹² aborted the
//! process (the range was allocated before anything else; it is now limited
//! to `MAX_PERIODS`, a million), and a `center_beams` near `i64::MAX`
//! overflowed the plan's body count (the config check now refuses more than
//! 1000 center beams). The tests at the end keep both so.
//!
//! Inputs tried: the property runs `QUAKEJOINT_FUZZ_CASES` cases (default
//! 15 000), so a default run tries 15 000 inputs. A long run:
//!
//! ```text
//! QUAKEJOINT_FUZZ_CASES=1000000 cargo test --release -p quakejoint-sweep --test fuzz_plan
//! ```
//!
//! tries a million inputs in about 4 minutes (the property runs on one
//! core).
//!
//! Failures are not persisted (no regression files in the source tree);
//! proptest prints the shrunk input of a failing case.

#[path = "../../../tests/support/fuzz.rs"]
mod fuzz;

use std::path::{Path, PathBuf};
use std::sync::LazyLock;

use proptest::collection::vec;
use proptest::option;
use proptest::prelude::*;
use proptest::sample::select;
use quakejoint_sweep::{Job, Plan};

/// Cases of the property without `QUAKEJOINT_FUZZ_CASES`: a few seconds in
/// `cargo test`.
const DEFAULT_CASES: u32 = 15_000;

fn fuzz_config() -> ProptestConfig {
    fuzz::config(DEFAULT_CASES)
}

/// The config file name given to the plan.
const SOURCE: &str = "c.toml";

/// The repository's `configs/` directory: the base of the record paths.
fn configs_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs")
}

/// The text of `configs/small.toml`, read once.
fn small_toml() -> &'static str {
    static TEXT: LazyLock<String> = LazyLock::new(|| {
        let path = configs_dir().join("small.toml");
        std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    });
    &TEXT
}

/// Values any key may get, as TOML.
const VALUES: &[&str] = &[
    "0",
    "-1",
    "1",
    "0.5",
    "2",
    "1e308",
    "-1e308",
    "1e-300",
    "5e-324",
    "nan",
    "inf",
    "-inf",
    "-0.0",
    "\"text\"",
    "\"\"",
    "[]",
    "{}",
    "true",
    "1000000",
    "-9223372036854775808",
    "[1, 2]",
    "[[]]",
    "{ a = 1 }",
];

/// Periods [s] a sweep would use.
const GOOD_PERIODS: &[&str] = &["0.2", "0.5", "0.94", "1", "1.0", "2.0", "3.0"];

/// Numbers good and bad for periods and histories [s].
const NUMBERS: &[&str] = &[
    "0.2", "0.94", "1", "3.0", "0", "-0.0", "-1", "1e308", "1e-300", "5e-324", "nan", "inf", "-inf", "\"1\"", "true",
    "[]", "{}",
];

/// Damping ratios a sweep would use.
const GOOD_DAMPING: &[&str] = &["0", "0.02", "0.05", "0.5", "0.999"];

/// Damping ratios good and bad.
const DAMPING: &[&str] = &["0.05", "1", "1.0", "-0.01", "nan", "inf", "1e-300", "\"0.05\"", "[]"];

/// Period counts of a range table, good and bad.
const COUNTS: &[&str] = &[
    "-5",
    "0",
    "1",
    "2",
    "8",
    "50",
    "1000",
    "100000",
    "1000001",
    "1000000000000",
    "9223372036854775807",
    "8.0",
    "\"8\"",
    "nan",
    "-9223372036854775808",
    "[]",
];

/// Usable record entries (two of them share a name).
const GOOD_RECORDS: &[&str] = &[
    "{ file = \"../ground_motions/RSN753_LOMAP_CLS090-hor2.AT2\" }",
    "{ file = \"../ground_motions/RSN753_LOMAP_CLS000-hor1.AT2\" }",
    "{ file = \"../ground_motions/RSN753_LOMAP_CLS090-hor2.AT2\", name = \"b\" }",
    "{ file = \"../ground_motions/RSN753_LOMAP_CLS090-hor2.AT2\", scale = -1.0 }",
    "{ file = \"../ground_motions/RSN753_LOMAP_CLS090-hor2.AT2\", target_pga_g = 0.3, name = \"c\" }",
];

/// Record entries that cannot be used: missing, unreadable, invalid.
const BAD_RECORDS: &[&str] = &[
    "{ file = \"../ground_motions/RSN753_LOMAP_CLS090-hor2.AT2\", target_pga_g = 0.0 }",
    "{ file = \"../ground_motions/RSN753_LOMAP_CLS090-hor2.AT2\", scale = 1e308 }",
    "{ file = \"../ground_motions/RSN753_LOMAP_CLS090-hor2.AT2\", dt = 0.01 }",
    "{ file = \"../ground_motions/RSN753_LOMAP_CLS090-hor2.AT2\", format = \"one-column\" }",
    "{ file = \"../ground_motions/RSN753_LOMAP_CLS090-hor2.AT2\", units = \"gal\" }",
    "{ file = \"missing.AT2\" }",
    "{ file = \"\" }",
    "{ file = \".\" }",
    "{ file = \"small.toml\" }",
    "{ file = \"small.toml\", format = \"one-column\", dt = 0.01 }",
    "{}",
    "{ nonsense = 1 }",
    "\"text\"",
    "1",
    "[]",
];

/// Overrides a case may make, with values that pass.
const GOOD_OVERRIDES: &[(&str, &str)] = &[
    ("joint.friction.normal_force", "40e3"),
    ("joint.friction.mu", "0.1"),
    ("joint.friction.law", "\"smooth\""),
    ("joint.pitch", "0.14"),
    ("joint.enabled", "false"),
    ("joint.center_beams", "5"),
    ("bridge.mass", "2e8"),
    ("simulation.duration", "5.0"),
    ("simulation.rtol", "1e-5"),
];

/// Keys a case may try to override (and some it may not).
const OVERRIDES: &[&str] = &[
    "joint.friction.normal_force",
    "joint.friction.mu",
    "joint.friction.law",
    "joint.center_beams",
    "joint.pitch",
    "joint.enabled",
    "joint.center_beam.width",
    "joint.support_beams",
    "joint.nonsense",
    "joint",
    "bridge.mass",
    "bridge.period",
    "bridge.w0",
    "bridge.damping",
    "bridge",
    "simulation.duration",
    "simulation.rtol",
    "simulation.max_steps",
    "simulation",
    "record.scale",
    "record",
    "service.speed",
    "sweep.periods",
    "nonsense",
];

/// Case names, as TOML.
const GOOD_NAMES: &[&str] = &["\"a\"", "\"b\"", "\"c\"", "\"d\"", "\"e\"", "\"f\"", "\"g\"", "\"preload 40 kN\""];

/// Case names that are refused.
const BAD_NAMES: &[&str] = &["\"\"", "\"  \"", "1", "[]"];

/// Usually `good`, sometimes `bad`: most inputs get past the early keys and
/// reach the later ones.
fn mostly<T: std::fmt::Debug>(
    good: impl Strategy<Value = T> + 'static,
    bad: impl Strategy<Value = T> + 'static,
) -> BoxedStrategy<T> {
    prop_oneof![4 => good, 1 => bad].boxed()
}

/// A TOML list of `len` items from `items`.
fn list(items: &'static [&'static str], len: std::ops::RangeInclusive<usize>) -> impl Strategy<Value = String> {
    vec(select(items.to_vec()), len).prop_map(|v| format!("[{}]", v.join(", ")))
}

/// One item of `items` as a `String`.
fn one(items: &'static [&'static str]) -> impl Strategy<Value = String> {
    select(items.to_vec()).prop_map(str::to_string)
}

/// A list, a scalar or something else for a key holding numbers.
fn bad_numbers(items: &'static [&'static str]) -> impl Strategy<Value = String> {
    prop_oneof![3 => list(items, 0..=5), 1 => one(items), 1 => one(VALUES)]
}

/// A period range table with random (or missing) entries.
fn period_range() -> impl Strategy<Value = String> {
    let number = || option::weighted(0.9, select(NUMBERS.to_vec()));
    let count = option::weighted(0.9, select(COUNTS.to_vec()));
    let spacing = option::of(select(vec!["\"log\"", "\"linear\"", "\"LOG\"", "\"\"", "1", "true"]));
    (number(), number(), count, spacing, prop::bool::weighted(0.1)).prop_map(|(from, to, count, spacing, unknown)| {
        let entries: Vec<String> = [("from", from), ("to", to), ("count", count), ("spacing", spacing)]
            .into_iter()
            .filter_map(|(k, v)| v.map(|v| format!("{k} = {v}")))
            .chain(unknown.then(|| "step = 1".to_string()))
            .collect();
        format!("{{ {} }}", entries.join(", "))
    })
}

/// A period range a sweep would use.
fn good_period_range() -> impl Strategy<Value = String> {
    (2usize..=60, select(vec!["log", "linear"]))
        .prop_map(|(count, spacing)| format!("{{ from = 0.2, to = 3.0, count = {count}, spacing = \"{spacing}\" }}"))
}

/// One `[[sweep.cases]]` entry.
#[derive(Debug, Clone)]
struct CaseTable {
    name: Option<&'static str>,
    overrides: Vec<(&'static str, &'static str)>,
}

fn case_table() -> impl Strategy<Value = CaseTable> {
    let good = (select(GOOD_NAMES.to_vec()), vec(select(GOOD_OVERRIDES.to_vec()), 0..=2))
        .prop_map(|(name, overrides)| CaseTable { name: Some(name), overrides });
    let value = prop_oneof![select(VALUES.to_vec()), select(NUMBERS.to_vec())];
    let bad = (
        option::weighted(0.8, prop_oneof![select(GOOD_NAMES.to_vec()), select(BAD_NAMES.to_vec())]),
        vec((select(OVERRIDES.to_vec()), value), 0..=3),
    )
        .prop_map(|(name, overrides)| CaseTable { name, overrides });
    mostly(good, bad)
}

/// `cases`: a value that is not a list of tables, or `[[sweep.cases]]`.
#[derive(Debug, Clone)]
enum Cases {
    Value(&'static str),
    Tables(Vec<CaseTable>),
}

/// A `[sweep]` table: each key missing or given as TOML text.
#[derive(Debug, Clone)]
struct SweepTable {
    periods: Option<String>,
    damping: Option<String>,
    records: Option<String>,
    histories: Option<String>,
    checkpoint_seconds: Option<&'static str>,
    unknown: bool,
    cases: Option<Cases>,
}

impl SweepTable {
    /// The config: `configs/small.toml` and this table.
    fn config_text(&self) -> String {
        let mut text = format!("{}\n[sweep]\n", small_toml());
        let keys = [
            ("periods", &self.periods),
            ("damping", &self.damping),
            ("records", &self.records),
            ("histories", &self.histories),
        ];
        for (key, value) in keys {
            if let Some(v) = value {
                text += &format!("{key} = {v}\n");
            }
        }
        if let Some(v) = self.checkpoint_seconds {
            text += &format!("checkpoint_seconds = {v}\n");
        }
        if self.unknown {
            text += "nonsense = 1\n";
        }
        match &self.cases {
            None => {}
            Some(Cases::Value(v)) => text += &format!("cases = {v}\n"),
            Some(Cases::Tables(tables)) => {
                for case in tables {
                    text += "\n[[sweep.cases]]\n";
                    if let Some(name) = case.name {
                        text += &format!("name = {name}\n");
                    }
                    for (key, value) in &case.overrides {
                        text += &format!("{key} = {value}\n");
                    }
                }
            }
        }
        text
    }
}

/// Each key mostly missing or usable, else adversarial.
fn sweep_table() -> impl Strategy<Value = SweepTable> {
    let periods = mostly(
        prop_oneof![list(GOOD_PERIODS, 1..=5), good_period_range()].prop_map(Some),
        option::weighted(0.9, prop_oneof![bad_numbers(NUMBERS), period_range()]),
    );
    let damping = mostly(option::of(list(GOOD_DAMPING, 1..=4)), bad_numbers(DAMPING).prop_map(Some));
    let records = mostly(
        option::of(list(GOOD_RECORDS, 1..=2)),
        prop_oneof![
            3 => (list(GOOD_RECORDS, 0..=2), one(BAD_RECORDS))
                .prop_map(|(good, bad)| format!("[{bad}, {}", &good[1..])),
            1 => one(BAD_RECORDS),
        ]
        .prop_map(Some),
    );
    let histories =
        mostly(option::of(list(GOOD_PERIODS, 0..=3)), prop_oneof![bad_numbers(NUMBERS), one(VALUES)].prop_map(Some));
    let checkpoint_seconds =
        mostly(option::of(select(vec!["60", "0.5", "3600"])), select(VALUES.to_vec()).prop_map(Some));
    let cases = mostly(
        option::of(vec(case_table(), 0..=3).prop_map(Cases::Tables)),
        select(VALUES.to_vec()).prop_map(|v| Some(Cases::Value(v))),
    );
    (periods, damping, records, histories, checkpoint_seconds, prop::bool::weighted(0.03), cases).prop_map(
        |(periods, damping, records, histories, checkpoint_seconds, unknown, cases)| SweepTable {
            periods,
            damping,
            records,
            histories,
            checkpoint_seconds,
            unknown,
            cases,
        },
    )
}

/// The invariants of an accepted plan.
fn check_plan(plan: &Plan) -> Result<(), TestCaseError> {
    prop_assert!(!plan.periods.is_empty());
    prop_assert!(plan.periods.iter().all(|t| t.is_finite() && *t > 0.0), "periods {:?}", plan.periods);
    prop_assert!(!plan.damping.is_empty());
    prop_assert!(plan.damping.iter().all(|z| (0.0..1.0).contains(z)), "damping {:?}", plan.damping);
    prop_assert!(!plan.records.is_empty());
    prop_assert!(!plan.cases.is_empty());
    for (i, case) in plan.cases.iter().enumerate() {
        prop_assert!(!case.name.trim().is_empty());
        prop_assert!(plan.cases[..i].iter().all(|c| c.name != case.name), "case {:?} twice", case.name);
    }
    prop_assert!(plan.history_periods.iter().all(|&i| i < plan.periods.len()));
    prop_assert!(plan.checkpoint_seconds.is_finite() && plan.checkpoint_seconds > 0.0);
    let jobs = plan.job_count();
    prop_assert!(jobs > 0);
    for index in [0, jobs / 2, jobs - 1] {
        let job: Job = plan.job(index);
        prop_assert_eq!(plan.index(job), index);
        prop_assert!(!plan.cost(job).is_nan());
    }
    Ok(())
}

proptest! {
    #![proptest_config(fuzz_config())]

    /// `configs/small.toml` with a random `[sweep]` table.
    #[test]
    fn random_sweep_table_never_panics(table in sweep_table()) {
        match Plan::new(&table.config_text(), SOURCE, &configs_dir()) {
            Ok(plan) => check_plan(&plan)?,
            Err(e) => prop_assert!(!e.to_string().trim().is_empty(), "empty error message"),
        }
    }
}

/// `configs/quick.toml`'s sweep on the small config is accepted (else the
/// property tests nothing but errors).
#[test]
fn quick_sweep_is_accepted() {
    let text = format!(
        "{}\n[simulation]\nduration = 10.0\n\n[sweep]\nperiods = {{ from = 0.2, to = 3.0, count = 8, spacing = \
         \"log\" }}\ndamping = [0.02, 0.05]\nhistories = [0.94]\n",
        small_toml()
    );
    let plan = Plan::new(&text, SOURCE, &configs_dir()).expect("the quick sweep");
    assert_eq!(plan.dims(), [1, 1, 2, 8]);
}

/// A period range with a count that could not be allocated (10¹² would need
/// 8 TB; `i64::MAX` overflows the capacity) is an error naming the key.
#[test]
fn huge_period_count_is_an_error() {
    for count in ["1000001", "1000000000000", "9223372036854775807"] {
        let text = format!("{}\n[sweep]\nperiods = {{ from = 0.2, to = 3.0, count = {count} }}\n", small_toml());
        let msg = Plan::new(&text, SOURCE, &configs_dir()).expect_err(count).to_string();
        assert!(msg.contains("sweep.periods"), "{msg}");
    }
}

/// A `center_beams` whose body count `nc + ns + nc * ns` would overflow is
/// refused by the config check, in the base config and in a case.
#[test]
fn huge_center_beam_count_is_refused() {
    let sweep = "[sweep]\nperiods = [1.0]\n";
    let base = small_toml().replace("center_beams = 3", "center_beams = 9223372036854775807");
    let in_case =
        format!("{}\n{sweep}\n[[sweep.cases]]\nname = \"a\"\njoint.center_beams = 9223372036854775807\n", small_toml());
    for text in [format!("{base}\n{sweep}"), in_case] {
        let err = Plan::new(&text, SOURCE, &configs_dir()).expect_err("a huge center_beams").to_string();
        assert!(err.contains("joint.center_beams"), "{err}");
    }
}
