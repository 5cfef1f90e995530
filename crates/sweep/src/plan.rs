//! What a sweep computes: the `[sweep]` table of a config, its cases, the
//! records and the job list.
//!
//! ```toml
//! [sweep]
//! periods = { from = 0.1, to = 5.0, count = 50, spacing = "log" }  # or a list
//! damping = [0.05]
//! records = [{ file = "../ground_motions/RSN753_LOMAP_CLS090-hor2.AT2" }]  # default: [record]
//! histories = [1.0]          # time histories of the nearest swept periods
//! checkpoint_seconds = 60.0  # HDF5 checkpoint interval
//!
//! [[sweep.cases]]            # optional: parameter sets that differ from the base
//! name = "preload 40 kN"
//! joint.friction.normal_force = 40e3
//! ```
//!
//! A case overrides any `joint`, `bridge` or `simulation` parameter except
//! the swept ones (`bridge.w0`, `bridge.period`, `bridge.damping`); the
//! overrides are merged into the base config and checked like it, so an
//! unknown key or a bad value is an error naming the case and the key.
//!
//! A bridge given by its modes (`[bridge.modal]`) is swept by a factor on
//! every period of its modes instead ([`ModalSweep`]):
//!
//! ```toml
//! [sweep]
//! period_scales = [0.8, 1.0, 1.25]   # or { from, to, count, spacing }; default [1.0]
//! ```
//!
//! Its damping is the modes file's (or `bridge.damping`), one value, so
//! `sweep.periods` and `sweep.damping` are refused; a case may change
//! `bridge.modal.modes_used` or `joint_point` but not the modes file, the
//! period scale or `bridge.damping`.

use std::path::{Path, PathBuf};

use quakejoint_model::config::ModalConfig;
use quakejoint_model::runspec::{Named, Overrides, RunSpec};
use quakejoint_model::{Config, ModelError};
use quakejoint_motion::sha256_hex;
use quakejoint_motion::{
    load_record, period_range, scale_suite, Record, RecordSpec, SuiteRule, SuiteScaling, TargetSpectrum, G,
    MAX_ACCELERATION_G,
};

use crate::error::SweepError;

/// The keys of the `[sweep]` table.
pub const SWEEP_KEYS: [&str; 8] =
    ["periods", "period_scales", "damping", "records", "cases", "histories", "checkpoint_seconds", "suite"];

/// Longest interval between checkpoints or progress lines \[s\] (116 days;
/// the longest run allowed, `simulation.max_wall_time`, is as long).
pub const MAX_INTERVAL: f64 = 1e7;

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

/// One named parameter set.
#[derive(Debug, Clone)]
pub struct Case {
    /// Name, unique within the sweep.
    pub name: String,
    /// The full config of this case.
    pub config: Config,
    /// Number of joint bodies (for the cost estimate).
    pub bodies: usize,
}

/// A record of the sweep.
#[derive(Debug, Clone)]
pub struct SweepRecord {
    /// How it was specified.
    pub spec: RecordSpec,
    /// The record (m/s^2).
    pub record: Record,
    /// SHA-256 of the file's bytes (hex).
    pub sha256: String,
    /// Warnings from reading it.
    pub warnings: Vec<String>,
    /// The file it was read from (resolved against the config's folder).
    pub path: PathBuf,
}

impl SweepRecord {
    /// Reads a record and hashes its file.
    pub fn load(spec: RecordSpec, base_dir: &Path) -> Result<Self, SweepError> {
        let loaded = load_record(&spec, base_dir)?;
        let path = spec.resolve_path(base_dir);
        Ok(Self { sha256: loaded.sha256, record: loaded.record, warnings: loaded.warnings, spec, path })
    }
}

/// What a sweep over a bridge given by its modes (`[bridge.modal]`) adds
/// to its plan: the swept factors on the modes' periods, the modes file
/// and the joints after the first.
#[derive(Debug, Clone)]
pub struct ModalSweep {
    /// The swept factors on every period of the modes [-]
    /// (`sweep.period_scales`; each job's `bridge.modal.period_scale`).
    pub period_scales: Vec<f64>,
    /// Whether they are `sweep.period_scales` (else the config's own
    /// `bridge.modal.period_scale`, 1 by default: one job per record and
    /// case, each the config's run as it stands).
    pub swept: bool,
    /// The modes file as the config names it (`bridge.modal.modes`).
    pub file: String,
    /// The modes file, resolved against the config's folder.
    pub path: PathBuf,
    /// SHA-256 of its bytes (hex), part of the config's hash: a changed
    /// modes file is another sweep.
    pub sha256: String,
    /// The names of the joints after the first of `[[joints]]` (their
    /// values are stored per joint).
    pub joints: Vec<String>,
}

impl ModalSweep {
    /// The override of the jobs at period scale `t` (an index), named as
    /// the sweep names it (none when the scale is the config's own).
    pub fn overrides(&self, t: usize) -> Overrides {
        Overrides {
            period_scale: self.swept.then(|| Named::new(self.period_scales[t], format!("sweep.period_scales[{t}]"))),
            ..Overrides::default()
        }
    }
}

