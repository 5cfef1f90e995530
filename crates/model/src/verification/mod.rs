//! The verification manual's problems: each reference problem with its
//! independent solution (a closed form, a published value, a conservation
//! law or a second method), the quantity compared, the acceptance band and
//! the command that reproduces it ([`PROBLEMS`]). The tests run every one
//! against its band (`crates/model/tests/verification.rs`), the benchmark
//! times them (`cargo bench -p quakejoint-model --bench verification`), and
//! `docs/verification.md` is made from them and their results (a test keeps
//! it current).

pub mod modal;
mod problems;
mod programs;

use std::path::Path;

/// How a problem's error is measured against its band.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Band {
    /// |computed - reference| / |reference| at most this.
    Relative(f64),
    /// |computed - reference| at most this, in the problem's units.
    Absolute(f64),
}

impl Band {
    /// The error of `computed` against `reference` as this band measures it.
    pub fn error(self, computed: f64, reference: f64) -> f64 {
        match self {
            Band::Relative(_) => (computed - reference).abs() / reference.abs(),
            Band::Absolute(_) => (computed - reference).abs(),
        }
    }

    /// The largest error accepted.
    pub fn limit(self) -> f64 {
        match self {
            Band::Relative(x) | Band::Absolute(x) => x,
        }
    }

    /// In words: `relative 1e-6`, `absolute 1e-9`.
    pub fn describe(self) -> String {
        match self {
            Band::Relative(x) => format!("relative {x:e}"),
            Band::Absolute(x) => format!("absolute {x:e}"),
        }
    }
}

/// What a problem computed, and what its independent solution says.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outcome {
    /// The tool's value.
    pub computed: f64,
    /// The independent solution's value.
    pub reference: f64,
}

/// A reference problem.
#[derive(Debug, Clone, Copy)]
pub struct Problem {
    /// Short name (`pendulum-period`), used to run it alone.
    pub id: &'static str,
    /// The layer it checks: `solver`, `motion` (records and spectra) or
    /// `model` (the joint).
    pub layer: &'static str,
    /// The problem, in words.
    pub title: &'static str,
    /// The independent solution and where it comes from.
    pub source: &'static str,
    /// The quantity compared, with its units.
    pub quantity: &'static str,
    /// The acceptance band.
    pub band: Band,
    /// Runs it; `root` is the repository (configs and records).
    pub run: fn(&Path) -> Result<Outcome, String>,
}

impl Problem {
    /// The command that runs it alone and prints its outcome.
    pub fn command(&self) -> String {
        format!("cargo run --release -p quakejoint-model --example verify -- {}", self.id)
    }
}

pub use problems::PROBLEMS;

/// The problem named `id`.
pub fn problem(id: &str) -> Option<&'static Problem> {
    PROBLEMS.iter().find(|p| p.id == id)
}

/// A number for the manual: 7 significant digits, or exponent form.
fn shown(x: f64) -> String {
    if x == 0.0 || (1e-3..1e6).contains(&x.abs()) {
        format!("{:.7}", x).trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{x:.6e}")
    }
}

/// Text for a markdown table cell: its `|` escaped.
fn cell(text: &str) -> String {
    text.replace('|', "\\|")
}

/// The table of `docs/verification.md`: one row per problem with its
/// outcome (`outcomes[i]` of `PROBLEMS[i]`).
pub fn manual_table(outcomes: &[Result<Outcome, String>]) -> String {
    let mut t = String::from(
        "| problem | layer | independent solution | quantity | acceptance | computed | reference | error | reproduce |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for (p, o) in PROBLEMS.iter().zip(outcomes) {
        let (computed, reference, error) = match o {
            Ok(o) => (shown(o.computed), shown(o.reference), format!("{:.1e}", p.band.error(o.computed, o.reference))),
            Err(e) => (format!("failed: {e}"), String::new(), String::new()),
        };
        t += &format!(
            "| `{}`: {} | {} | {} | {} | {} | {computed} | {reference} | {error} | `{}` |\n",
            p.id,
            cell(p.title),
            p.layer,
            cell(p.source),
            cell(p.quantity),
            p.band.describe(),
            p.command()
        );
    }
    t
}

/// The fastest of `repeats` runs of `config` under its record (read
/// against `base_dir`): the wall-clock time \[s\] and that run's result
/// (the benchmarks' measure).
pub fn fastest_run(
    base_dir: &Path,
    config: &crate::Config,
    repeats: usize,
) -> Result<(f64, crate::run::RunResult), String> {
    let (x, _) = crate::run::load_records(config, base_dir).map_err(|e| e.to_string())?;
    let mut best = (f64::INFINITY, crate::run::RunResult::default());
    for _ in 0..repeats {
        let start = std::time::Instant::now();
        let r = crate::run::simulate_records(config, &x.record, None, &crate::run::RunOptions::default())
            .map_err(|e| e.to_string())?;
        let t = start.elapsed().as_secs_f64();
        if t < best.0 {
            best = (t, r);
        }
    }
    Ok(best)
}
