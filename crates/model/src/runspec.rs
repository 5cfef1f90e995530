//! One run, defined once: the config with every override a front end
//! applies (the command line's `--period`, Python's `period=`, a sweep
//! job's period and damping from its grid), checked by the same code
//! wherever it comes from ([`RunSpec`]), and the bridge alone that every
//! run with the joint is compared with ([`Reference`]).
//!
//! An override names itself in its errors as its front end names it:
//! `--period 100000: must be within 0.01 <= x <= 10 s` on the command
//! line, `period = 100000: ...` in Python, `sweep.periods[0] = 100000:
//! ...` in a sweep; the reason is the same text.

use std::path::Path;

use quakejoint_motion::{LoadedRecord, Peaks, Record, RecordSpec, SpectrumError, SpectrumOptions, SpectrumRow};

use crate::bridge::Bridge;
use crate::config::Config;
use crate::error::ModelError;
use crate::run::{run_duration, simulate_scenario, RunOptions, RunResult};
use crate::scenario::Scenario;

/// A value a front end sets for one run, with the name it gives it
/// (`--period`, `period`, `sweep.periods[3]`).
#[derive(Debug, Clone, PartialEq)]
pub struct Named<T> {
    /// The value.
    pub value: T,
    /// How the front end names it, for its errors.
    pub name: String,
}

impl<T> Named<T> {
    /// `value` named `name`.
    pub fn new(value: T, name: impl Into<String>) -> Self {
        Named { value, name: name.into() }
    }
}

/// What a front end changes in a config for one run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Overrides {
    /// The bridge's natural period \[s\] (replaces `bridge.period` and
    /// `bridge.w0`).
    pub period: Option<Named<f64>>,
    /// The bridge's damping ratio \[-\] (replaces `bridge.damping`).
    pub damping: Option<Named<f64>>,
    /// A record replacing the config's whole `[record]` (the command
    /// line's `--record`, Python's `record=`).
    pub record: Option<RecordOverride>,
    /// Run the bridge alone, exactly (no joint).
    pub alone: bool,
    /// A factor on every period of a bridge given by its modes \[-\]
    /// (replaces `bridge.modal.period_scale`).
    pub period_scale: Option<Named<f64>>,
    /// The service case's deck speed \[m/s\] (replaces `service.speed`).
    pub service_speed: Option<Named<f64>>,
    /// The service case's opening amplitude \[m\] (replaces
    /// `service.amplitude`).
    pub service_amplitude: Option<Named<f64>>,
    /// The service case's number of cycles (replaces `service.cycles`).
    pub service_cycles: Option<Named<u32>>,
}

/// The ground motion along x a front end gives for one run, replacing the
/// config's `[record]`.
#[derive(Debug, Clone, PartialEq)]
pub enum RecordOverride {
    /// A file and how to read it (the command line's `--record`; its path
    /// relative to the folder the run's records are read against).
    File(RecordSpec),
    /// A record already read (Python's `record=`, a `quakejoint.Record`).
    Loaded(Box<LoadedRecord>),
}

/// A run: the config with every override applied and checked.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSpec {
    /// The config as the run uses it, resolved (checked once, its joints
    /// placed).
    pub scenario: Scenario,
    /// The bridge alone, exactly, instead of the coupled model.
    pub alone: bool,
    /// The bridge's natural period \[s\]: the override as given, else the
    /// config's (2π/ω); a modal bridge's longest kept period.
    pub period: f64,
    /// A record read by the front end, which the run takes instead of the
    /// config's `[record]` ([`RunSpec::records`]).
    pub record: Option<Box<LoadedRecord>>,
}

/// Checks an override of the config key `key` (its range in
/// [`crate::limits::LIMITS`]), naming it `name` in the error.
pub fn check_override(key: &str, name: &str, value: f64) -> Result<(), ModelError> {
    crate::config::check_as(key, name, value).map_err(|e| match e {
        ModelError::Invalid { value, reason, .. } => ModelError::Override { name: name.to_string(), value, reason },
        other => other,
    })
}