/// The bridge alone at the first joint's deck point of a config with a
/// bridge given by its modes (as its period scale sets them), under
/// `window` (the ground motion over the run's window): the exact modal
/// superposition ([`quakejoint_model::linear::modal_response`]), as
/// `quakejoint simulate --no-joint` gives it.
pub fn modal_alone(config: &Config, window: &Record) -> Result<quakejoint_model::run::RunResult, ModelError> {
    let Some(m) = &config.bridge.modal else {
        return Err(ModelError::Invalid {
            field: "bridge.modal".into(),
            value: "none".into(),
            reason: "the bridge is not given by its modes".into(),
        });
    };
    let kept = quakejoint_model::modal::kept_modes(m, config.bridge.damping)?;
    let point = quakejoint_model::placement::places(config)?[0].deck_point;
    Ok(quakejoint_model::linear::modal_response(window, &kept, point, false))
}

/// Everything a sweep computes.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Cases (at least one: "base").
    pub cases: Vec<Case>,
    /// Records (each acts along the bridge axis, x).
    pub records: Vec<SweepRecord>,
    /// The config's transverse record (`[record_y]`), applied in every job.
    pub record_y: Option<SweepRecord>,
    /// The suite's target and scaling, when the records are a suite
    /// (`[sweep.suite]`).
    pub suite: Option<Suite>,
    /// Damping ratios [-] (a bridge given by its modes: one,
    /// `bridge.damping`, the damping of the modes the file gives none for).
    pub damping: Vec<f64>,
    /// Bridge periods \[s\] (a bridge given by its modes: its longest kept
    /// period at each of `modal.period_scales`, which are the swept axis).
    pub periods: Vec<f64>,
    /// A bridge given by its modes: the swept period scales, the modes
    /// file and the joints after the first.
    pub modal: Option<ModalSweep>,
    /// Indices into `periods` whose histories are stored.
    pub history_periods: Vec<usize>,
    /// Seconds between HDF5 checkpoints.
    pub checkpoint_seconds: f64,
    /// The config as used: every default filled in, the `[sweep]` table
    /// as given (TOML).
    pub config_used: String,
    /// What a user should know about the sweep before reading its results
    /// (a run window shorter than a record, say); kept in the output.
    pub warnings: Vec<String>,
    /// The config file's text.
    pub config_text: String,
    /// SHA-256 of the parsed config (independent of comments and layout).
    pub config_sha256: String,
}

/// A job: one coupled run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Job {
    /// Case index.
    pub case: usize,
    /// Record index.
    pub record: usize,
    /// Damping index.
    pub damping: usize,
    /// Period index.
    pub period: usize,
}

fn sweep_err(field: &str, message: impl Into<String>) -> SweepError {
    SweepError::Config { field: field.to_string(), message: message.into() }
}

fn f64_of(v: &toml::Value, field: &str) -> Result<f64, SweepError> {
    match v {
        toml::Value::Float(x) => Ok(*x),
        toml::Value::Integer(i) => Ok(*i as f64),
        other => Err(sweep_err(field, format!("expected a number, found {other}"))),
    }
}

fn list_of_f64(v: &toml::Value, field: &str) -> Result<Vec<f64>, SweepError> {
    match v {
        toml::Value::Array(items) => items.iter().map(|x| f64_of(x, field)).collect(),
        other => Ok(vec![f64_of(other, field)?]),
    }
}

/// The key of a case's `[bridge]` table `b` that a case may not change,
/// and why (`modal`: the sweep's bridge is given by its modes).
fn refused_in_case(b: &toml::Table, modal: bool) -> Option<(String, &'static str)> {
    let modal_table = b.get("modal").and_then(|m| m.as_table());
    if !modal {
        if b.contains_key("modal") {
            return Some((
                "modal".into(),
                "the sweep's bridge is a single-DOF deck; a case cannot give it modes (a sweep of a bridge given by \
                 its modes has [bridge.modal] in its base config)",
            ));
        }
        return ["w0", "period", "damping"]
            .into_iter()
            .find(|k| b.contains_key(*k))
            .map(|k| (k.to_string(), "the bridge period and damping are swept, not set per case"));
    }
    for k in ["w0", "period"] {
        if b.contains_key(k) {
            return Some((
                k.into(),
                "the bridge is given by its modes: its periods are the modes file's times sweep.period_scales",
            ));
        }
    }
    if b.contains_key("damping") {
        return Some((
            "damping".into(),
            "the modes' damping (the modes file's, or bridge.damping) is the sweep's damping axis, shared by its \
             cases: run one sweep per bridge.damping",
        ));
    }
    match modal_table {
        Some(m) if m.contains_key("modes") => Some((
            "modal.modes".into(),
            "the modes file is the sweep's bridge, shared by its cases (a case may keep fewer or more of its modes: \
             bridge.modal.modes_used)",
        )),
        Some(m) if m.contains_key("period_scale") => {
            Some(("modal.period_scale".into(), "the period scale is swept (sweep.period_scales), not set per case"))
        }
        _ => None,
    }
}

