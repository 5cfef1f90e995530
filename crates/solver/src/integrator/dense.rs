//! Dense output at requested times and zeros of functions of the state.
//!
//! Every accepted step of [`crate::Radau5`] carries the collocation
//! polynomial of its positions, velocities and multipliers (Hairer and
//! Wanner IV.8's continuous output: a cubic through the step's start and its
//! three stages, shifted by the end state's projection onto the constraints,
//! so that its value at the end is the accepted state).
//! An [`Observer`](super::Observer) receives it in each [`StepView`]:
//!
//! - [`StepView::interpolate`] and [`StepView::state_at`]: the state at any
//!   time within the step (an error outside it, or for a slice of the wrong
//!   length);
//! - [`OutputTimes`]: a grid or a list of requested times, handed out step
//!   by step ([`OutputTimes::next_in`]) and evaluated by
//!   [`StepView::sample`];
//! - [`StepView::locate_root`] and [`RootTracker`]: the time at which a
//!   function of the state `g(t, q, v, lambda)` changes sign, located on the
//!   dense output by the Illinois method.
//!
//! Nothing here allocates: the caller owns the [`StateBuffer`] written into.
//!
//! Accuracy: within a step the polynomial is of order 3 in the step size (the
//! stage order of Radau IIA), at the step's end it is the integrator's
//! state. On a linear oscillator against its closed form
//! (`tests/dense_output.rs`) its error is 4 times the error at the steps'
//! ends at `rtol` 1e-6 and 14 times at 1e-9, shrinking as `rtol^(2/3)`. A
//! root is located to `tolerance` on the polynomial, so its error is that
//! tolerance plus the polynomial's error over the slope of `g`.

use super::StepView;
use crate::assembly::Assembly;
use crate::error::DenseOutputError;

/// Rounding allowance of a time against the ends of a step, in units of
/// `f64::EPSILON` times the larger |end|: a time computed differently from
/// the step's end (`k * dt` against a breakpoint) may differ in the last bits.
const TIME_ULPS: f64 = 4.0;

/// Default snap of [`OutputTimes`], relative to the smallest spacing of the
/// times [-].
pub const DEFAULT_SNAP: f64 = 1e-9;

/// Bisection steps forced into the Illinois iteration: every fourth step
/// halves the bracket, so a root is found in at most four times the
/// bisection's steps.
const BISECT_EVERY: u32 = 4;

/// Largest number of evaluations of `g` per located root.
const MAX_ITERATIONS: u32 = 400;

/// Positions, velocities and multipliers at one time: what the dense output
/// writes into (allocated once by the caller, reused at every step).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StateBuffer {
    /// Time \[s\].
    pub t: f64,
    /// Positions [m, rad], indexed as [`Assembly::coordinate`] says.
    pub q: Vec<f64>,
    /// Velocities [m/s, rad/s].
    pub v: Vec<f64>,
    /// Constraint multipliers, one per equation [N for a point or line
    /// equation, N m for an angle; a driver's in its coordinate's force unit].
    pub lambda: Vec<f64>,
}

impl StateBuffer {
    /// A buffer sized for `asm` (zeros at t = 0).
    pub fn new(asm: &Assembly) -> Self {
        let (n, m) = (asm.coordinates(), asm.equations());
        Self { t: 0.0, q: vec![0.0; n], v: vec![0.0; n], lambda: vec![0.0; m] }
    }
}

/// Requested output times, handed out to the step that reaches each of them.
///
/// Either a uniform grid `t0 + j dt` for `j = 1, 2, ...` (the start `t0`
/// itself is not in it: the state there is the integrator's before the run,
/// [`crate::Radau5::positions`] and its siblings) or a strictly increasing
/// list. A time is handed out to the first step whose end it does not exceed
/// by more than the *snap*; [`StepView::sample`] evaluates it there, and a
/// time past the end within the snap is the end (steps end on breakpoints
/// such as record samples, which are output times up to the last bits).
/// The default snap is [`DEFAULT_SNAP`] times the grid's `dt` (the list's
/// smallest spacing).
///
/// ```
/// use quakejoint_solver::OutputTimes;
/// let mut times = OutputTimes::uniform(0.0, 0.01).unwrap();
/// assert_eq!(times.peek(), Some(0.01));
/// assert!(OutputTimes::list(vec![0.2, 0.1]).is_err());
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct OutputTimes {
    times: Times,
    next: u64,
    snap: f64,
}

#[derive(Debug, Clone, PartialEq)]
enum Times {
    Uniform { t0: f64, dt: f64 },
    List(Vec<f64>),
}

/// One requested time handed out by [`OutputTimes::next_in`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputTime {
    index: u64,
    t: f64,
    snap: f64,
}

impl OutputTime {
    /// Its place in the sequence, from 0 (a uniform grid's `j - 1`).
    pub fn index(&self) -> u64 {
        self.index
    }

