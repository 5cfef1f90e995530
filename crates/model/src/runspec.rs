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

use quakejoint_motion::{Peaks, Record, RecordSpec, SpectrumError, SpectrumOptions, SpectrumRow};

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
    /// line's `--record`).
    pub record: Option<RecordSpec>,
    /// Run the bridge alone, exactly (no joint).
    pub alone: bool,
    /// A factor on every period of a bridge given by its modes \[-\]
    /// (replaces `bridge.modal.period_scale`).
    pub period_scale: Option<Named<f64>>,
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
        if let Some(r) = &overrides.record {
            config.record = Some(r.clone());
        }
        if overrides.alone {
            config.joint.enabled = false;
        }
        let scenario = Scenario::new(config)?;
        let period = match &scenario.kept {
            Some(kept) => 2.0 * std::f64::consts::PI / kept[0].omega,
            None => overrides.period.as_ref().map_or_else(|| scenario.config.bridge.natural_period(), |p| p.value),
        };
        Ok(RunSpec { scenario, alone: overrides.alone, period })
    }

    /// The config as the run uses it.
    pub fn config(&self) -> &Config {
        &self.scenario.config
    }

    /// The bridge's circular frequency \[rad/s\].
    pub fn omega(&self) -> f64 {
        self.config().bridge.omega()
    }

    /// Runs it under `record_x` (and `record_y` across, if the deck moves
    /// across): the coupled model, or the bridge alone exactly; with
    /// histories also the bridge alone's absolute acceleration at the same
    /// output times (`a_abs_without_joint` of the histories).
    pub fn run(
        &self,
        record_x: &Record,
        record_y: Option<&Record>,
        options: &RunOptions,
    ) -> Result<RunResult, ModelError> {
        let config = self.config();
        let reference = Reference::for_run(config, record_x, record_x);
        if let Some(m) = &config.bridge.modal {
            return self.run_modal(m, &reference, record_x, record_y, options);
        }
        let mut result = if self.alone {
            crate::linear::linear_response(reference.window(), self.omega(), config.bridge.damping, options.histories)
        } else {
            simulate_scenario(&self.scenario, record_x, record_y, options)?
        };
        if let Some(h) = &mut result.histories {
            h.a_abs_without_joint = reference.a_abs(self.period, config.bridge.damping, h.t.len());
        }
        Ok(result)
    }

    /// [`RunSpec::run`] of a bridge given by its modes: the run (or the
    /// bridge alone at the first joint's deck point), each point of the
    /// modes file and the base shear without the joints, and the check of
    /// the kept modes, from one modal superposition.
    fn run_modal(
        &self,
        m: &crate::config::ModalConfig,
        reference: &Reference,
        record_x: &Record,
        record_y: Option<&Record>,
        options: &RunOptions,
    ) -> Result<RunResult, ModelError> {
        let kept = self.scenario.kept.as_deref().unwrap_or_default();
        let bridge = crate::modal::loaded(m)?;
        let places = &self.scenario.places;
        // the first joint's deck point
        let point = places[0].deck_point;
        let alone = crate::modal::alone(m, kept, reference.window())?;
        let mut result = if self.alone {
            let h = alone.points[point].clone();
            let mut r = crate::linear::modal_result(reference.window(), kept[0].omega, h, options.histories);
            // the run is the bridge alone: its values are those
            r.points = bridge
                .points
                .iter()
                .enumerate()
                .map(|(p, mp)| {
                    let [sd, sa] = alone.peaks(p);
                    crate::modal::PointPeaks {
                        name: mp.name.clone(),
                        sd,
                        sa,
                        t_sd: f64::NAN,
                        t_sa: f64::NAN,
                        ..Default::default()
                    }
                })
                .collect();
            r.base_shear = Some(alone.base_shear_peak());
            r
        } else {
            simulate_scenario(&self.scenario, record_x, record_y, options)?
        };
        for (p, peaks) in result.points.iter_mut().enumerate() {
            [peaks.sd_without, peaks.sa_without] = alone.peaks(p);
        }
        result.base_shear_without = Some(alone.base_shear_peak());
        let points: Vec<usize> =
            places.iter().flat_map(|p| std::iter::once(p.deck_point).chain(p.abutment_point)).collect();
        let check = bridge.mode_check(kept, &points);
        let mut warnings = check.warnings(bridge, &points, m.corrected(), !self.alone);
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
            h.a_abs_without_joint = at_times(&alone.points[point].a_abs);
            // every point's, the bridge alone's (and the run's, when it is
            // the bridge alone)
            h.points_u_without_joint = alone.points.iter().map(|p| at_times(&p.u)).collect();
            h.points_a_abs_without_joint = alone.points.iter().map(|p| at_times(&p.a_abs)).collect();
            if self.alone {
                h.points_u = h.points_u_without_joint.clone();
                h.points_a_abs = h.points_a_abs_without_joint.clone();
            }
        }
        Ok(result)
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

    /// The bridge's absolute acceleration \[m/s^2\] at the first `samples`
    /// sample times (NaN past the window).
    pub fn a_abs(&self, period: f64, damping: f64, samples: usize) -> Vec<f64> {
        let exact = quakejoint_motion::history(&self.window.acceleration, self.window.dt, period, damping).a_abs;
        let mut a: Vec<f64> = exact.into_iter().take(samples).collect();
        a.resize(samples, f64::NAN);
        a
    }

    /// The spectrum over `periods` \[s\] and `damping` ratios \[-\].
    pub fn spectrum(&self, periods: &[f64], damping: &[f64]) -> Result<Vec<SpectrumRow>, SpectrumError> {
        quakejoint_motion::spectrum(&self.window, periods, damping, SpectrumOptions::default())
    }
}
