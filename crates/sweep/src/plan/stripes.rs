//! The stripes of a multiple-stripe analysis (`[sweep.stripes]`): every
//! record scaled to every level of an intensity measure, exactly, each
//! scaled copy a record of the sweep.
//!
//! ```toml
//! [sweep.stripes]
//! measure = "sa"       # Sa(T1): pseudo-spectral acceleration w^2 Sd at the bridge's period and damping; or "pga"
//! levels = [0.1, 0.2, 0.4, 0.8]   # [g]; or { from, to, count, spacing }
//! ```
//!
//! The intensity of a record is taken over the runs' window (what the jobs
//! see), as the bridge without the joint is: at a stripe of Sa the bridge
//! alone's `psa` equals the level. The scaled copies are named
//! `<record>@<level>g` and ordered stripe by stripe (all records of the
//! first stripe, then the second's), so that the weak stripes run first.

use quakejoint_model::runspec::Reference;
use quakejoint_model::Config;
use quakejoint_motion::{number, G, MAX_ACCELERATION_G};

use super::grid::range_of;
use super::records::SweepRecord;
use super::{list_of_f64, sweep_err};
use crate::error::SweepError;

/// The keys of the `[sweep.stripes]` table.
pub const STRIPES_KEYS: [&str; 2] = ["measure", "levels"];

/// Factors beyond `[1 / FAR_FACTOR, FAR_FACTOR]` are warned about.
pub const FAR_FACTOR: f64 = 4.0;

/// `n thing(s)`.
fn plural(n: usize, thing: &str) -> String {
    format!("{n} {thing}{}", if n == 1 { "" } else { "s" })
}

/// `x` to four decimals, without trailing zeros (`0.7368`, `2.5`).
fn short(x: f64) -> String {
    let s = format!("{x:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The intensity measure the records are scaled to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Measure {
    /// Pseudo-spectral acceleration `w^2 Sd` of a linear oscillator.
    Sa {
        /// Its period \[s\] (the bridge's).
        period: f64,
        /// Its damping ratio [-] (the bridge's).
        damping: f64,
    },
    /// Peak ground acceleration.
    Pga,
}

impl Measure {
    /// The measure in words: `Sa(1 s, 5 %)` or `PGA`.
    pub fn label(&self) -> String {
        match self {
            Measure::Sa { period, damping } => format!("Sa({} s, {} %)", short(*period), short(100.0 * damping)),
            Measure::Pga => "PGA".to_string(),
        }
    }

    /// The measure's key in a config: `sa` or `pga`.
    pub fn key(&self) -> &'static str {
        match self {
            Measure::Sa { .. } => "sa",
            Measure::Pga => "pga",
        }
    }

    /// The intensity of `record` over the window of a run of `config` \[m/s^2\].
    pub fn of(&self, config: &Config, record: &quakejoint_motion::Record) -> f64 {
        let reference = Reference::for_run(config, record, record);
        match self {
            Measure::Sa { period, damping } => reference
                .spectrum(&[*period], &[*damping])
                .ok()
                .and_then(|rows| rows.first().map(|r| r.peaks.psa))
                .unwrap_or(f64::NAN),
            Measure::Pga => reference.window().pga(),
        }
    }
}

/// One scaled copy of a record: a record of the sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StripeRun {
    /// The record as given (index into [`Stripes::ground`]).
    pub ground: usize,
    /// Its stripe (index into [`Stripes::levels`]).
    pub stripe: usize,
    /// The factor on the record as read [-].
    pub factor: f64,
}

/// The stripes of a sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct Stripes {
    /// The intensity measure.
    pub measure: Measure,
    /// Its levels \[g\], increasing.
    pub levels: Vec<f64>,
    /// The records as given: name and intensity as read \[g\].
    pub ground: Vec<(String, f64)>,
    /// Every record of the sweep, in the sweep's order.
    pub runs: Vec<StripeRun>,
}