    /// The requested time \[s\].
    pub fn t(&self) -> f64 {
        self.t
    }
}

impl OutputTimes {
    /// The times `t0 + j dt`, `j = 1, 2, ...` \[s\]; `dt` positive and finite.
    pub fn uniform(t0: f64, dt: f64) -> Result<Self, DenseOutputError> {
        if !t0.is_finite() {
            return Err(invalid("t0", t0, "must be finite"));
        }
        if !(dt.is_finite() && dt > 0.0) {
            return Err(invalid("dt", dt, "must be positive and finite"));
        }
        Ok(Self { times: Times::Uniform { t0, dt }, next: 0, snap: DEFAULT_SNAP * dt })
    }

    /// The given times \[s\], finite and strictly increasing (may be empty).
    pub fn list(times: Vec<f64>) -> Result<Self, DenseOutputError> {
        if let Some(&t) = times.iter().find(|t| !t.is_finite()) {
            return Err(invalid("times", t, "must be finite"));
        }
        let mut gap = f64::INFINITY;
        for w in times.windows(2) {
            if w[1] <= w[0] {
                return Err(invalid("times", w[1], "must increase strictly"));
            }
            gap = gap.min(w[1] - w[0]);
        }
        let snap = if gap.is_finite() { DEFAULT_SNAP * gap } else { 0.0 };
        Ok(Self { times: Times::List(times), next: 0, snap })
    }

    /// The same times with another snap \[s\] (finite, not negative).
    pub fn with_snap(mut self, snap: f64) -> Result<Self, DenseOutputError> {
        if !(snap.is_finite() && snap >= 0.0) {
            return Err(invalid("snap", snap, "must be finite and not negative"));
        }
        self.snap = snap;
        Ok(self)
    }

    /// How far past a step's end a time still counts as its end \[s\].
    pub fn snap(&self) -> f64 {
        self.snap
    }

    /// How many times were handed out so far.
    pub fn handed_out(&self) -> u64 {
        self.next
    }

    /// The next time not yet handed out \[s\] (None once a list is used up).
    pub fn peek(&self) -> Option<f64> {
        match &self.times {
            Times::Uniform { t0, dt } => Some(t0 + (self.next + 1) as f64 * dt),
            Times::List(times) => usize::try_from(self.next).ok().and_then(|i| times.get(i)).copied(),
        }
    }

    /// The next requested time that the step of `view` reaches (at most its
    /// end plus the snap), or None; call it until None in each step.
    pub fn next_in(&mut self, view: &StepView<'_>) -> Option<OutputTime> {
        let t = self.peek()?;
        if t > view.t + self.snap {
            return None;
        }
        let index = self.next;
        self.next += 1;
        Some(OutputTime { index, t, snap: self.snap })
    }
}

/// A zero of a function of the state located within a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Root {
    /// The first time at which the function no longer has the sign it had
    /// before (within the tolerance after the zero) \[s\].
    pub t: f64,
    /// Whether the function went from negative to zero or positive.
    pub rising: bool,
}

