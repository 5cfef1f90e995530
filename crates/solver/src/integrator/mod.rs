//! Time integration of the constrained equations of motion
//!
//! ```text
//!   q' = v
//!   M v' = Q(t, q, v) - G(q)^T lambda
//!   0 = g(q, t)
//! ```
//!
//! with the Radau IIA method of order 5 ([`radau5`]), variable step size
//! driven by a local error estimate, the stages satisfying the constraints at
//! velocity level, every accepted state projected onto `g = 0` and
//! `G v + g_t = 0`, and sliding friction solved locally inside the Newton
//! iteration (`local_friction`). An [`Observer`] sees every accepted step
//! with its dense output ([`dense`]: the state at requested times, zeros of
//! functions of the state).

pub mod dense;
pub mod events;
mod local_friction;
pub mod radau5;

use crate::assembly::{Assembly, Workspace};
use crate::error::BuildError;
use crate::linalg::LinearSolver;

pub use dense::{OutputTime, OutputTimes, Root, RootTracker, StateBuffer};
pub use radau5::Radau5;

/// How the Jacobian is obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum JacobianMode {
    /// Analytic element derivatives (default).
    #[default]
    Analytic,
    /// Finite differences with Curtis-Powell-Reid column colouring, the
    /// colour groups on the rayon pool when `parallel`.
    FiniteDifference {
        /// Evaluate colour groups in parallel.
        parallel: bool,
    },
}

/// Options of the integrator. Tolerances apply to the local error of one
/// step: a coordinate's error is measured against
/// `atol + rtol * |q - q_0|` (positions, relative to the initial state) or
/// `atol + rtol * |v|` (velocities). Multipliers are not in the error test.
#[derive(Debug, Clone, PartialEq)]
pub struct IntegratorOptions {
    /// Relative tolerance [-].
    pub rtol: f64,
    /// Absolute tolerance of translations \[m\].
    pub atol_translation: f64,
    /// Absolute tolerance of rotations \[rad\].
    pub atol_rotation: f64,
    /// Absolute tolerance of translational velocities [m/s].
    pub atol_velocity: f64,
    /// Absolute tolerance of angular velocities [rad/s].
    pub atol_angular_velocity: f64,
    /// First step size tried \[s\].
    pub h_initial: f64,
    /// Largest step size \[s\].
    pub h_max: f64,
    /// Smallest step size before the run is abandoned \[s\].
    pub h_min: f64,
    /// Largest number of steps (accepted and rejected) per run.
    pub max_steps: u64,
    /// Newton iterations per step before the step is rejected.
    pub max_newton: u32,
    /// Newton stops when its estimated remaining error is below this
    /// fraction of the error tolerance (RADAU5's `FNEWT`). `None`: RADAU5's
    /// default `min(0.03, sqrt(rtol'))` with its internal
    /// `rtol' = 0.1 rtol^(2/3)` (3.2e-3 at rtol = 1e-6). The expansion-joint
    /// runs use 0.2 (see `quakejoint_model::run::integrator_options`).
    pub newton_tolerance: Option<f64>,
    /// Keep the Jacobian while Newton contracts faster than this rate
    /// (RADAU5's `THET`; Hairer and Wanner suggest 0.001 for cheap Jacobians
    /// and larger values when a new Jacobian and factorisation cost much
    /// more than an iteration). The expansion-joint runs use 0.2.
    pub jacobian_reuse: f64,
    /// Largest |g| and |G v + g_t| accepted after a step; larger values are
    /// projected away [m, rad, m/s, rad/s].
    pub constraint_tolerance: f64,
    /// Largest |g| of the given initial positions that is silently projected [m, rad].
    pub initial_tolerance: f64,
    /// Consecutive failed attempts at one time before the run ends.
    pub max_failures: u32,
    /// Wall-clock limit of a run \[s\] (None: no limit).
    pub max_wall_time: Option<f64>,
    /// Sparse LU used for the iteration matrices.
    pub linear_solver: LinearSolver,
    /// Analytic or finite-difference Jacobian.
    pub jacobian: JacobianMode,
    /// Solve each friction element whose slider runs on a line of its base
    /// locally at every Newton iteration, with the law's zone slope in the
    /// iteration matrix (see [`radau5`]; analytic Jacobian only).
    pub local_friction: bool,
}

