//! Fragility of the joint's limit states from a multiple-stripe sweep
//! (`[sweep.stripes]`, `[sweep.fragility]`): each limit state evaluated on
//! every run's results ([`spec`]), counted stripe by stripe and fitted by
//! maximum likelihood with bootstrap intervals and, with a site's hazard
//! curve, its mean annual frequency ([`eval`], on
//! [`quakejoint_model::fragility`]); stored in `/fragility` ([`h5`]).

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

/// The fitted curves as a table for a terminal: per limit state (and per
/// case, damping ratio and period when there are several), the median
/// and dispersion with their intervals, with a hazard curve the mean
/// annual frequency and return period, and the exceedances per stripe;
/// each curve's note below it.
pub fn summary(f: &StoredFragility, rows: &[CurveRow]) -> String {
    let mut out = format!(
        "fragility: {} at {} stripes ({} g), {} records each\n",
        f.stripes.measure.label(),
        f.stripes.levels.len(),
        f.stripes.levels.iter().map(|l| quakejoint_motion::number(*l)).collect::<Vec<_>>().join(", "),
        f.stripes.ground.len()
    );
    let hazard = f.spec.hazard.is_some();
    let pct = (100.0 * f.spec.confidence).round();
    out += &format!(
        "  {:<44} {:>26} {:>18}{}  exceeded / runs per stripe\n",
        "limit state",
        format!("median [g] ({pct} % interval)"),
        "beta (interval)",
        if hazard { format!(" {:>26} {:>10}", "per year (interval)", "return [y]") } else { String::new() }
    );
    for row in rows {
        let median = if row.median_interval[0].is_finite() {
            format!("{} ({}-{})", g3(row.median), g3(row.median_interval[0]), g3(row.median_interval[1]))
        } else {
            g3(row.median)
        };
        let beta = if row.beta_interval[0].is_finite() {
            format!("{} ({}-{})", b2(row.beta), b2(row.beta_interval[0]), b2(row.beta_interval[1]))
        } else if row.beta.is_finite() {
            b2(row.beta)
        } else {
            "-".to_string()
        };
        let risk = if hazard && row.annual_frequency.is_finite() {
            let years = 1.0 / row.annual_frequency;
            let years = if years >= 10.0 { format!("{years:.0}") } else { format!("{years:.2}") };
            let [lo, hi] = row.annual_frequency_interval;
            let rate = if lo.is_finite() {
                format!("{:.2e} ({lo:.1e}-{hi:.1e})", row.annual_frequency)
            } else {
                format!("{:.2e}", row.annual_frequency)
            };
            format!(" {rate:>26} {years:>10}")
        } else if hazard {
            format!(" {:>26} {:>10}", "-", "-")
        } else {
            String::new()
        };
        let counts: Vec<String> = row.exceeded.iter().zip(&row.runs).map(|(e, n)| format!("{e}/{n}")).collect();
        out += &format!("  {:<44} {median:>26} {beta:>18}{risk}  {}\n", row.name, counts.join(" "));
        if !row.note.is_empty() {
            out += &format!("      {}\n", row.note);
        }
    }
    out
}
