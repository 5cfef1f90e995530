//! A suite of records scaled to a target spectrum (`[sweep.suite]`): its
//! table read, its records scaled in place and checked against the bound
//! on a record's acceleration, and what its scaling says a user should
//! know.

use quakejoint_model::Config;
use quakejoint_motion::{scale_suite, Record, SuiteRule, SuiteScaling, TargetSpectrum, G, MAX_ACCELERATION_G};

use super::records::SweepRecord;
use super::{list_of_f64, sweep_err};
use crate::error::SweepError;

/// The keys of the `[sweep.suite]` table.
pub const SUITE_KEYS: [&str; 3] = ["target", "range", "rule"];

/// A suite of records scaled to a target spectrum (`[sweep.suite]`).
#[derive(Debug, Clone)]
pub struct Suite {
    /// The target spectrum.
    pub target: TargetSpectrum,
    /// Periods of the fit \[s\].
    pub range: (f64, f64),
    /// What the Eurocode 8 rule does.
    pub rule: SuiteRule,
    /// The factors and the check (the records of the plan are scaled by
    /// them already).
    pub scaling: SuiteScaling,
}

/// Reads `[sweep.suite]`, scales the suite's records to its target (in
/// place) and returns it. The records are fitted over the runs' window
/// (what the jobs see), and each scaled record is checked again against
/// the bound on a record's acceleration.
pub(super) fn suite_of(
    v: &toml::Value,
    periods: &[f64],
    records: &mut [SweepRecord],
    config: &Config,
) -> Result<Suite, SweepError> {
    let toml::Value::Table(t) = v else {
        return Err(sweep_err("sweep.suite", "must be a table ([sweep.suite])"));
    };
    super::known_keys(t, "sweep.suite", &SUITE_KEYS)?;
    let target: TargetSpectrum = t
        .get("target")
        .ok_or_else(|| {
            sweep_err("sweep.suite.target", "missing: the target spectrum (code = \"ec8\", \"asce7\" or \"table\")")
        })?
        .clone()
        .try_into()
        .map_err(|e: toml::de::Error| sweep_err("sweep.suite.target", e.message().to_string()))?;
    target.validate().map_err(|e| sweep_err("sweep.suite", e.to_string()))?;
    let (shortest, longest) = periods.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &p| (a.min(p), b.max(p)));
    let range = match t.get("range") {
        Some(v) => match list_of_f64(v, "sweep.suite.range")?[..] {
            [a, b] => (a, b),
            _ => return Err(sweep_err("sweep.suite.range", "two periods [from, to] in s")),
        },
        // Eurocode 8's 0.2 T1 to 2 T1 around every swept period
        None => ((0.2 * shortest).max(0.01), (2.0 * longest).min(10.0)),
    };
    let rule = match t.get("rule") {
        Some(v) => v.clone().try_into().map_err(|e: toml::de::Error| {
            sweep_err(
                "sweep.suite.rule",
                format!("{} (\"ec8\" scales the suite up to the rule, \"check\" only reports)", e.message()),
            )
        })?,
        None => SuiteRule::Ec8,
    };
    let windows: Vec<Record> = records.iter().map(|r| quakejoint_model::run::run_window(config, &r.record)).collect();
    let refs: Vec<&Record> = windows.iter().collect();
    let scaling = scale_suite(&refs, &target, range, rule).map_err(|e| sweep_err("sweep.suite", e.to_string()))?;
    let limit = MAX_ACCELERATION_G * G;
    for (r, f) in records.iter_mut().zip(&scaling.factors) {
        let rec = &mut r.record;
        rec.acceleration.iter_mut().for_each(|a| *a *= f);
        rec.scale *= f;
        rec.user_scale *= f;
        let peak = rec.pga();
        if peak > limit {
            return Err(sweep_err(
                "sweep.suite",
                format!(
                    "record {:?} scaled by {f:.3} peaks at {:.2} g, beyond {MAX_ACCELERATION_G} g: no recorded ground \
                     motion is that strong; leave the record out of the suite or choose a weaker target",
                    rec.name,
                    peak / G
                ),
            ));
        }
    }
    Ok(Suite { target, range, rule, scaling })
}

/// What the suite's scaling says a user should know.
pub(super) fn suite_warnings(suite: &Suite) -> Vec<String> {
    let s = &suite.scaling;
    let mut out: Vec<String> = s.warnings.iter().map(|w| format!("suite: {w}")).collect();
    if !s.ec8_satisfied {
        out.push(format!(
            "suite: the mean of the scaled records is {:.1} % of the target at T = {:.3} s, below the 90 % of \
             Eurocode 8 (rule = \"check\" reports it; rule = \"ec8\" scales the suite up)",
            100.0 * s.min_ratio.0,
            s.min_ratio.1
        ));
    }
    out
}
