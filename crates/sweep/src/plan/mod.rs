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
//! `bridge.modal.modes_used`, `joint_point` or `static_correction` but not
//! the modes file, the period scale or `bridge.damping`.

use std::path::Path;

use quakejoint_model::runspec::{Named, Overrides, RunSpec};
use quakejoint_model::{Config, ModelError};
use quakejoint_motion::sha256_hex;
use quakejoint_motion::RecordSpec;

use crate::error::SweepError;

mod cases;
mod cost;
mod grid;
mod modal;
mod records;
mod section;
mod stripes;
mod suite;

pub use cases::Case;
use cases::{merge, refused_in_case};
use cost::bodies_of;
pub use cost::{
    cost_seconds, Estimate, COST_PER_BODY_SAMPLE, COST_PER_SAMPLE, MEMORY_BASE_MB, MEMORY_PER_BODY_MB,
    MEMORY_PER_WORKER_MB,
};
use grid::{check_swept, grid_of};
use modal::modal_axis;
pub use modal::ModalSweep;
use records::window_warning;
pub use records::SweepRecord;
use section::SweepSection;
use stripes::stripes_of;
pub use stripes::{Measure, StripeRun, Stripes, STRIPES_KEYS};
use suite::{suite_of, suite_warnings};
pub use suite::{Suite, SUITE_KEYS};
/// The keys of the `[sweep]` table.
pub const SWEEP_KEYS: [&str; 10] = [
    "periods",
    "period_scales",
    "damping",
    "records",
    "cases",
    "histories",
    "checkpoint_seconds",
    "suite",
    "stripes",
    "fragility",
];

/// Longest interval between checkpoints or progress lines \[s\] (116 days;
/// the longest run allowed, `simulation.max_wall_time`, is as long).
pub const MAX_INTERVAL: f64 = 1e7;

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
    /// The stripes of a multiple-stripe analysis (`[sweep.stripes]`):
    /// `records` are then the records as given scaled to every level.
    pub stripes: Option<Stripes>,
    /// The limit states, hazard and fitting of the stripes
    /// (`[sweep.fragility]`; its defaults when the table is absent).
    pub fragility: Option<crate::fragility::FragilitySpec>,
    /// Damping ratios [-] (a bridge given by its modes: one,
    /// `bridge.damping`, the damping of the modes the file gives none for).
    pub damping: Vec<f64>,
    /// Bridge periods \[s\] (a bridge given by its modes: its longest kept
    /// period at each of `modal.period_scales`, which are the swept axis).
    pub periods: Vec<f64>,
    /// A bridge given by its modes: the swept period scales, the modes
    /// file and its joints.
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

/// Refuses a key of the table `t` (at `field`) that is not one of `keys`.
pub(crate) fn known_keys(t: &toml::Table, field: &str, keys: &[&str]) -> Result<(), SweepError> {
    match t.keys().find(|k| !keys.contains(&k.as_str())) {
        Some(key) => Err(sweep_err(&format!("{field}.{key}"), format!("unknown key (expected {})", keys.join(", ")))),
        None => Ok(()),
    }
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
    // limit states, hazard and fitting change no job's result: a finished
    // sweep is refitted by running it again
    t.remove("fragility");
    if let Some(toml::Value::Array(cases)) = t.get_mut("cases") {
        for case in cases {
            if let toml::Value::Table(c) = case {
                strip(c);
            }
        }
    }
    t
}

/// Refuses a hazard curve that does not reach the stripes' range: it is
/// for another measure, or in other units than g.
fn hazard_overlaps(s: &Stripes, f: &crate::fragility::FragilitySpec) -> Result<(), SweepError> {
    let Some(h) = &f.hazard else { return Ok(()) };
    let (points, source) = (h.curve.points(), &h.source);
    let (h0, h1) = (points[0].0, points[points.len() - 1].0);
    let (l0, l1) = (s.levels[0], s.levels[s.levels.len() - 1]);
    if h1 < l0 || h0 > l1 {
        return Err(sweep_err(
            "sweep.fragility.hazard",
            format!(
                "{source}: its intensities ({h0} to {h1} g) do not reach the stripes' ({l0} to {l1} g): a hazard curve \
                 of {} in g is needed",
                s.measure.label()
            ),
        ));
    }
    Ok(())
}

/// Refuses what stripes cannot go with besides a suite: a record's own
/// scaling (it would be undone) and a transverse record (it would stay
/// unscaled).
fn stripes_allowed(config: &Config, records: &[SweepRecord]) -> Result<(), SweepError> {
    if let Some(y) = &config.record_y {
        return Err(sweep_err(
            "sweep.stripes",
            format!(
                "the stripes scale the records along the bridge; [record_y] ({}) would stay unscaled: remove it",
                y.file.display()
            ),
        ));
    }
    for (i, r) in records.iter().enumerate() {
        if r.spec.scale != 1.0 || r.spec.target_pga_g.is_some() {
            return Err(sweep_err(
                &format!("sweep.records[{i}]"),
                format!(
                    "{}: the stripes scale every record to every level; remove `scale` and `target_pga_g`",
                    r.spec.file.display()
                ),
            ));
        }
    }
    Ok(())
}