/// A swept axis: a list, or `{ from, to, count, spacing }` (`field`, in
/// `unit`), each value checked against the range of the config key `key`
/// it overrides, each once.
fn grid_of(v: &toml::Value, field: &str, key: &str, unit: &str) -> Result<Vec<f64>, SweepError> {
    let values = match v {
        toml::Value::Table(t) => {
            for key in t.keys() {
                if !["from", "to", "count", "spacing"].contains(&key.as_str()) {
                    return Err(sweep_err(
                        &format!("{field}.{key}"),
                        "unknown key (expected from, to, count, spacing)",
                    ));
                }
            }
            let get = |k: &str| t.get(k).ok_or_else(|| sweep_err(&format!("{field}.{k}"), "missing"));
            let from = f64_of(get("from")?, &format!("{field}.from"))?;
            let to = f64_of(get("to")?, &format!("{field}.to"))?;
            let count = match get("count")? {
                toml::Value::Integer(n) if *n >= 1 => *n as usize,
                other => {
                    return Err(sweep_err(&format!("{field}.count"), format!("{other}: must be a whole number >= 1")))
                }
            };
            let log = match t.get("spacing").map(|s| s.as_str()) {
                None | Some(Some("log")) => true,
                Some(Some("linear")) => false,
                Some(other) => {
                    return Err(sweep_err(
                        &format!("{field}.spacing"),
                        format!("{other:?}: expected \"log\" or \"linear\""),
                    ))
                }
            };
            period_range(from, to, count, log).map_err(|e| match e {
                // (the range's words are about periods in s)
                quakejoint_motion::SpectrumError::Range(m) if unit != "s" => {
                    sweep_err(field, format!("range: {}", m.replace(" s", "").replace("periods", "values")))
                }
                other => sweep_err(field, other.to_string()),
            })?
        }
        other => list_of_f64(other, field)?,
    };
    if values.is_empty() {
        return Err(sweep_err(field, if unit == "s" { "no periods" } else { "no values" }));
    }
    check_swept(&values, field, key)?;
    Ok(values)
}

/// The swept axis of a bridge given by its modes (`sweep.period_scales`,
/// default the config's `bridge.modal.period_scale`, 1) and what the sweep
/// keeps of its modes file; `sweep.periods` and `sweep.damping` are
/// refused.
fn modal_axis(
    sweep: &toml::Table,
    m: &ModalConfig,
    config: &Config,
    base_dir: &Path,
) -> Result<ModalSweep, SweepError> {
    if sweep.contains_key("periods") {
        return Err(sweep_err(
            "sweep.periods",
            "the bridge is given by its modes ([bridge.modal]): sweep its periods with sweep.period_scales, a \
             factor on every period of the modes (period_scales = [0.8, 1.0, 1.25], or { from, to, count, spacing })",
        ));
    }
    if sweep.contains_key("damping") {
        return Err(sweep_err(
            "sweep.damping",
            "the bridge is given by its modes ([bridge.modal]): their damping ratios are the modes file's, or \
             bridge.damping where it gives none, and are not swept; sweep the periods with sweep.period_scales (and \
             run one sweep per bridge.damping to study the damping)",
        ));
    }
    let swept = sweep.contains_key("period_scales");
    let period_scales = match sweep.get("period_scales") {
        Some(v) => {
            if let Some(f) = m.period_scale {
                return Err(sweep_err(
                    "bridge.modal.period_scale",
                    format!(
                        "{}: the sweep sets every job's period scale (sweep.period_scales); remove \
                         bridge.modal.period_scale, or sweep.period_scales to run the config's scale alone",
                        quakejoint_motion::number(f)
                    ),
                ));
            }
            grid_of(v, "sweep.period_scales", "bridge.modal.period_scale", "1")?
        }
        None => vec![m.scale()],
    };
    Ok(ModalSweep {
        period_scales,
        swept,
        file: m.modes.clone(),
        path: base_dir.join(&m.modes),
        sha256: quakejoint_model::modal::loaded(m)?.sha256.clone(),
        joints: config.joints.iter().skip(1).map(|j| j.name.clone()).collect(),
    })
}

/// Checks swept values (`field`, a list) against the range of the config
/// key `key` they stand for (as an override of it), each once.
fn check_swept(values: &[f64], field: &str, key: &str) -> Result<(), SweepError> {
    for (i, &x) in values.iter().enumerate() {
        // as every front end's override of the key is checked, in the same words
        quakejoint_model::runspec::check_override(key, &format!("{field}[{i}]"), x)?;
        if let Some(k) = values[..i].iter().position(|&y| y == x) {
            return Err(sweep_err(
                &format!("{field}[{i}]"),
                format!("{x} is already {field}[{k}]: each is swept once"),
            ));
        }
    }
    Ok(())
}

