//! One coupled earthquake run: the bridge with the joint under a record.
//!
//! What is reported follows the model description: the deck's absolute
//! acceleration `a_abs = u'' + a_g` from the force balance on the deck
//! (spring, damper and joint reaction, not by differencing), the spectral
//! values `Sa = max |a_abs|`, `Sd = max |u|`, `Sv = max |u'|`, `PSa = w0^2 Sd`
//! with the times of the peaks (taken at the record's sample times, the
//! spectrum convention), the joint's demands and the run's quality figures.

use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use quakejoint_motion::{load_record, LoadedRecord, Record};
use quakejoint_solver::{IntegratorOptions, JacobianMode, LinearSolver, TimeSeries};

use crate::config::{Config, LinearSolverConfig};
use crate::error::ModelError;
use crate::generator::BearingJoint;

pub use crate::history::Histories;

/// Called with the simulated time as a run advances.
pub type ProgressFn = Arc<dyn Fn(f64) + Send + Sync>;

/// Options of one run.
#[derive(Clone, Default)]
pub struct RunOptions {
    /// Record time histories at every output time.
    pub histories: bool,
    /// Reports the simulated time about every 0.1 s of it.
    pub progress: Option<ProgressFn>,
    /// When set (by a signal handler, say), the run stops at its next step
    /// with [`ModelError::Interrupted`].
    pub cancel: Option<Arc<AtomicBool>>,
    /// How the bearings' sliding joints are written (the translational form
    /// unless a check asks for the spec's prismatic one).
    pub bearing_joint: BearingJoint,
}

impl std::fmt::Debug for RunOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RunOptions")
            .field("histories", &self.histories)
            .field("progress", &self.progress.is_some())
            .field("cancel", &self.cancel.is_some())
            .field("bearing_joint", &self.bearing_joint)
            .finish()
    }
}

mod coupled;
pub mod fuse;
mod observer;
mod result;

pub(crate) use crate::watch::DENSE_OUTPUT;
pub use coupled::{simulate_records, simulate_scenario};
pub use observer::CHECK_INTERVAL;
pub use result::{FarSegment, JointResult, RunResult, Transverse, JOINT_FIELDS};

/// Loads the records of a config (x, and y if given), with their hashes
/// and the warnings raised while reading them.
pub fn load_records(config: &Config, base_dir: &Path) -> Result<(LoadedRecord, Option<LoadedRecord>), ModelError> {
    let x = load_record(&config.record_x(), base_dir)?;
    let y = config.record_y.as_ref().map(|spec| load_record(spec, base_dir)).transpose()?;
    Ok((x, y))
}

/// Reads the records of `config` (relative paths against `base_dir`) and runs.
pub fn simulate(config: &Config, base_dir: &Path, options: &RunOptions) -> Result<RunResult, ModelError> {
    let (x, y) = load_records(config, base_dir)?;
    simulate_records(config, &x.record, y.as_ref().map(|y| &y.record), options)
}

/// Solver options from the config.
pub fn integrator_options(config: &Config) -> IntegratorOptions {
    let s = &config.simulation;
    let mut o = IntegratorOptions {
        rtol: s.rtol,
        atol_translation: s.atol,
        atol_velocity: s.atol,
        atol_rotation: s.atol_rotation,
        atol_angular_velocity: s.atol_rotation,
        max_wall_time: s.max_wall_time,
        linear_solver: match s.linear_solver {
            LinearSolverConfig::Block => LinearSolver::Block,
            LinearSolverConfig::Faer => LinearSolver::Faer,
        },
        jacobian: if s.finite_difference_jacobian {
            JacobianMode::FiniteDifference { parallel: false }
        } else {
            JacobianMode::Analytic
        },
        // measured on the expansion-joint models against 100 times tighter
        // tolerances (docs/performance.md): keeping the Jacobian while Newton
        // contracts by 0.2 and stopping Newton at 0.2 of the tolerance
        // (RADAU5's default, min(0.03, sqrt(0.1 rtol^(2/3))), is 3.2e-3 at
        // rtol = 1e-6; the earlier 0.03 took 10 % more
        // iterations and 7 % more time on the reference run) change no
        // result beyond 3e-4 and take 5-40 times fewer factorisations
        jacobian_reuse: 0.2,
        newton_tolerance: Some(0.2),
        ..IntegratorOptions::default()
    };
    if let Some(h) = s.h_max {
        o.h_max = o.h_max.min(h);
    }
    if let Some(n) = s.max_steps {
        o.max_steps = n;
    }
    o
}

fn series(record: &Record) -> Result<TimeSeries, ModelError> {
    Ok(TimeSeries::uniform(0.0, record.dt, record.acceleration.clone())?)
}

/// The simulated duration of a run \[s\]: `simulation.duration`, else the
/// record's duration plus `simulation.extra_time`.
pub fn run_duration(config: &Config, record_x: &Record) -> f64 {
    config.simulation.duration.unwrap_or(record_x.duration() + config.simulation.extra_time)
}

/// The ground motion over the run's window, `[0, run_duration]`: the record
/// cut at the last sample inside the window (`simulation.duration` shorter
/// than the record), or followed by zeros (`extra_time`: the ground is at
/// rest after the record ends, as in the coupled run). The bridge without
/// the joint is solved under this, so that both spectra cover the same
/// time: the peaks of a 40 s record's response are not compared with those
/// of a run that stopped after 10 s.
pub fn run_window(config: &Config, record: &Record) -> Record {
    window_to(record, run_duration(config, record))
}

/// `record` over `[0, duration]` [s]: cut at the last sample inside, or
/// followed by zeros.
pub(crate) fn window_to(record: &Record, duration: f64) -> Record {
    let samples = (duration / record.dt * (1.0 + 1e-12)).floor() as usize + 1;
    let mut acceleration = record.acceleration.clone();
    acceleration.resize(samples.max(2), 0.0);
    Record { acceleration, ..record.clone() }
}

/// Most output samples a run may write (its duration over the record's time
/// step): each is a force balance and, with histories, eight numbers.
pub const MAX_OUTPUT_SAMPLES: f64 = 1e7;

/// Refuses a run whose length and record cannot work: more output samples
/// than [`MAX_OUTPUT_SAMPLES`] (a day of free vibration at 1e-5 s, say).
pub fn check_run_length(config: &Config, record_x: &Record) -> Result<(), ModelError> {
    let duration = run_duration(config, record_x);
    let samples = duration / record_x.dt;
    if samples > MAX_OUTPUT_SAMPLES {
        let field = if config.simulation.duration.is_some() { "simulation.duration" } else { "simulation.extra_time" };
        return Err(ModelError::Invalid {
            field: field.to_string(),
            value: quakejoint_motion::number(duration),
            reason: format!(
                "{} s of run at the record's time step of {} s are {} output samples, more than {:e}",
                quakejoint_motion::number(duration),
                quakejoint_motion::number(record_x.dt),
                quakejoint_motion::number(samples.round()),
                MAX_OUTPUT_SAMPLES
            ),
        });
    }
    Ok(())
}
