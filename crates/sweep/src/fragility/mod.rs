//! Fragility of the joint's limit states from a multiple-stripe sweep
//! (`[sweep.stripes]`, `[sweep.fragility]`): each limit state evaluated on
//! every run's results ([`spec`]), counted stripe by stripe and fitted by
//! maximum likelihood with bootstrap intervals and, with a site's hazard
//! curve, its mean annual frequency ([`eval`], on
//! [`quakejoint_model::fragility`]); stored in `/fragility` ([`h5`]); with
//! target frequencies, the choice among the cases as candidate joints
//! ([`design`]).

pub mod design;
pub mod eval;
pub mod h5;
pub mod spec;

pub use eval::{bootstrap_key, evaluate, outcome, Curve, LimitStateResult, Memo, StripeCounts};
pub use h5::{count_arrays, curve_arrays, read_fragility, write_fragility, StoredFragility};
pub use spec::{Failed, FragilitySpec, Kind, LimitState, DECK_MEASURES, FRAGILITY_KEYS, KINDS};

use crate::results::Results;

/// A number of g for a table: three significant digits.
fn g3(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.3}")
    } else {
        "-".to_string()
    }
}

/// A dispersion for a table: two decimals, or in exponent form when huge.
fn b2(x: f64) -> String {
    if x < 100.0 {
        format!("{x:.2}")
    } else {
        format!("{x:.1e}")
    }
}

/// One fitted curve as the summaries list it.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveRow {
    /// The limit state's name (and, when there are several curves, its
    /// case, damping ratio and period).
    pub name: String,
    /// Its key (`/fragility/<key>`).
    pub key: String,
    /// The curve's case, damping ratio and period (indices).
    pub at: [usize; 3],
    /// Median \[g\] and dispersion [-] (NaN without a fit).
    pub median: f64,
    /// Dispersion [-].
    pub beta: f64,
    /// Bootstrap intervals of the median \[g\] and of beta (NaN without).
    pub median_interval: [f64; 2],
    /// Of beta.
    pub beta_interval: [f64; 2],
    /// Mean annual frequency \[1/year\] (NaN without a hazard curve).
    pub annual_frequency: f64,
    /// Its bootstrap interval (NaN without).
    pub annual_frequency_interval: [f64; 2],
    /// Runs that exceeded, and runs that count, per stripe.
    pub exceeded: Vec<u32>,
    /// Runs that count per stripe.
    pub runs: Vec<u32>,
    /// What a user should know about it.
    pub note: String,
}

/// Every curve of `f` on `results` (`label(c, z, t)`: a curve's case,
/// damping ratio and period in words, used when there are several).
pub fn rows(f: &StoredFragility, results: &Results, label: &dyn Fn(usize, usize, usize) -> String) -> Vec<CurveRow> {
    let [nc, _, nz, nt] = results.dims;
    let several = nc * nz * nt > 1;
    let nan = [f64::NAN; 2];
    let mut out = Vec::new();
    for (ls, r) in f.spec.limit_states.iter().zip(f.evaluate(results)) {
        for (i, curve) in r.curves.iter().enumerate() {
            let (c, z, t) = (i / (nz * nt), i / nt % nz, i % nt);
            out.push(CurveRow {
                name: if several { format!("{} [{}]", ls.name, label(c, z, t)) } else { ls.name.clone() },
                key: ls.key.clone(),
                at: [c, z, t],
                median: curve.fit.map_or(f64::NAN, |f| f.median),
                beta: curve.fit.map_or(f64::NAN, |f| f.beta),
                median_interval: curve.intervals.as_ref().map_or(nan, |i| i.median),
                beta_interval: curve.intervals.as_ref().map_or(nan, |i| i.beta),
                annual_frequency: curve.annual_frequency,
                annual_frequency_interval: curve.intervals.as_ref().and_then(|i| i.annual_frequency).unwrap_or(nan),
                exceeded: curve.counts.iter().map(|k| k.exceeded).collect(),
                runs: curve.counts.iter().map(|k| k.runs).collect(),
                note: curve.note.clone(),
            });
        }
    }
    out
}

/// The fitted curves for a terminal, a few lines each within 100
/// columns: the limit state, its median and dispersion with their
/// intervals and, with a hazard curve, the mean annual frequency with its
/// interval and the return period; the exceedances per stripe; the notes
/// of its own. Notes every curve shares are said once, at the end.
pub fn summary(f: &StoredFragility, rows: &[CurveRow]) -> String {
    let mut out = format!(
        "fragility: {} at {} stripes ({} g), {} records each\n  (intervals: {} %, bootstrap over the records)\n",
        f.stripes.measure.label(),
        f.stripes.levels.len(),
        f.stripes.levels.iter().map(|l| quakejoint_motion::number(*l)).collect::<Vec<_>>().join(", "),
        f.stripes.ground.len(),
        (100.0 * f.spec.confidence).round()
    );
    let notes: Vec<Vec<&str>> = rows.iter().map(|r| r.note.split("; ").filter(|n| !n.is_empty()).collect()).collect();
    let shared: Vec<&str> = match notes.first() {
        Some(first) if rows.len() > 1 => {
            first.iter().copied().filter(|n| notes.iter().all(|ns| ns.contains(n))).collect()
        }
        _ => Vec::new(),
    };
    for (row, own) in rows.iter().zip(&notes) {
        out += &format!("  {}\n", row.name);
        let interval = |[lo, hi]: [f64; 2], f: fn(f64) -> String| {
            if lo.is_finite() {
                format!(" ({}-{})", f(lo), f(hi))
            } else {
                String::new()
            }
        };
        // (a limit state without a fit has no annual frequency either)
        let mut fit = if row.median.is_finite() {
            format!(
                "median {} g{}, beta {}{}",
                g3(row.median),
                interval(row.median_interval, g3),
                b2(row.beta),
                interval(row.beta_interval, b2)
            )
        } else {
            "no fit".to_string()
        };
        if f.spec.hazard.is_some() && row.annual_frequency.is_finite() {
            let years = 1.0 / row.annual_frequency;
            let years = if years >= 10.0 { format!("{years:.0}") } else { format!("{years:.2}") };
            fit += &format!(
                "\n      {:.2e} per year{}: once in {years} years",
                row.annual_frequency,
                interval(row.annual_frequency_interval, |x| format!("{x:.1e}"))
            );
        }
        out += &format!("      {fit}\n");
        let counts: Vec<String> = row.exceeded.iter().zip(&row.runs).map(|(e, n)| format!("{e}/{n}")).collect();
        out += &format!("      exceeded / runs per stripe: {}\n", counts.join(" "));
        for n in own.iter().filter(|n| !shared.contains(n)) {
            out += &wrapped(n, 6, 100);
        }
    }
    if !shared.is_empty() {
        out += "  every limit state:\n";
        for n in shared {
            out += &wrapped(n, 6, 100);
        }
    }
    out
}

/// `text` in lines of at most `width` columns (a word longer than a line
/// on its own), each indented by `indent` spaces, the later ones by two
/// more.
fn wrapped(text: &str, indent: usize, width: usize) -> String {
    let mut out = String::new();
    let mut line = " ".repeat(indent);
    let mut empty = true;
    for word in text.split(' ') {
        if !empty && line.chars().count() + 1 + word.chars().count() > width {
            out += &line;
            out.push('\n');
            line = " ".repeat(indent + 2);
            empty = true;
        }
        if !empty {
            line.push(' ');
        }
        line += word;
        empty = false;
    }
    out + &line + "\n"
}