/// Reads `[sweep.suite]`, scales the suite's records to its target (in
/// place) and returns it. The records are fitted over the runs' window
/// (what the jobs see), and each scaled record is checked again against
/// the bound on a record's acceleration.
fn suite_of(
    v: &toml::Value,
    periods: &[f64],
    records: &mut [SweepRecord],
    config: &Config,
) -> Result<Suite, SweepError> {
    let toml::Value::Table(t) = v else {
        return Err(sweep_err("sweep.suite", "must be a table ([sweep.suite])"));
    };
    for key in t.keys() {
        if !SUITE_KEYS.contains(&key.as_str()) {
            return Err(sweep_err(
                &format!("sweep.suite.{key}"),
                format!("unknown key (expected {})", SUITE_KEYS.join(", ")),
            ));
        }
    }
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
fn suite_warnings(suite: &Suite) -> Vec<String> {
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

/// A warning when the run window ([`quakejoint_model::run::run_window`])
/// cuts `record` short: both spectra cover the window only, and how much
/// the spectrum without the joint over the whole record is larger says how
/// much of the record's effect the window leaves out (a bridge given by its
/// modes, `modal`: the bridge alone at the first joint's point at each
/// period scale).
fn window_warning(
    config: &Config,
    record: &Record,
    periods: &[f64],
    damping: &[f64],
    modal: Option<&ModalSweep>,
) -> Option<String> {
    use quakejoint_motion::{spectrum, SpectrumOptions};
    let window = quakejoint_model::run::run_window(config, record);
    if window.acceleration.len() >= record.acceleration.len() {
        return None;
    }
    let (whole, cut, labels): (Vec<f64>, Vec<f64>, Vec<String>) = match modal {
        None => {
            let sa = |r: &Record| -> Vec<f64> {
                spectrum(r, periods, damping, SpectrumOptions::default())
                    .map(|rows| rows.iter().map(|row| row.peaks.sa).collect())
                    .unwrap_or_default()
            };
            let labels = (0..periods.len() * damping.len())
                .map(|i| format!("T = {:.4} s, damping {}", periods[i % periods.len()], damping[i / periods.len()]))
                .collect();
            (sa(record), sa(&window), labels)
        }
        Some(m) => {
            let at = |t: usize, r: &Record| {
                RunSpec::new(config.clone(), &m.overrides(t))
                    .and_then(|spec| modal_alone(&spec.config, r))
                    .map_or(f64::NAN, |alone| alone.sa)
            };
            let n = m.period_scales.len();
            let labels = (0..n)
                .map(|t| format!("period scale {}, longest period {:.4} s", m.period_scales[t], periods[t]))
                .collect();
            ((0..n).map(|t| at(t, record)).collect(), (0..n).map(|t| at(t, &window)).collect(), labels)
        }
    };
    let worst = whole
        .iter()
        .zip(&cut)
        .enumerate()
        .map(|(i, (w, c))| (i, if *c > 0.0 { w / c - 1.0 } else { 0.0 }))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    let missed = match worst {
        Some((i, excess)) if excess > 1e-3 => format!(
            "; over the whole record the bridge without the joint would respond up to {:.1} % more ({})",
            100.0 * excess,
            labels[i]
        ),
        _ => "; the record's remainder changes no peak of the spectrum without the joint".to_string(),
    };
    Some(format!(
        "record {}: the runs cover its first {} s of {} s (simulation.duration); both spectra, with and without \
          the joint, are taken over that window{missed}",
        record.name,
        quakejoint_motion::number(window.duration()),
        quakejoint_motion::number(record.duration())
    ))
}

/// Recursively merges `over` into `base` (tables merge, other values replace).
fn merge(base: &mut toml::Table, over: &toml::Table) {
    for (k, v) in over {
        match (base.get_mut(k), v) {
            (Some(toml::Value::Table(b)), toml::Value::Table(o)) => merge(b, o),
            _ => {
                base.insert(k.clone(), v.clone());
            }
        }
    }
}

/// Settings that change no finished result are left out of the config's
/// hash: the per-job limits `simulation.max_wall_time` and
/// `simulation.max_steps` (a job either ends within them with the same
/// numbers or is recorded as stopped) and `sweep.checkpoint_seconds`. So a
/// sweep can be continued, and its stopped jobs retried, with raised limits.
/// `table` is the config or its `[sweep]` table (whose cases may set the
/// limits too).
fn without_run_settings(table: &toml::Table) -> toml::Table {
    fn strip(t: &mut toml::Table) {
        if let Some(toml::Value::Table(sim)) = t.get_mut("simulation") {
            sim.remove("max_wall_time");
            sim.remove("max_steps");
            if sim.is_empty() {
                t.remove("simulation");
            }
        }
    }
    let mut t = table.clone();
    strip(&mut t);
    t.remove("checkpoint_seconds");
    if let Some(toml::Value::Array(cases)) = t.get_mut("cases") {
        for case in cases {
            if let toml::Value::Table(c) = case {
                strip(c);
            }
        }
    }
    t
}

impl Plan {
    /// Reads the sweep of a config file (`source` names it in messages;
    /// record paths are resolved against `base_dir`).
    pub fn new(config_text: &str, source: &str, base_dir: &Path) -> Result<Self, SweepError> {
        let mut base_config = Config::from_toml(config_text, source)?;
        // the modes file, read once: every case shares it
        base_config.load_modes(base_dir)?;
        let mut table: toml::Table = toml::from_str(config_text)
            .map_err(|e| SweepError::from(quakejoint_model::config::parse_error(source, &e)))?;
        let sweep = match table.remove("sweep") {
            Some(toml::Value::Table(t)) => t,
            Some(_) => return Err(sweep_err("sweep", "must be a table")),
            None => return Err(sweep_err("sweep", format!("{source} has no [sweep] table"))),
        };
        for key in sweep.keys() {
            if !SWEEP_KEYS.contains(&key.as_str()) {
                return Err(sweep_err(
                    &format!("sweep.{key}"),
                    format!("unknown key (expected {})", SWEEP_KEYS.join(", ")),
                ));
            }
        }
        let (periods, damping, modal) = match &base_config.bridge.modal {
            Some(m) => {
                let modal = modal_axis(&sweep, m, &base_config, base_dir)?;
                // each scale applied and checked as every job applies it:
                // the bridge's longest kept period there
                let periods = (0..modal.period_scales.len())
                    .map(|t| RunSpec::new(base_config.clone(), &modal.overrides(t)).map(|spec| spec.period))
                    .collect::<Result<Vec<f64>, ModelError>>()?;
                (periods, vec![base_config.bridge.damping], Some(modal))
            }
            None => {
                if sweep.contains_key("period_scales") {
                    return Err(sweep_err(
                        "sweep.period_scales",
                        "a factor on the periods of a bridge given by its modes ([bridge.modal]); this bridge is a \
                         single-DOF deck: sweep its period with sweep.periods",
                    ));
                }
                let periods = grid_of(
                    sweep.get("periods").ok_or_else(|| sweep_err("sweep.periods", "missing"))?,
                    "sweep.periods",
                    "bridge.period",
                    "s",
                )?;
                let damping = match sweep.get("damping") {
                    Some(v) => list_of_f64(v, "sweep.damping")?,
                    None => vec![base_config.bridge.damping],
                };
                if damping.is_empty() {
                    return Err(sweep_err("sweep.damping", "no damping ratio"));
                }
                check_swept(&damping, "sweep.damping", "bridge.damping")?;
                (periods, damping, None)
            }
        };
        // each requested period (a modal bridge: period scale) picks the
        // nearest swept one (within 5 %)
        let (axis, unit) = match &modal {
            Some(m) => (&m.period_scales, ""),
            None => (&periods, " s"),
        };
        let what = if modal.is_some() { "period scale" } else { "period" };
        let history_periods = match sweep.get("histories") {
            Some(v) => {
                let mut idx = Vec::new();
                for t in list_of_f64(v, "sweep.histories")? {
                    let (i, p) = axis
                        .iter()
                        .enumerate()
                        .min_by(|a, b| (a.1 - t).abs().total_cmp(&(b.1 - t).abs()))
                        .expect("periods not empty");
                    // NaN fails the comparison and is refused too
                    if (p - t).abs().partial_cmp(&(0.05 * t.abs())) != Some(std::cmp::Ordering::Less) {
                        return Err(sweep_err(
                            "sweep.histories",
                            format!("{t}{unit}: no swept {what} within 5 % (nearest {p}{unit})"),
                        ));
                    }
                    if !idx.contains(&i) {
                        idx.push(i);
                    }
                }
                idx
            }
            None => Vec::new(),
        };
        let checkpoint_seconds = match sweep.get("checkpoint_seconds") {
            Some(v) => f64_of(v, "sweep.checkpoint_seconds")?,
            None => 60.0,
        };
        if !(checkpoint_seconds.is_finite() && checkpoint_seconds > 0.0 && checkpoint_seconds <= MAX_INTERVAL) {
            return Err(sweep_err(
                "sweep.checkpoint_seconds",
                format!("{checkpoint_seconds}: seconds between checkpoints, above 0 and at most {MAX_INTERVAL:e}"),
            ));
        }
        // records
        let specs: Vec<RecordSpec> = match sweep.get("records") {
            Some(toml::Value::Array(items)) => items
                .iter()
                .enumerate()
                .map(|(i, v)| {
                    v.clone()
                        .try_into()
                        .map_err(|e: toml::de::Error| sweep_err(&format!("sweep.records[{i}]"), e.to_string()))
                })
                .collect::<Result<_, _>>()?,
            Some(_) => return Err(sweep_err("sweep.records", "must be a list of tables")),
            None => vec![base_config.record_x()],
        };
        if let (Some(_), Some(r)) = (sweep.get("records"), &base_config.record) {
            // [record]'s settings (its scale, say) would silently not apply
            return Err(sweep_err(
                "sweep.records",
                format!(
                    "the config has both [record] ({}) and sweep.records: a sweep runs the records of sweep.records \
                      only, with their own settings; remove [record], or list it in sweep.records",
                    r.file.display()
                ),
            ));
        }
        if specs.is_empty() {
            return Err(sweep_err("sweep.records", "the list of records is empty"));
        }
        if let (true, Some(y)) = (sweep.contains_key("suite"), &base_config.record_y) {
            return Err(sweep_err(
                "sweep.suite",
                format!(
                    "the suite scales its records along the bridge to the target; [record_y] ({}) would stay \
                     unscaled: remove it (suites of transverse records are not supported)",
                    y.file.display()
                ),
            ));
        }
        if sweep.contains_key("suite") {
            for (i, spec) in specs.iter().enumerate() {
                if spec.scale != 1.0 || spec.target_pga_g.is_some() {
                    return Err(sweep_err(
                        &format!("sweep.records[{i}]"),
                        format!(
                            "{}: the suite scales its records to the target; remove `scale` and `target_pga_g`",
                            spec.file.display()
                        ),
                    ));
                }
            }
        }
        let mut records = specs.into_iter().map(|s| SweepRecord::load(s, base_dir)).collect::<Result<Vec<_>, _>>()?;
        let suite = match sweep.get("suite") {
            Some(v) => {
                // a bridge given by its modes: the fit's default range is
                // about its longest kept period at scale 1, the modes file's
                // longest period
                let around = match &base_config.bridge.modal {
                    Some(m) => {
                        vec![quakejoint_model::modal::loaded(m)?.modes.iter().map(|m| m.period).fold(0.0, f64::max)]
                    }
                    None => periods.clone(),
                };
                Some(suite_of(v, &around, &mut records, &base_config)?)
            }
            None => None,
        };
        let record_y = base_config.record_y.clone().map(|s| SweepRecord::load(s, base_dir)).transpose()?;
        for (i, r) in records.iter().enumerate() {
            if records[..i].iter().any(|o| o.record.name == r.record.name) {
                return Err(sweep_err(
                    "sweep.records",
                    format!("two records are named {:?}; give one a `name`", r.record.name),
                ));
            }
        }
        // cases
        let case_tables: Vec<toml::Table> = match sweep.get("cases") {
            Some(toml::Value::Array(items)) => items
                .iter()
                .enumerate()
                .map(|(i, v)| match v {
                    toml::Value::Table(t) => Ok(t.clone()),
                    _ => Err(sweep_err(&format!("sweep.cases[{i}]"), "must be a table")),
                })
                .collect::<Result<_, _>>()?,
            Some(_) => return Err(sweep_err("sweep.cases", "must be a list of tables ([[sweep.cases]])")),
            None => Vec::new(),
        };
        let mut cases = Vec::new();
        if case_tables.is_empty() {
            cases.push(Case { name: "base".to_string(), bodies: bodies_of(&base_config), config: base_config.clone() });
        }
        for (i, mut ct) in case_tables.into_iter().enumerate() {
            let key = format!("sweep.cases[{i}]");
            let name = match ct.remove("name") {
                Some(toml::Value::String(s)) if !s.trim().is_empty() => s,
                _ => return Err(sweep_err(&format!("{key}.name"), "every case needs a non-empty name")),
            };
            if cases.iter().any(|c: &Case| c.name == name) {
                return Err(sweep_err(&format!("{key}.name"), format!("{name:?} is used twice")));
            }
            for k in ct.keys() {
                if !["joint", "bridge", "simulation"].contains(&k.as_str()) {
                    return Err(sweep_err(
                        &format!("{key}.{k}"),
                        format!("case {name:?}: a case may change joint, bridge and simulation parameters only"),
                    ));
                }
            }
            if let Some(toml::Value::Table(b)) = ct.get("bridge") {
                if let Some(why) = refused_in_case(b, modal.is_some()) {
                    return Err(sweep_err(&format!("{key}.bridge.{}", why.0), format!("case {name:?}: {}", why.1)));
                }
            }
            let mut merged = table.clone();
            merge(&mut merged, &ct);
            let mut config: Config = toml::Value::Table(merged)
                .try_into()
                .map_err(|e: toml::de::Error| sweep_err(&key, format!("case {name:?}: {}", e.message())))?;
            config.validate().map_err(|e| sweep_err(&key, format!("case {name:?}: {e}")))?;
            // the modes file the base config read (a case cannot change it)
            if let Some(bridge) = base_config.bridge.modal.as_ref().and_then(|m| m.loaded.clone()) {
                config.attach_modes(bridge).map_err(|e| sweep_err(&key, format!("case {name:?}: {e}")))?;
            }
            let (a, b) = (&config.simulation, &base_config.simulation);
            if (a.duration, a.extra_time) != (b.duration, b.extra_time) {
                return Err(sweep_err(
                    &format!("{key}.simulation"),
                    format!(
                        "case {name:?}: the cases of a sweep share its run window (simulation.duration and \
                          extra_time): the spectrum without the joint is computed once per record over that window"
                    ),
                ));
            }
            cases.push(Case { name, bodies: bodies_of(&config), config });
        }
        // what can be checked before any job runs is bad input, not a failed
        // job: every case's geometry, and every case's run length with
        // every record
        let named = sweep.contains_key("cases");
        for case in &cases {
            let name = &case.name;
            let context = |e: ModelError| {
                if named {
                    sweep_err("sweep.cases", format!("case {name:?}: {e}"))
                } else {
                    SweepError::from(e)
                }
            };
            // every joint's (a bridge given by its modes: each of [[joints]])
            for place in quakejoint_model::placement::places(&case.config).map_err(context)? {
                if place.config.joint.enabled {
                    quakejoint_model::geometry::Geometry::new(&place.config)
                        .map_err(|e| match e {
                            ModelError::Geometry(g) if !place.prefix.is_empty() => {
                                ModelError::Geometry(format!("joint {:?}: {g}", place.name))
                            }
                            other => other,
                        })
                        .map_err(context)?;
                }
            }
            if let Some(m) = &modal {
                // the modes the case keeps, at a swept scale
                RunSpec::new(case.config.clone(), &m.overrides(0)).map_err(context)?;
            }
            for r in &records {
                quakejoint_model::run::check_run_length(&case.config, &r.record).map_err(context)?;
            }
        }
        let mut warnings = Vec::new();
        if let Some(suite) = &suite {
            warnings.extend(suite_warnings(suite));
        }
        for r in &records {
            warnings.extend(window_warning(&base_config, &r.record, &periods, &damping, modal.as_ref()));
        }
        let mut used = base_config.clone();
        used.sweep = Some(sweep.clone());
        // the config as resolved, defaults included, so that a change of a
        // default between versions also tells a journal's jobs apart (as
        // written, should it not serialise)
        let mut resolved = toml::Table::try_from(&base_config).unwrap_or_else(|_| table.clone());
        resolved.remove("sweep");
        let mut canonical = toml::to_string(&without_run_settings(&resolved)).unwrap_or_default()
            + &toml::to_string(&without_run_settings(&sweep)).unwrap_or_default();
        if let Some(m) = &modal {
            // the modes file's contents: a changed file is another sweep
            canonical += &format!("\n# modes file sha256 {}\n", m.sha256);
        }
        Ok(Self {
            cases,
            records,
            record_y,
            suite,
            damping,
            periods,
            modal,
            history_periods,
            checkpoint_seconds,
            config_used: toml::to_string(&used).unwrap_or_default(),
            warnings,
            config_text: config_text.to_string(),
            config_sha256: sha256_hex(canonical.as_bytes()),
        })
    }

    /// The swept value `t` in words: `T 1.0000 s`, or for a bridge given
    /// by its modes `period scale 1.25 (T1 0.9210 s)`.
    pub fn axis_label(&self, t: usize) -> String {
        match &self.modal {
            Some(m) => format!("period scale {} (T1 {:.4} s)", m.period_scales[t], self.periods[t]),
            None => format!("T {:.4} s", self.periods[t]),
        }
    }

    /// The swept values: the periods \[s\], or for a bridge given by its
    /// modes the period scales [-].
    pub fn axis(&self) -> &[f64] {
        self.modal.as_ref().map_or(&self.periods, |m| &m.period_scales)
    }

    /// The overrides of job `job`: its period and damping from the grid,
    /// or for a bridge given by its modes its period scale, each named as
    /// the sweep names it.
    pub fn overrides(&self, job: Job) -> Overrides {
        match &self.modal {
            Some(m) => m.overrides(job.period),
            None => Overrides {
                period: Some(Named::new(self.periods[job.period], format!("sweep.periods[{}]", job.period))),
                damping: Some(Named::new(self.damping[job.damping], format!("sweep.damping[{}]", job.damping))),
                ..Overrides::default()
            },
        }
    }

    /// Array dimensions (cases, records, dampings, periods).
    pub fn dims(&self) -> [usize; 4] {
        [self.cases.len(), self.records.len(), self.damping.len(), self.periods.len()]
    }

    /// Number of coupled runs.
    pub fn job_count(&self) -> usize {
        self.dims().iter().product()
    }

    /// Flat index of a job (case-major, then record, damping, period).
    pub fn index(&self, job: Job) -> usize {
        let [_, nr, nz, nt] = self.dims();
        ((job.case * nr + job.record) * nz + job.damping) * nt + job.period
    }

    /// The job of a flat index.
    pub fn job(&self, index: usize) -> Job {
        let [_, nr, nz, nt] = self.dims();
        Job {
            case: index / (nr * nz * nt),
            record: index / (nz * nt) % nr,
            damping: index / nt % nz,
            period: index % nt,
        }
    }

    /// Estimated cost of a job: seconds on one core of the reference machine
    /// ([`cost_seconds`]).
    pub fn cost(&self, job: Job) -> f64 {
        let case = &self.cases[job.case];
        let record = &self.records[job.record].record;
        let duration = quakejoint_model::run::run_duration(&case.config, record);
        cost_seconds(case.bodies, duration / record.dt, self.periods[job.period])
    }

    /// The jobs of shard `k` of `n` (1-based `k`): jobs sorted by decreasing
    /// cost are dealt to the currently lightest shard (longest processing
    /// time first), which balances cost and depends only on the plan.
    pub fn shard(&self, k: usize, n: usize) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.job_count()).collect();
        order.sort_by(|&a, &b| self.cost(self.job(b)).total_cmp(&self.cost(self.job(a))).then(a.cmp(&b)));
        let mut load = vec![0.0f64; n];
        let mut mine = Vec::new();
        for i in order {
            let s = (0..n).min_by(|&x, &y| load[x].total_cmp(&load[y]).then(x.cmp(&y))).unwrap_or(0);
            load[s] += self.cost(self.job(i));
            if s + 1 == k {
                mine.push(i);
            }
        }
        mine.sort_unstable();
        mine
    }
}

