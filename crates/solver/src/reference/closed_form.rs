//! Closed forms the reference problems are checked against, and an
//! observer that finds where a coordinate or velocity changes sign on the
//! dense output (crossings, turning points). Shared by the solver's tests
//! and the verification manual (`quakejoint_model::verification`).

use std::f64::consts::PI;

use crate::assembly::Assembly;
use crate::error::DenseOutputError;
use crate::integrator::dense::{RootTracker, StateBuffer};
use crate::integrator::{Observer, StepView};

/// Complete elliptic integral of the first kind K(k), modulus `k` in
/// \[0, 1), by the arithmetic-geometric mean (Abramowitz and Stegun 17.6).
pub fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    for _ in 0..40 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    PI / (2.0 * a)
}

/// Exact period \[s\] of a simple pendulum of equivalent length `length`
/// \[m\] under gravity `g` \[m/s^2\] released from rest at `angle0` \[rad\]
/// from the downward vertical: `4 sqrt(L/g) K(sin(angle0/2))`.
pub fn pendulum_period(length: f64, g: f64, angle0: f64) -> f64 {
    4.0 * (length / g).sqrt() * elliptic_k((0.5 * angle0).sin())
}

/// The turning points \[m\] of a mass on a spring with Coulomb friction
/// released from rest at `x0` \[m\], `f_over_k` the friction force over the
/// stiffness \[m\] (Den Hartog 1931): each half cycle loses `2 F/k` of
/// amplitude, and the motion stops at the first turning point with
/// `|x| <= F/k`.
pub fn den_hartog_turning_points(x0: f64, f_over_k: f64) -> Vec<f64> {
    let mut out = Vec::new();
    let mut x = x0;
    while x.abs() > f_over_k {
        x = -(x.abs() - 2.0 * f_over_k) * x.signum();
        out.push(x);
    }
    out
}

/// What a [`SignChanges`] observer watches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Watch {
    /// The position coordinate of this index.
    Position(usize),
    /// The velocity of this index.
    Velocity(usize),
}

/// An observer that records where one coordinate or velocity changes sign,
/// located on the dense output by a [`RootTracker`], with the position of
/// the coordinate `report` there: `(time [s], position)`.
#[derive(Debug)]
pub struct SignChanges {
    watch: Watch,
    report: usize,
    tracker: RootTracker,
    state: StateBuffer,
    /// The sign changes found so far: time \[s\] and the position of the
    /// reported coordinate there.
    pub found: Vec<(f64, f64)>,
    /// The dense output's error, if one stopped the run.
    pub error: Option<DenseOutputError>,
}

impl SignChanges {
    /// Watches `watch` from the run's start `t0` \[s\] where it has value
    /// `g0`, locating each change to `tolerance` \[s\], and reports the
    /// position coordinate `report` there.
    pub fn new(
        asm: &Assembly,
        watch: Watch,
        report: usize,
        (t0, g0): (f64, f64),
        tolerance: f64,
    ) -> Result<Self, DenseOutputError> {
        let mut tracker = RootTracker::new(tolerance)?;
        tracker.start(t0, g0);
        Ok(Self { watch, report, tracker, state: StateBuffer::new(asm), found: Vec::new(), error: None })
    }

    /// The times of the sign changes \[s\].
    pub fn times(&self) -> Vec<f64> {
        self.found.iter().map(|f| f.0).collect()
    }
}

impl Observer for SignChanges {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        let (watch, report) = (self.watch, self.report);
        let g = |s: &StateBuffer| match watch {
            Watch::Position(i) => s.q[i],
            Watch::Velocity(i) => s.v[i],
        };
        loop {
            match self.tracker.next(view, &mut self.state, g) {
                Ok(Some(root)) => self.found.push((root.t, self.state.q[report])),
                Ok(None) => return true,
                Err(e) => {
                    self.error = Some(e);
                    return false;
                }
            }
        }
    }
}