impl RunSpec {
    /// `config` with `overrides` applied, then checked as a whole; an error
    /// about an overridden value names the override.
    pub fn new(mut config: Config, overrides: &Overrides) -> Result<Self, ModelError> {
        if config.bridge.modal.is_some() {
            if let Some(o) = [&overrides.period, &overrides.damping].into_iter().flatten().next() {
                return Err(ModelError::Override {
                    name: o.name.clone(),
                    value: quakejoint_motion::number(o.value),
                    reason: "the bridge is given by its modes ([bridge.modal]): its periods are the modes file's \
                             times bridge.modal.period_scale, its damping the file's (or bridge.damping where \
                             the file gives none)"
                        .to_string(),
                });
            }
        }
        if let Some(f) = &overrides.period_scale {
            let Some(m) = &mut config.bridge.modal else {
                return Err(ModelError::Override {
                    name: f.name.clone(),
                    value: quakejoint_motion::number(f.value),
                    reason: "a period scale applies to a bridge given by its modes ([bridge.modal])".to_string(),
                });
            };
            check_override("bridge.modal.period_scale", &f.name, f.value)?;
            m.period_scale = Some(f.value);
        }
        if let Some(p) = &overrides.period {
            check_override("bridge.period", &p.name, p.value)?;
            (config.bridge.period, config.bridge.w0) = (Some(p.value), None);
        }
        if let Some(z) = &overrides.damping {
            check_override("bridge.damping", &z.name, z.value)?;
            config.bridge.damping = z.value;
        }
        for (key, o) in
            [("service.speed", &overrides.service_speed), ("service.amplitude", &overrides.service_amplitude)]
        {
            if let Some(o) = o {
                check_override(key, &o.name, o.value)?;
            }
        }
        if let Some(o) = &overrides.service_cycles {
            check_override("service.cycles", &o.name, f64::from(o.value))?;
        }
        let s = &mut config.service;
        s.speed = overrides.service_speed.as_ref().map_or(s.speed, |o| o.value);
        s.amplitude = overrides.service_amplitude.as_ref().map_or(s.amplitude, |o| o.value);
        s.cycles = overrides.service_cycles.as_ref().map_or(s.cycles, |o| o.value);
        let mut record = None;
        match &overrides.record {
            Some(RecordOverride::File(r)) => config.record = Some(r.clone()),
            Some(RecordOverride::Loaded(r)) => record = Some(r.clone()),
            None => {}
        }
        if overrides.alone {
            config.joint.enabled = false;
        }
        let scenario = Scenario::with_period(config, overrides.period.as_ref().map(|p| p.value))?;
        let period = scenario.bridge.period();
        Ok(RunSpec { scenario, alone: overrides.alone, period, record })
    }

    /// The config as the run uses it.
    pub fn config(&self) -> &Config {
        &self.scenario.config
    }

    /// The run's records, along x and across: the one a front end read
    /// (Python's `record=`), else the config's `[record]`, relative paths
    /// against `base_dir`; `[record_y]` is always the config's.
    pub fn records(&self, base_dir: &Path) -> Result<(LoadedRecord, Option<LoadedRecord>), ModelError> {
        let Some(x) = &self.record else { return crate::run::load_records(self.config(), base_dir) };
        let y = self.config().record_y.as_ref().map(|s| quakejoint_motion::load_record(s, base_dir)).transpose()?;
        Ok((x.as_ref().clone(), y))
    }

    /// Runs it under `record_x` (and `record_y` across, if the deck moves
    /// across): the coupled model, or the bridge alone exactly; with the
    /// bridge alone's response beside it ([`Scenario::alone`]): its peaks
    /// at every point of a bridge given by its modes and, with histories,
    /// its absolute acceleration at the same output times
    /// (`a_abs_without_joint`, and every point's `points_*_without_joint`).
    pub fn run(
        &self,
        record_x: &Record,
        record_y: Option<&Record>,
        options: &RunOptions,
    ) -> Result<RunResult, ModelError> {
        let scenario = &self.scenario;
        let reference = Reference::for_run(self.config(), record_x, record_x);
        let window = reference.window();
        let modal = match &scenario.bridge {
            Bridge::SingleDof(b) => {
                let mut result = if self.alone {
                    b.alone(window, options.histories)
                } else {
                    simulate_scenario(scenario, record_x, record_y, options)?
                };
                if let Some(h) = &mut result.histories {
                    h.a_abs_without_joint = b.a_abs_alone(window, h.t.len());
                }
                return Ok(result);
            }
            Bridge::Modal(m) => m,
        };
        let every = modal.superposition(window, 0);
        let mut result = if self.alone {
            // the run is the bridge alone: its values are those
            let mut r = modal.alone_at(window, &every, scenario.first_point(), options.histories);
            r.points = (modal.file.points.iter().enumerate())
                .map(|(p, mp)| {
                    let [sd, sa] = every.peaks(p);
                    let name = mp.name.clone();
                    crate::modal::PointPeaks { name, sd, sa, t_sd: f64::NAN, t_sa: f64::NAN, ..Default::default() }
                })
                .collect();
            r.base_shear = Some(every.base_shear_peak());
            r
        } else {
            simulate_scenario(scenario, record_x, record_y, options)?
        };
        self.compare_modal(&mut result, modal, &every);
        Ok(result)
    }