impl StepView<'_> {
    /// The rounding allowance of a time against the step's ends \[s\].
    fn slack(&self) -> f64 {
        TIME_ULPS * f64::EPSILON * self.t_prev.abs().max(self.t.abs())
    }

    fn check_time(&self, t: f64) -> Result<(), DenseOutputError> {
        let slack = self.slack();
        if t >= self.t_prev - slack && t <= self.t + slack {
            Ok(())
        } else {
            Err(DenseOutputError::OutsideStep { t, start: self.t_prev, end: self.t })
        }
    }

    fn check_lengths(&self, q: usize, v: usize, lambda: usize) -> Result<(), DenseOutputError> {
        let (n, m) = (self.q.len(), self.lambda.len());
        for (what, len, expected) in [("q", q, n), ("v", v, n), ("lambda", lambda, m)] {
            if len != expected {
                return Err(DenseOutputError::WrongLength { what, len, expected });
            }
        }
        Ok(())
    }

    /// Positions, velocities and multipliers at `t` \[s\] from the collocation
    /// polynomial of the step. `t` must lie in `[t_prev, t]` (give or take a
    /// few units in the last place) and the slices must have the system's
    /// lengths (coordinates for `q` and `v`, constraint equations for
    /// `lambda`); otherwise nothing is written and the error says why.
    pub fn interpolate(
        &self,
        t: f64,
        q: &mut [f64],
        v: &mut [f64],
        lambda: &mut [f64],
    ) -> Result<(), DenseOutputError> {
        self.check_time(t)?;
        self.check_lengths(q.len(), v.len(), lambda.len())?;
        self.dense.eval(t, q, v, lambda);
        Ok(())
    }

    /// [`Self::interpolate`] into `state` (its time set to `t`).
    pub fn state_at(&self, t: f64, state: &mut StateBuffer) -> Result<(), DenseOutputError> {
        self.interpolate(t, &mut state.q, &mut state.v, &mut state.lambda)?;
        state.t = t;
        Ok(())
    }

    /// The state at the step's end (the integrator's own, projected onto the
    /// constraints) into `state`.
    pub fn end_state(&self, state: &mut StateBuffer) -> Result<(), DenseOutputError> {
        self.check_lengths(state.q.len(), state.v.len(), state.lambda.len())?;
        state.q.copy_from_slice(self.q);
        state.v.copy_from_slice(self.v);
        state.lambda.copy_from_slice(self.lambda);
        state.t = self.t;
        Ok(())
    }

    /// The state at a requested time handed out by [`OutputTimes::next_in`]:
    /// the step's end state ([`Self::end_state`]) at its end, the dense
    /// output ([`Self::state_at`]) at a time within the step (give or take
    /// rounding), and the end state again, with its time, at a time past the
    /// end by less than the snap.
    pub fn sample(&self, time: &OutputTime, state: &mut StateBuffer) -> Result<(), DenseOutputError> {
        if time.t == self.t {
            return self.end_state(state);
        }
        match self.state_at(time.t, state) {
            Err(DenseOutputError::OutsideStep { .. }) if time.t > self.t && time.t <= self.t + time.snap => {
                self.end_state(state)
            }
            result => result,
        }
    }

    /// The first zero of `g` within the step, if `g` has a sign at the step's
    /// start (on the dense output) and not at its end (the end state): its
    /// time to within `tolerance` \[s\] on the dense output, `state` left
    /// holding the state there. Only the ends are compared: a pair of zeros
    /// within one step is not seen, and the start's value is the
    /// polynomial's, which differs from the previous step's end state by
    /// its projection onto the constraints; over a run, [`RootTracker`]
    /// carries each step's end value over to the next step and can scan
    /// points within.
    pub fn locate_root<G>(
        &self,
        tolerance: f64,
        state: &mut StateBuffer,
        mut g: G,
    ) -> Result<Option<Root>, DenseOutputError>
    where
        G: FnMut(&StateBuffer) -> f64,
    {
        check_tolerance(tolerance)?;
        self.state_at(self.t_prev, state)?;
        let ga = g(state);
        self.end_state(state)?;
        let gb = g(state);
        let sa = sign(ga);
        if sa == 0 || sign(gb) == sa {
            return Ok(None);
        }
        let t = self.refine((self.t_prev, ga), (self.t, gb), sa, tolerance, state, &mut g)?;
        Ok(Some(Root { t, rising: sa < 0 }))
    }

    /// Evaluates `g` at `t` (the end state at the step's end).
    fn g_at<G: FnMut(&StateBuffer) -> f64>(
        &self,
        t: f64,
        state: &mut StateBuffer,
        g: &mut G,
    ) -> Result<f64, DenseOutputError> {
        if t == self.t {
            self.end_state(state)?;
        } else {
            self.state_at(t, state)?;
        }
        Ok(g(state))
    }

    /// Narrows `[a, b]`, over which `g` leaves the sign `sa`, to `tolerance`
    /// by the Illinois method (regula falsi halving the value of an end kept
    /// twice), a bisection every [`BISECT_EVERY`] steps; returns the right
    /// end (where `g` no longer has the sign `sa`) with `state` there.
    fn refine<G: FnMut(&StateBuffer) -> f64>(
        &self,
        (mut a, mut fa): (f64, f64),
        (mut b, mut fb): (f64, f64),
        sa: i8,
        tolerance: f64,
        state: &mut StateBuffer,
        g: &mut G,
    ) -> Result<f64, DenseOutputError> {
        let mut state_at_b = false;
        let mut kept = 0i8; // +1: a was replaced last, -1: b
        for k in 1..=MAX_ITERATIONS {
            if b - a <= tolerance {
                break;
            }
            let secant = b - fb * (b - a) / (fb - fa);
            let mut c = if k % BISECT_EVERY == 0 || !(secant > a && secant < b) { 0.5 * (a + b) } else { secant };
            // at least half the tolerance from either end, so that the
            // bracket closes from both sides
            c = c.max(a + 0.5 * tolerance).min(b - 0.5 * tolerance);
            if !(c > a && c < b) {
                break; // no representable time between them
            }
            let fc = self.g_at(c, state, g)?;
            if sign(fc) == sa {
                (a, fa) = (c, fc);
                if kept == 1 {
                    fb *= 0.5;
                }
                kept = 1;
                state_at_b = false;
            } else {
                (b, fb) = (c, fc);
                if kept == -1 {
                    fa *= 0.5;
                }
                kept = -1;
                state_at_b = true;
            }
        }
        if !state_at_b {
            self.g_at(b, state, g)?;
        }
        Ok(b)
    }
}