/// Reads `[sweep.stripes]` and replaces `records` by their copies scaled
/// to every level. `periods` and `damping` are the sweep's (Sa is taken
/// at the one swept period and damping), `modal`: the bridge is given by
/// its modes (Sa at its longest kept period, with `bridge.damping`).
pub(super) fn stripes_of(
    v: &toml::Value,
    periods: &[f64],
    damping: &[f64],
    records: &mut Vec<SweepRecord>,
    config: &Config,
) -> Result<(Stripes, Vec<String>), SweepError> {
    let toml::Value::Table(t) = v else {
        return Err(sweep_err("sweep.stripes", "must be a table ([sweep.stripes])"));
    };
    super::known_keys(t, "sweep.stripes", &STRIPES_KEYS)?;
    let measure = match t.get("measure").map(|m| m.as_str()) {
        Some(Some("sa")) => match (periods, damping) {
            ([period], [damping]) => Measure::Sa { period: *period, damping: *damping },
            _ => {
                return Err(sweep_err(
                    "sweep.stripes.measure",
                    format!(
                        "\"sa\" is Sa(T1) at the bridge's period and damping: sweep one period and one damping \
                         ratio (this sweep has {} and {}), or scale to \"pga\"",
                        plural(periods.len(), "period"),
                        plural(damping.len(), "damping ratio")
                    ),
                ))
            }
        },
        Some(Some("pga")) => Measure::Pga,
        None => return Err(sweep_err("sweep.stripes.measure", "missing: \"sa\" (Sa(T1)) or \"pga\"")),
        Some(_) => {
            return Err(sweep_err(
                "sweep.stripes.measure",
                format!("{}: expected \"sa\" or \"pga\"", crate::fragility::spec::shown(t.get("measure"))),
            ))
        }
    };
    let levels = levels_of(t.get("levels").ok_or_else(|| sweep_err("sweep.stripes.levels", "missing"))?)?;
    let mut ground = Vec::new();
    let mut runs = Vec::new();
    let mut warnings = Vec::new();
    let limit = MAX_ACCELERATION_G * G;
    let mut scaled = Vec::with_capacity(levels.len() * records.len());
    let mut intensity = Vec::with_capacity(records.len());
    for r in records.iter() {
        let im = measure.of(config, &r.record);
        if !(im.is_finite() && im > 0.0) {
            return Err(sweep_err(
                "sweep.stripes",
                format!(
                    "record {:?}: its {} over the runs' window is {im}: it cannot be scaled",
                    r.record.name,
                    measure.label()
                ),
            ));
        }
        ground.push((r.record.name.clone(), im / G));
        intensity.push(im);
    }
    for (s, &level) in levels.iter().enumerate() {
        for (g, r) in records.iter().enumerate() {
            let factor = level * G / intensity[g];
            let mut copy = r.clone();
            if s > 0 {
                // the record's own warnings (its reading) once, with the first stripe
                copy.warnings.clear();
            }
            let rec = &mut copy.record;
            rec.acceleration.iter_mut().for_each(|a| *a *= factor);
            rec.scale *= factor;
            rec.user_scale *= factor;
            rec.name = format!("{}@{}g", r.record.name, number(level));
            let peak = rec.pga();
            if peak > limit {
                return Err(sweep_err(
                    &format!("sweep.stripes.levels[{s}]"),
                    format!(
                        "record {:?} scaled by {factor:.3} to {} = {} g peaks at {:.2} g, beyond {MAX_ACCELERATION_G} \
                         g: no recorded ground motion is that strong; lower the highest level",
                        r.record.name,
                        measure.label(),
                        number(level),
                        peak / G
                    ),
                ));
            }
            runs.push(StripeRun { ground: g, stripe: s, factor });
            scaled.push(copy);
        }
    }
    for (g, (name, im)) in ground.iter().enumerate() {
        let factors: Vec<f64> = runs.iter().filter(|r| r.ground == g).map(|r| r.factor).collect();
        let (lo, hi) = factors.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &f| (a.min(f), b.max(f)));
        if lo < 1.0 / FAR_FACTOR || hi > FAR_FACTOR {
            warnings.push(format!(
                "stripes: record {name:?} ({} = {:.3} g as read) is scaled by {lo:.3} to {hi:.3}, beyond 1/{FAR_FACTOR} \
                 to {FAR_FACTOR}: a record scaled far from its own intensity may not stand for records of that \
                 intensity (their duration and spectral shape differ)",
                measure.label(),
                im
            ));
        }
    }
    *records = scaled;
    Ok((Stripes { measure, levels, ground, runs }, warnings))
}

/// The levels \[g\]: a list, or `{ from, to, count, spacing }`; positive,
/// increasing.
fn levels_of(v: &toml::Value) -> Result<Vec<f64>, SweepError> {
    let field = "sweep.stripes.levels";
    let levels = match v {
        toml::Value::Table(t) => range_of(t, field, "g")?
            .into_iter()
            // four significant digits: 0.3, not 0.30000000000000004, and
            // 0.07579, not 0.075785828326, in the records' names
            .map(|x| format!("{x:.3e}").parse().unwrap_or(x))
            .collect(),
        other => list_of_f64(other, field)?,
    };
    if levels.len() < 2 {
        return Err(sweep_err(field, "a fragility needs two stripes at least"));
    }
    for (i, &x) in levels.iter().enumerate() {
        if !(x.is_finite() && x > 0.0 && x <= 10.0 * MAX_ACCELERATION_G) {
            return Err(sweep_err(
                &format!("{field}[{i}]"),
                format!("{x}: a level in g, above 0 and at most {}", 10.0 * MAX_ACCELERATION_G),
            ));
        }
        if i > 0 && x <= levels[i - 1] {
            return Err(sweep_err(&format!("{field}[{i}]"), format!("{x}: the levels must increase")));
        }
    }
    Ok(levels)
}