/// What running some jobs of a plan in one process takes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// Jobs.
    pub jobs: usize,
    /// Cost-model seconds on one core of the reference machine (the wall
    /// time on one thread; on `t` threads about this divided by `t`).
    pub seconds: f64,
    /// Peak resident memory of the process \[MB\].
    pub memory_mb: f64,
}

impl Plan {
    /// The time and memory of running `jobs` (flat indices) in one process
    /// with `threads` workers (docs/sweep.md, "Cost of a job"). The memory
    /// is that of the measured components: the program and HDF5 library,
    /// the records, the result arrays and the stored histories (each held
    /// three times: arrays, journal frame, HDF5 write), and one model per
    /// worker; the sweep reports its measured peak (`peak_memory_mb`), which
    /// a test keeps below this estimate.
    pub fn estimate(&self, jobs: &[usize], threads: usize) -> Estimate {
        const MB: f64 = 1.0 / (1024.0 * 1024.0);
        let seconds = jobs.iter().map(|&j| self.cost(self.job(j))).sum();
        let samples = |r: &SweepRecord| r.record.acceleration.len() as f64;
        let record_bytes: f64 = self.records.iter().chain(&self.record_y).map(|r| samples(r) * 8.0 * 3.0).sum();
        let longest = self.records.iter().map(samples).fold(0.0, f64::max);
        let joints = self.modal.as_ref().map_or(0, |m| m.joints.len()) as f64;
        let per_job =
            crate::results::FIELDS.len() as f64 + 4.0 + joints * (crate::results::JOINT_FIELDS.len() as f64 + 1.0);
        let result_bytes = self.job_count() as f64 * (per_job * 8.0) * 3.0;
        let histories = self.history_periods.len() * self.job_count() / self.periods.len().max(1);
        // seven series, the clear sub-gaps at both ends and their contact
        // forces, Nc + 1 of each
        let gaps = self.cases.iter().filter(|c| c.config.joint.enabled).map(|c| c.config.joint.center_beams + 1).max();
        let history_bytes = histories as f64 * longest * (7 + 3 * gaps.unwrap_or(0)) as f64 * 8.0 * 3.0;
        let bodies = self.cases.iter().map(|c| c.bodies).max().unwrap_or(0) as f64;
        let worker_mb = MEMORY_PER_WORKER_MB + MEMORY_PER_BODY_MB * bodies + longest * 8.0 * 6.0 * MB;
        let memory_mb = MEMORY_BASE_MB
            + (record_bytes + result_bytes + history_bytes) * MB
            + threads.max(1).min(jobs.len().max(1)) as f64 * worker_mb;
        Estimate { jobs: jobs.len(), seconds, memory_mb }
    }
}