/// Checks the `[sweep]` table of a config's text, if it has one, as
/// `quakejoint sweep` reads it (its records read, a suite or stripes scaled,
/// its fragility and hazard curve checked): `model`, `simulate` and
/// Python's `Config` run it, so that a config whose `[sweep]` is broken is
/// refused by every command, naming the key, not by the sweep alone.
pub fn check_sweep(config_text: &str, source: &str, base_dir: &Path) -> Result<(), SweepError> {
    let table: toml::Table =
        toml::from_str(config_text).map_err(|e| SweepError::from(quakejoint_model::config::parse_error(source, &e)))?;
    if table.contains_key("sweep") {
        Plan::new(config_text, source, base_dir)?;
    }
    Ok(())
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
        let sweep = SweepSection::read(sweep)?;
        let (periods, damping, modal) = axes_of(&sweep, &base_config, base_dir)?;
        let history_periods = history_indices(&sweep.histories, &periods, modal.as_ref())?;
        let checkpoint_seconds = sweep.checkpoint_seconds;
        let specs = record_specs(&sweep, &base_config)?;
        let mut records = specs.into_iter().map(|s| SweepRecord::load(s, base_dir)).collect::<Result<Vec<_>, _>>()?;
        let suite = match &sweep.suite {
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
        // the records as given: the window warnings are about them
        let given = sweep.stripes.is_some().then(|| records.clone());
        let (stripes, stripe_warnings) = match &sweep.stripes {
            Some(v) => {
                stripes_allowed(&base_config, &records)?;
                let (s, w) = stripes_of(v, &periods, &damping, &mut records, &base_config)?;
                (Some(s), w)
            }
            None => (None, Vec::new()),
        };
        let fragility = match (&stripes, sweep.fragility.as_ref()) {
            (Some(_), f) => Some(crate::fragility::FragilitySpec::from_toml(f, base_dir)?),
            (None, Some(_)) => {
                return Err(sweep_err(
                    "sweep.fragility",
                    "limit states are fitted on stripes: add [sweep.stripes] (the measure and its levels)",
                ))
            }
            (None, None) => None,
        };
        if let (Some(s), Some(f)) = (&stripes, &fragility) {
            hazard_overlaps(s, f)?;
        }
        let record_y = base_config.record_y.clone().map(|s| SweepRecord::load(s, base_dir)).transpose()?;
        for (i, r) in records.iter().enumerate() {
            if records[..i].iter().any(|o| o.record.name == r.record.name) {
                return Err(sweep_err(
                    "sweep.records",
                    format!("two records are named {:?}; give one a `name`", r.record.name),
                ));
            }
        }
        let cases = cases_of(sweep.cases.as_deref().unwrap_or_default(), &table, &base_config, modal.is_some())?;
        check_cases(&cases, sweep.cases.is_some(), modal.as_ref(), &records)?;
        let mut warnings = Vec::new();
        if let Some(suite) = &suite {
            warnings.extend(suite_warnings(suite));
        }
        for r in given.as_ref().unwrap_or(&records) {
            warnings.extend(window_warning(&base_config, &r.record, &periods, &damping, modal.as_ref()));
        }
        warnings.extend(stripe_warnings);
        let (config_used, config_sha256) = identity(&base_config, &table, &sweep.table, modal.as_ref());
        Ok(Self {
            cases,
            records,
            record_y,
            suite,
            stripes,
            fragility,
            damping,
            periods,
            modal,
            history_periods,
            checkpoint_seconds,
            config_used,
            warnings,
            config_text: config_text.to_string(),
            config_sha256,
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
}

/// The swept axes: the periods \[s\] (a bridge given by its modes: its
/// longest kept period at each swept scale), the damping ratios and, for a
/// bridge given by its modes, the period scales.
fn axes_of(sweep: &SweepSection, base_config: &Config, base_dir: &Path) -> Result<Axes, SweepError> {
    match &base_config.bridge.modal {
        Some(m) => {
            let modal = modal_axis(sweep, m, base_config, base_dir)?;
            // each scale applied and checked as every job applies it:
            // the bridge's longest kept period there
            let periods = (0..modal.period_scales.len())
                .map(|t| RunSpec::new(base_config.clone(), &modal.overrides(t)).map(|spec| spec.period))
                .collect::<Result<Vec<f64>, ModelError>>()?;
            Ok((periods, vec![base_config.bridge.damping], Some(modal)))
        }
        None => {
            if sweep.period_scales.is_some() {
                return Err(sweep_err(
                    "sweep.period_scales",
                    "a factor on the periods of a bridge given by its modes ([bridge.modal]); this bridge is a \
                     single-DOF deck: sweep its period with sweep.periods",
                ));
            }
            let periods = grid_of(
                sweep.periods.as_ref().ok_or_else(|| sweep_err("sweep.periods", "missing"))?,
                "sweep.periods",
                "bridge.period",
                "s",
            )?;
            let damping = sweep.damping.clone().unwrap_or_else(|| vec![base_config.bridge.damping]);
            if damping.is_empty() {
                return Err(sweep_err("sweep.damping", "no damping ratio"));
            }
            check_swept(&damping, "sweep.damping", "bridge.damping")?;
            Ok((periods, damping, None))
        }
    }
}

/// The swept periods \[s\], damping ratios \[-\] and a modal bridge's
/// period scales.
type Axes = (Vec<f64>, Vec<f64>, Option<ModalSweep>);

/// The indices of the swept periods (period scales) whose histories are
/// kept: each requested one picks the nearest swept one, within 5 %.
fn history_indices(requested: &[f64], periods: &[f64], modal: Option<&ModalSweep>) -> Result<Vec<usize>, SweepError> {
    // each requested period (a modal bridge: period scale) picks the
    // nearest swept one (within 5 %)
    let (axis, unit) = match modal {
        Some(m) => (m.period_scales.as_slice(), ""),
        None => (periods, " s"),
    };
    let what = if modal.is_some() { "period scale" } else { "period" };
    let mut idx = Vec::new();
    for &t in requested {
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
    Ok(idx)
}

/// The records of `sweep.records` (the config's `[record]` without it),
/// checked against the config's `[record]`, `[record_y]` and a suite.
fn record_specs(sweep: &SweepSection, base_config: &Config) -> Result<Vec<RecordSpec>, SweepError> {
    let specs = sweep.records.clone().unwrap_or_else(|| vec![base_config.record_x()]);
    if let (Some(_), Some(r)) = (&sweep.records, &base_config.record) {
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
    if let (true, Some(y)) = (sweep.suite.is_some(), &base_config.record_y) {
        return Err(sweep_err(
            "sweep.suite",
            format!(
                "the suite scales its records along the bridge to the target; [record_y] ({}) would stay \
                 unscaled: remove it (suites of transverse records are not supported)",
                y.file.display()
            ),
        ));
    }
    if sweep.suite.is_some() {
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
    Ok(specs)
}

/// The sweep's cases: each `[[sweep.cases]]` merged into the config and
/// checked, or the config alone as the case "base".
fn cases_of(
    case_tables: &[toml::Table],
    table: &toml::Table,
    base_config: &Config,
    modal: bool,
) -> Result<Vec<Case>, SweepError> {
    let mut cases = Vec::new();
    if case_tables.is_empty() {
        cases.push(Case { name: "base".to_string(), bodies: bodies_of(base_config), config: base_config.clone() });
    }
    for (i, mut ct) in case_tables.iter().cloned().enumerate() {
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
            if let Some(why) = refused_in_case(b, modal) {
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
    Ok(cases)
}

/// What can be checked before any job runs is bad input, not a failed
/// job: every case's geometry, and every case's run length with every
/// record.
fn check_cases(
    cases: &[Case],
    named: bool,
    modal: Option<&ModalSweep>,
    records: &[SweepRecord],
) -> Result<(), SweepError> {
    for case in cases {
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
        if let Some(m) = modal {
            // the modes the case keeps, at a swept scale
            RunSpec::new(case.config.clone(), &m.overrides(0)).map_err(context)?;
        }
        for r in records {
            quakejoint_model::run::check_run_length(&case.config, &r.record).map_err(context)?;
        }
    }
    Ok(())
}

/// The config as a sweep file records it (`config_used`) and the sweep's
/// identity, the SHA-256 of the config as resolved (defaults included, so
/// that a change of a default between versions also tells a journal's jobs
/// apart; as written, should it not serialise) with its `[sweep]` and, for
/// a bridge given by its modes, the modes file's contents.
fn identity(
    base_config: &Config,
    table: &toml::Table,
    sweep: &toml::Table,
    modal: Option<&ModalSweep>,
) -> (String, String) {
    let mut used = base_config.clone();
    used.sweep = Some(sweep.clone());
    // the config as resolved, defaults included, so that a change of a
    // default between versions also tells a journal's jobs apart (as
    // written, should it not serialise)
    let mut resolved = toml::Table::try_from(base_config).unwrap_or_else(|_| table.clone());
    resolved.remove("sweep");
    let mut canonical = toml::to_string(&without_run_settings(&resolved)).unwrap_or_default()
        + &toml::to_string(&without_run_settings(sweep)).unwrap_or_default();
    if let Some(m) = modal {
        // the modes file's contents: a changed file is another sweep
        canonical += &format!("\n# modes file sha256 {}\n", m.sha256);
    }
    (toml::to_string(&used).unwrap_or_default(), sha256_hex(canonical.as_bytes()))
}
