//! Simple pendulum released from horizontal.
//!
//! A 1 kg point-like bob on a 1 m massless link under g = 9.81 m/s^2,
//! released from rest at 90 degrees. Its exact period is
//! `T = 4 sqrt(L/g) K(sin(theta0/2))` with `K` the complete elliptic integral
//! of the first kind (`reference::closed_form::pendulum_period`), about
//! 18 % longer than the small-angle `2 pi sqrt(L/g)`. The bob's tiny own
//! inertia lengthens the equivalent length by `I/(m L)`, accounted for.
//! The motion is conservative, so kinetic plus potential energy must stay
//! constant.

use std::f64::consts::PI;
use std::sync::Arc;

use quakejoint_solver::reference::closed_form::{pendulum_period, SignChanges, Watch};
use quakejoint_solver::reference::pendulum;
use quakejoint_solver::*;

struct Outcome {
    crossings: Vec<f64>,
    energy_error: f64,
    residuals: (f64, f64),
    steps: u64,
}

fn run(options: IntegratorOptions) -> (Outcome, f64) {
    let (l, m, g) = (1.0, 1.0, 9.81);
    let (sys, bob) = pendulum(m, l, g, PI / 2.0);
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let x = asm.coordinate(bob, Coord::X).unwrap();
    let mut sim = Radau5::new(asm.clone(), options).unwrap();
    // the bob passes the bottom where x = 0, located on the dense output
    let mut obs = SignChanges::new(&asm, Watch::Position(x), x, (0.0, sim.positions()[x]), 1e-12).unwrap();
    sim.run(10.0, &mut obs).unwrap();
    assert!(obs.error.is_none(), "dense output: {:?}", obs.error);
    let inertia = sys.body(bob).inertia;
    let l_eq = l + inertia / (m * l);
    let exact = pendulum_period(l_eq, g, PI / 2.0);
    let outcome = Outcome {
        crossings: obs.times(),
        energy_error: sim.energy().relative_error(),
        residuals: sim.max_constraint_residuals(),
        steps: sim.stats().steps,
    };
    (outcome, exact)
}

#[test]
fn pendulum_period_matches_elliptic_integral_and_energy_is_conserved() {
    let (o, exact) = run(IntegratorOptions::default());
    assert!(o.crossings.len() >= 8, "crossings: {:?}", o.crossings);
    // first crossing at T/4, then every T/2
    let first = 4.0 * o.crossings[0];
    assert!((first - exact).abs() / exact < 1e-6, "quarter period: {first} vs {exact}");
    let n = o.crossings.len();
    let period = 2.0 * (o.crossings[n - 1] - o.crossings[0]) / (n - 1) as f64;
    let rel = (period - exact).abs() / exact;
    assert!(rel < 1e-6, "period {period} vs exact {exact} (relative {rel:e})");
    assert!(o.energy_error < 1e-5, "energy drift {:e} over 10 s at default tolerances", o.energy_error);
    assert!(o.residuals.0 < 1e-8 && o.residuals.1 < 1e-8, "constraint residuals {:?}", o.residuals);

    // The drift is a discretisation error: it shrinks with the tolerance.
    let (tight, _) = run(IntegratorOptions::default().scaled_tolerances(1e-2));
    assert!(tight.energy_error < o.energy_error / 20.0, "drift {:e} -> {:e}", o.energy_error, tight.energy_error);
    assert!(tight.energy_error < 1e-7, "energy drift {:e} at 100x tighter tolerances", tight.energy_error);
    eprintln!(
        "pendulum: period relative error {rel:.1e}; energy drift {:.1e} ({} steps), tight {:.1e} ({} steps)",
        o.energy_error, o.steps, tight.energy_error, tight.steps
    );
}