/// Memory of the program, the HDF5 library and the allocator \[MB\].
pub const MEMORY_BASE_MB: f64 = 18.0;
/// Memory of a worker without its model \[MB\].
pub const MEMORY_PER_WORKER_MB: f64 = 1.0;
/// Memory of a worker's model per joint body \[MB\].
pub const MEMORY_PER_BODY_MB: f64 = 0.025;

/// Seconds per output sample of a job, whatever the model ([`cost_seconds`]).
pub const COST_PER_SAMPLE: f64 = 4.0e-6;
/// Seconds per joint body and output sample ([`cost_seconds`]).
pub const COST_PER_BODY_SAMPLE: f64 = 1.45e-6;

/// The cost model of a coupled run, measured on this engine (docs/sweep.md,
/// "Cost of a job"): seconds on one core of the reference machine for a
/// joint of `bodies` rigid bodies, `samples` output samples (the steps never
/// cross a sample, so the step count follows the sample count) and bridge
/// period `period` \[s\]:
/// `samples * (COST_PER_SAMPLE + COST_PER_BODY_SAMPLE * bodies) * f(T)` with
/// `f(T) = 1 - 0.45 exp(-(T / 0.2 s)^2)`: a stiff bridge (short period)
/// barely moves the joint, so its friction rarely reverses and Newton needs
/// fewer iterations (T = 0.1 s costs about 60 % of T = 1 s).
pub fn cost_seconds(bodies: usize, samples: f64, period: f64) -> f64 {
    let f = 1.0 - 0.45 * (-(period / 0.2).powi(2)).exp();
    samples.max(1.0) * (COST_PER_SAMPLE + COST_PER_BODY_SAMPLE * bodies as f64) * f
}

/// The bodies of a job's model for the cost estimate: the joints' (each
/// of `[[joints]]` on a bridge given by its modes) and, on a bridge given
/// by its modes, one per kept mode (a one-coordinate body: counted as a
/// joint body, an overestimate the cost model was not measured for).
fn bodies_of(config: &Config) -> usize {
    let joint = |j: &quakejoint_model::config::JointConfig| {
        if j.enabled {
            let (nc, ns) = (j.center_beams, j.support_beams.len());
            nc + ns + nc * ns
        } else {
            0
        }
    };
    let Some(m) = &config.bridge.modal else { return joint(&config.joint) };
    let joints: usize = if config.joints.is_empty() {
        joint(&config.joint)
    } else {
        config.joints.iter().map(|p| joint(p.joint.as_ref().unwrap_or(&config.joint))).sum()
    };
    let modes = quakejoint_model::modal::loaded(m).map_or(0, |b| b.modes.len().min(m.modes_used.unwrap_or(usize::MAX)));
    joints + modes
}