impl IntegratorOptions {
    /// Checks that every option is in its admissible range.
    pub fn validate(&self) -> Result<(), BuildError> {
        let what = "integrator options";
        let bad = |name: &'static str, value: f64, reason: &'static str| {
            Err(BuildError::InvalidParameter { what: what.to_string(), name, value, reason })
        };
        for (name, value) in [
            ("rtol", self.rtol),
            ("atol_translation", self.atol_translation),
            ("atol_rotation", self.atol_rotation),
            ("atol_velocity", self.atol_velocity),
            ("atol_angular_velocity", self.atol_angular_velocity),
            ("h_initial", self.h_initial),
            ("h_min", self.h_min),
            ("initial_tolerance", self.initial_tolerance),
            ("constraint_tolerance", self.constraint_tolerance),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return bad(name, value, "must be positive and finite");
            }
        }
        if let Some(t) = self.newton_tolerance {
            if !(t.is_finite() && t > 0.0 && t < 1.0) {
                return bad("newton_tolerance", t, "must be above 0 and below 1");
            }
        }
        if self.h_max.is_nan() || self.h_max <= 0.0 {
            return bad("h_max", self.h_max, "must be positive (infinite for no limit)");
        }
        if self.rtol >= 1.0 {
            return bad("rtol", self.rtol, "must be below 1");
        }
        if !(self.jacobian_reuse.is_finite() && self.jacobian_reuse < 1.0) {
            return bad("jacobian_reuse", self.jacobian_reuse, "must be below 1");
        }
        if self.max_newton < 2 {
            return bad("max_newton", self.max_newton as f64, "must be at least 2");
        }
        if let Some(w) = self.max_wall_time {
            if w.is_nan() || w < 0.0 {
                return bad("max_wall_time", w, "must not be negative");
            }
        }
        Ok(())
    }
}

impl Default for IntegratorOptions {
    fn default() -> Self {
        Self {
            rtol: 1e-6,
            atol_translation: 1e-6,
            atol_rotation: 1e-6,
            atol_velocity: 1e-6,
            atol_angular_velocity: 1e-6,
            h_initial: 1e-4,
            h_max: f64::INFINITY,
            h_min: 1e-12,
            max_steps: 10_000_000,
            max_newton: 7,
            jacobian_reuse: 0.05,
            newton_tolerance: None,
            constraint_tolerance: 1e-9,
            initial_tolerance: 1e-6,
            max_failures: 25,
            max_wall_time: None,
            linear_solver: LinearSolver::Block,
            jacobian: JacobianMode::Analytic,
            local_friction: true,
        }
    }
}

impl IntegratorOptions {
    /// The same options with all tolerances multiplied by `factor`.
    pub fn scaled_tolerances(&self, factor: f64) -> Self {
        let mut o = self.clone();
        o.rtol *= factor;
        o.atol_translation *= factor;
        o.atol_rotation *= factor;
        o.atol_velocity *= factor;
        o.atol_angular_velocity *= factor;
        o
    }
}

/// Counters of one run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: u64,
    /// Steps rejected by the error test.
    pub rejected: u64,
    /// Attempts abandoned because Newton failed or a matrix was singular.
    pub failed_attempts: u64,
    /// Newton iterations.
    pub newton_iterations: u64,
    /// Evaluations of the residual (forces and constraints).
    pub residual_evaluations: u64,
    /// Evaluations of the Jacobian.
    pub jacobian_evaluations: u64,
    /// Numeric factorisations of the iteration matrix pair (real and complex).
    pub factorizations: u64,
    /// Factorisations taken back instead of repeated: the step size
    /// returned to the one before with the same Jacobian.
    pub factorizations_reused: u64,
    /// Factorisations that needed the faer fallback.
    pub faer_fallbacks: u64,
    /// Linear solves (real and complex counted separately).
    pub linear_solves: u64,
    /// Projections of the accepted state onto the constraints.
    pub projections: u64,
    /// Contact onsets and releases.
    pub contact_events: u64,
    /// Steps taken again to end at a contact event.
    pub event_retries: u64,
}