/// Locates, step after step, each time at which a function of the state
/// `g(t, q, v, lambda)` changes sign (or reaches zero): an event such as a
/// velocity reversal or a dead centre.
///
/// It keeps `g`'s value at the end of the last step searched (the
/// integrator's end state), so a zero on a step boundary is found once, and
/// it scans `samples` equal parts of each step for the first change, so up
/// to that many zeros per step are told apart. Call [`RootTracker::next`] in
/// every step until it returns None. A function that touches zero and turns
/// back is reported once, at the touch; a function that starts at zero is
/// reported from its first sign on.
///
/// ```
/// use quakejoint_solver::{DenseOutputError, RootTracker, StateBuffer, StepView};
///
/// /// In an observer's step: the times at which coordinate `x`'s velocity
/// /// changes sign within the step.
/// fn reversals(
///     view: &StepView<'_>,
///     tracker: &mut RootTracker,
///     state: &mut StateBuffer,
///     x: usize,
///     out: &mut Vec<f64>,
/// ) -> Result<(), DenseOutputError> {
///     while let Some(root) = tracker.next(view, state, |s| s.v[x])? {
///         out.push(root.t);
///     }
///     Ok(())
/// }
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct RootTracker {
    tolerance: f64,
    samples: u32,
    /// Searched up to this time \[s\] ...
    at: f64,
    /// ... where `g` had this value ...
    value: f64,
    /// ... and the last sign it had (0: none yet).
    sign: i8,
    started: bool,
}

impl RootTracker {
    /// A tracker locating zeros to `tolerance` \[s\] (positive and finite),
    /// comparing the ends of each step only.
    pub fn new(tolerance: f64) -> Result<Self, DenseOutputError> {
        check_tolerance(tolerance)?;
        Ok(Self { tolerance, samples: 1, at: f64::NAN, value: f64::NAN, sign: 0, started: false })
    }

    /// The same tracker scanning each step at `samples` equal parts (at
    /// least 1) for the first change of sign.
    pub fn with_samples(mut self, samples: u32) -> Result<Self, DenseOutputError> {
        if samples == 0 {
            return Err(invalid("samples", 0.0, "must be at least 1"));
        }
        self.samples = samples;
        Ok(self)
    }

    /// Seeds the tracker with `g`'s value `g0` at the run's start `t0` \[s\]
    /// (the initial state); without it the first step's dense output at its
    /// start is used.
    pub fn start(&mut self, t0: f64, g0: f64) {
        self.at = t0;
        self.value = g0;
        let s = sign(g0);
        self.sign = s;
        self.started = true;
    }

    /// The next zero of `g` in the step of `view` after the last one
    /// found, with `state` left holding the state there; None once the step
    /// is searched to its end.
    pub fn next<G>(
        &mut self,
        view: &StepView<'_>,
        state: &mut StateBuffer,
        mut g: G,
    ) -> Result<Option<Root>, DenseOutputError>
    where
        G: FnMut(&StateBuffer) -> f64,
    {
        if self.started && self.at >= view.t {
            // this step is searched (or the tracker is ahead of it)
            return Ok(None);
        }
        let slack = view.slack();
        let (a0, mut prev, mut prev_sign) = if self.started && self.at >= view.t_prev - slack {
            (self.at, (self.at, self.value), self.sign)
        } else {
            // a fresh start, or a step left out: from this step's start
            let v = view.g_at(view.t_prev, state, &mut g)?;
            (view.t_prev, (view.t_prev, v), sign(v))
        };
        let samples = self.samples;
        for i in 1..=samples {
            let ti = if i == samples { view.t } else { a0 + (view.t - a0) * f64::from(i) / f64::from(samples) };
            let gi = view.g_at(ti, state, &mut g)?;
            let si = sign(gi);
            if prev_sign != 0 && si != prev_sign {
                let t = view.refine(prev, (ti, gi), prev_sign, self.tolerance, state, &mut g)?;
                let after = g(state);
                (self.at, self.value, self.sign, self.started) = (t, after, sign(after), true);
                return Ok(Some(Root { t, rising: prev_sign < 0 }));
            }
            prev = (ti, gi);
            if si != 0 {
                prev_sign = si;
            }
        }
        (self.at, self.value, self.sign, self.started) = (view.t, prev.1, prev_sign, true);
        Ok(None)
    }
}

fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

fn check_tolerance(tolerance: f64) -> Result<(), DenseOutputError> {
    if tolerance.is_finite() && tolerance > 0.0 {
        Ok(())
    } else {
        Err(invalid("tolerance", tolerance, "must be positive and finite"))
    }
}

fn invalid(name: &'static str, value: f64, reason: &'static str) -> DenseOutputError {
    DenseOutputError::InvalidArgument { name, value, reason }
}