    /// A run on a bridge given by its modes set beside its bridge alone
    /// `every`: each point's peaks and the base shear without the joints,
    /// the check of the kept modes, and the histories without the joints.
    fn compare_modal(&self, result: &mut RunResult, modal: &crate::bridge::Modal, every: &crate::modal::ModalAlone) {
        for (p, peaks) in result.points.iter_mut().enumerate() {
            [peaks.sd_without, peaks.sa_without] = every.peaks(p);
        }
        result.base_shear_without = Some(every.base_shear_peak());
        let places = &self.scenario.places;
        let points: Vec<usize> =
            places.iter().flat_map(|p| std::iter::once(p.deck_point).chain(p.abutment_point)).collect();
        let bridge = &*modal.file;
        let check = bridge.mode_check(&modal.kept, &points);
        let mut warnings = check.warnings(bridge, &points, modal.correction.is_some(), !self.alone);
        if !self.alone {
            warnings.extend(places.iter().filter_map(|p| bridge.across_warning(p.deck_point_y?)));
        }
        result.mode_check = Some((check, warnings));
        if let Some(h) = &mut result.histories {
            let at_times = |x: &[f64]| {
                let mut x = x.to_vec();
                x.resize(h.t.len(), f64::NAN);
                x
            };
            h.a_abs_without_joint = at_times(&every.points[self.scenario.first_point()].a_abs);
            // every point's, the bridge alone's (and the run's, when it is
            // the bridge alone)
            h.points_u_without_joint = every.points.iter().map(|p| at_times(&p.u)).collect();
            h.points_a_abs_without_joint = every.points.iter().map(|p| at_times(&p.a_abs)).collect();
            if self.alone {
                h.points_u = h.points_u_without_joint.clone();
                h.points_a_abs = h.points_a_abs_without_joint.clone();
            }
        }
    }
}

/// The bridge without the joint, solved exactly (a damped linear
/// oscillator under ground acceleration linear between samples) over a
/// run's window: what every run with the joint is compared with, and the
/// spectra without the joint of a sweep.
#[derive(Debug, Clone)]
pub struct Reference {
    window: Record,
}

impl Reference {
    /// `record` over the window of a run of `config` under `record_x` (the
    /// run's duration: `simulation.duration`, or `record_x` plus
    /// `extra_time`), cut at the last sample inside or followed by zeros.
    /// `record` is `record_x`, or the record across the bridge.
    pub fn for_run(config: &Config, record_x: &Record, record: &Record) -> Self {
        Reference { window: crate::run::window_to(record, run_duration(config, record_x)) }
    }

    /// The ground motion over the window.
    pub fn window(&self) -> &Record {
        &self.window
    }

    /// Peaks of the bridge of `period` \[s\] and `damping` \[-\].
    pub fn peaks(&self, period: f64, damping: f64) -> Peaks {
        quakejoint_motion::peaks(&self.window.acceleration, self.window.dt, period, damping, Default::default())
    }

    /// The spectrum over `periods` \[s\] and `damping` ratios \[-\].
    pub fn spectrum(&self, periods: &[f64], damping: &[f64]) -> Result<Vec<SpectrumRow>, SpectrumError> {
        quakejoint_motion::spectrum(&self.window, periods, damping, SpectrumOptions::default())
    }
}