/// Running energy balance of a run \[J\].
///
/// `error = (T + V) - (T0 + V0) + damping + friction + contact - applied - base - constraints`
/// is zero for the exact solution.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EnergyBalance {
    /// Kinetic plus stored energy at the start.
    pub initial: f64,
    /// Kinetic energy now.
    pub kinetic: f64,
    /// Stored energy (springs, bushings, gravity) now.
    pub potential: f64,
    /// Energy dissipated by dampers so far.
    pub damping: f64,
    /// Energy dissipated by friction so far.
    pub friction: f64,
    /// Work of applied loads so far.
    pub applied: f64,
    /// Work of the base excitation so far.
    pub base: f64,
    /// Work of rheonomic constraints (drivers) so far.
    pub constraints: f64,
    /// Energy dissipated by contacts so far: their damping, and the elastic
    /// energy a contact still stored when it opened.
    pub contact: f64,
    /// Largest |error| seen so far.
    pub max_error: f64,
    /// Largest energy scale seen so far (see [`EnergyBalance::relative_error`]).
    pub max_scale: f64,
    /// Largest |work of applied loads + base excitation + drivers| seen so far.
    pub max_input: f64,
}

impl EnergyBalance {
    /// The balance error now.
    pub fn error(&self) -> f64 {
        self.kinetic + self.potential - self.initial + self.damping + self.friction + self.contact
            - self.applied
            - self.base
            - self.constraints
    }

    /// Largest |error| over the run divided by the largest energy scale over
    /// the run, `max_t (T + |V - V0| + |W_applied| + |W_base| + |W_constraints|)`
    /// (for an earthquake run, essentially the work of the earthquake load).
    pub fn relative_error(&self) -> f64 {
        if self.max_scale > 0.0 {
            self.max_error / self.max_scale
        } else {
            0.0
        }
    }

    /// Largest |error| over the run divided by the largest total input work
    /// (applied loads, base excitation, drivers) over the run: for an
    /// earthquake run, relative to the work of the earthquake load.
    pub fn error_relative_to_input(&self) -> f64 {
        if self.max_input > 0.0 {
            self.max_error / self.max_input
        } else {
            self.relative_error()
        }
    }

    pub(crate) fn record(&mut self, potential0: f64) {
        self.max_input = self.max_input.max((self.applied + self.base + self.constraints).abs());
        let e = self.error().abs();
        self.max_error = self.max_error.max(e);
        let scale = self.kinetic
            + (self.potential - potential0).abs()
            + self.applied.abs()
            + self.base.abs()
            + self.constraints.abs();
        self.max_scale = self.max_scale.max(scale);
    }
}

/// Receives every accepted step.
pub trait Observer {
    /// Called after each accepted step; return `false` to stop the run.
    fn step(&mut self, view: &mut StepView<'_>) -> bool;
}

/// An observer that does nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoObserver;

impl Observer for NoObserver {
    fn step(&mut self, _: &mut StepView<'_>) -> bool {
        true
    }
}

/// The last accepted step, with dense output over it: the state at any time
/// within the step ([`StepView::interpolate`], [`StepView::state_at`]), at
/// requested times ([`OutputTimes`], [`StepView::sample`]) and the zeros of a
/// function of the state ([`StepView::locate_root`], [`RootTracker`]); see
/// [`dense`].
pub struct StepView<'a> {
    /// Start of the step \[s\].
    pub t_prev: f64,
    /// End of the step \[s\].
    pub t: f64,
    /// Positions at `t`.
    pub q: &'a [f64],
    /// Velocities at `t`.
    pub v: &'a [f64],
    /// Constraint multipliers at `t`.
    pub lambda: &'a [f64],
    /// The compiled system (for derived quantities).
    pub assembly: &'a Assembly,
    /// A scratch workspace for evaluations (with the contacts' modes).
    pub workspace: &'a mut Workspace,
    /// Contact onsets and releases at `t` (the end of this step).
    pub events: &'a [events::ContactEvent],
    pub(crate) dense: radau5::DenseRef<'a>,
}
