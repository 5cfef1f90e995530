//! A single-DOF oscillator (a bridge deck on its piers) pounding against a
//! rigid stop (the abutment) under a harmonic ground motion, against a
//! second method written here apart from the solver.
//!
//! The second method integrates `m x'' + c x' + k x + F(x - gap, x') = -m
//! a_g(t)` (F only while the contact is closed) with the classical
//! fourth-order Runge-Kutta method at 2 microseconds, locating every onset
//! (penetration rising through zero with the law pushing) and release
//! (penetration or force falling through zero) by bisection on the step
//! length to 1e-13 s, as an ODE solver with event location does (scipy's
//! `solve_ivp` with `events`). Its ground acceleration is the same
//! piecewise-linear signal the solver gets. The deck: 1e5 kg, T = 0.5 s, 5 %
//! damping, 10 mm from the stop, under 4 m/s^2 at 0.7 s for 3 s: about a
//! dozen impacts.
//!
//! Both must agree on the number of impacts and their times (1e-6 s), the
//! peak contact force (1e-4) and the displacement at every millisecond
//! (1e-7 m), for the linear and the Hertz law; and the solver's energy
//! balance, with the contact's dissipation, closes to 1e-6 of the
//! earthquake's work.

use std::f64::consts::PI;
use std::sync::Arc;

use quakejoint_solver::reference::contact::PoundingOscillator;
use quakejoint_solver::*;

const DT: f64 = 1e-3;
const DURATION: f64 = 3.0;

fn ground() -> (Vec<f64>, TimeSeries) {
    let n = (DURATION / DT).round() as usize + 1;
    let a: Vec<f64> = (0..n).map(|i| 4.0 * (2.0 * PI * i as f64 * DT / 0.7).sin()).collect();
    (a.clone(), TimeSeries::uniform(0.0, DT, a).unwrap())
}

fn deck(law: ContactLaw) -> PoundingOscillator {
    PoundingOscillator { mass: 1e5, period: 0.5, damping: 0.05, gap: 0.01, law }
}

/// The contact law as the second method evaluates it: force at
/// penetration `d` and rate `v`, approach speed `v0` at onset.
fn law_force(law: ContactLaw, mass: f64, d: f64, v: f64, v0: f64) -> f64 {
    match law {
        ContactLaw::Linear { stiffness, restitution } => {
            let l = restitution.ln();
            let zeta = -l / (PI * PI + l * l).sqrt();
            stiffness * d + 2.0 * zeta * (stiffness * mass).sqrt() * v
        }
        ContactLaw::Hertz { stiffness, restitution, damping } => {
            let big_d = damping.factor(restitution) / v0.max(MIN_APPROACH_SPEED);
            stiffness * d.signum() * d.abs().powf(1.5) * (1.0 + big_d * v)
        }
    }
}

/// What both methods report.
#[derive(Debug, Default)]
struct Trace {
    /// x at every millisecond [m].
    x: Vec<f64>,
    /// Contact force at every millisecond [N].
    force: Vec<f64>,
    /// Onset times [s].
    onsets: Vec<f64>,
}

/// The second method.
fn runge_kutta(p: &PoundingOscillator, ag: &[f64]) -> Trace {
    let w = 2.0 * PI / p.period;
    let (k, c) = (p.mass * w * w, 2.0 * p.damping * p.mass * w);
    let ground = |t: f64| {
        let s = t / DT;
        let i = (s.floor() as usize).min(ag.len() - 2);
        let f = s - i as f64;
        ag[i] + f * (ag[i + 1] - ag[i])
    };
    let contact = |x: f64, v: f64, v0: f64| law_force(p.law, p.mass, x - p.gap, v, v0);
    let rhs = |t: f64, y: [f64; 2], closed: bool, v0: f64| {
        let f = if closed { contact(y[0], y[1], v0) } else { 0.0 };
        [y[1], (-c * y[1] - k * y[0] - f) / p.mass - ground(t)]
    };
    let step = |t: f64, y: [f64; 2], h: f64, closed: bool, v0: f64| {
        let add = |a: [f64; 2], b: [f64; 2], s: f64| [a[0] + s * b[0], a[1] + s * b[1]];
        let k1 = rhs(t, y, closed, v0);
        let k2 = rhs(t + 0.5 * h, add(y, k1, 0.5 * h), closed, v0);
        let k3 = rhs(t + 0.5 * h, add(y, k2, 0.5 * h), closed, v0);
        let k4 = rhs(t + h, add(y, k3, h), closed, v0);
        [
            y[0] + h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]),
            y[1] + h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]),
        ]
    };
    // the mode is wrong at y: an open contact penetrating with the law
    // pushing, a closed one no longer penetrating or pulling
    let wrong = |y: [f64; 2], closed: bool, v0: f64| {
        let d = y[0] - p.gap;
        let f = contact(y[0], y[1], v0);
        if closed {
            d < 0.0 || f < 0.0
        } else {
            d > 0.0 && f > 0.0
        }
    };
    let h: f64 = 2e-6;
    let (mut t, mut y, mut closed, mut v0) = (0.0, [0.0, 0.0], false, 0.0);
    let mut trace = Trace { x: vec![0.0], force: vec![0.0], onsets: Vec::new() };
    let mut next_out = 1usize;
    while t < DURATION - 1e-12 {
        // steps end at every output time, where the ground's slope changes
        let h = h.min(next_out as f64 * DT - t);
        let mut y1 = step(t, y, h, closed, if closed { v0 } else { y[1].max(0.0) });
        let mut taken = h;
        if wrong(y1, closed, if closed { v0 } else { y1[1].max(0.0) }) {
            let (mut lo, mut hi) = (0.0, h);
            while hi - lo > 1e-13 {
                let mid = 0.5 * (lo + hi);
                let ym = step(t, y, mid, closed, if closed { v0 } else { y[1].max(0.0) });
                if wrong(ym, closed, if closed { v0 } else { ym[1].max(0.0) }) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            taken = hi;
            y1 = step(t, y, hi, closed, if closed { v0 } else { y[1].max(0.0) });
            closed = !closed;
            if closed {
                v0 = y1[1];
                trace.onsets.push(t + hi);
            }
        }
        t += taken;
        y = y1;
        if (t - next_out as f64 * DT).abs() < 1e-12 {
            trace.x.push(y[0]);
            trace.force.push(if closed { contact(y[0], y[1], v0) } else { 0.0 });
            next_out += 1;
        }
    }
    trace
}

/// The solver's trace at the same times (the dense output at every
/// millisecond after the start).
struct Sampler {
    x: usize,
    times: OutputTimes,
    state: StateBuffer,
    trace: Trace,
    contacts: Vec<ContactValue>,
}

impl Sampler {
    /// The trace's entry at a state.
    fn record(&mut self, asm: &Assembly, ws: &mut Workspace) {
        asm.contacts(ws, &self.state.q, &self.state.v, &mut self.contacts);
        self.trace.x.push(self.state.q[self.x]);
        self.trace.force.push(if self.contacts[0].closed { self.contacts[0].force } else { 0.0 });
    }
}

impl Observer for Sampler {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        for e in view.events {
            if let ContactEventKind::Onset { .. } = e.kind {
                self.trace.onsets.push(e.time);
            }
        }
        while let Some(t) = self.times.next_in(view) {
            view.sample(&t, &mut self.state).unwrap();
            self.record(view.assembly, view.workspace);
        }
        true
    }
}

fn compare(law: ContactLaw) {
    let p = deck(law);
    let (ag, series) = ground();
    let (sys, body) = p.system(series);
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let x = asm.coordinate(body, Coord::X).unwrap();
    let options =
        IntegratorOptions { rtol: 1e-9, atol_translation: 1e-12, atol_velocity: 1e-10, ..IntegratorOptions::default() };
    let mut sim = Radau5::new(asm.clone(), options).unwrap();
    let mut obs = Sampler {
        x,
        times: OutputTimes::uniform(0.0, DT).unwrap(),
        state: StateBuffer::new(&asm),
        trace: Trace::default(),
        contacts: vec![ContactValue::default(); 1],
    };
    // the first entry: the initial state
    obs.state.q.copy_from_slice(sim.positions());
    obs.state.v.copy_from_slice(sim.velocities());
    obs.record(&asm, &mut asm.workspace());
    assert!(sim.run(DURATION, &mut obs).unwrap());
    let solver = obs.trace;
    let reference = runge_kutta(&p, &ag);
    eprintln!("{law:?}: {} impacts, at {:?}", reference.onsets.len(), reference.onsets);
    assert!(reference.onsets.len() >= 5, "the deck pounds: {:?}", reference.onsets);
    assert_eq!(solver.onsets.len(), reference.onsets.len(), "{:?} vs {:?}", solver.onsets, reference.onsets);
    for (a, b) in solver.onsets.iter().zip(&reference.onsets) {
        assert!((a - b).abs() < 1e-6, "impact at {a} s against {b} s");
    }
    assert_eq!(solver.x.len(), reference.x.len());
    let dx = solver.x.iter().zip(&reference.x).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    let peak = |f: &[f64]| f.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let (fs, fr) = (peak(&solver.force), peak(&reference.force));
    eprintln!("{law:?}: largest difference of x {dx:.2e} m, peak force {fs:.6e} N against {fr:.6e} N");
    assert!(dx < 1e-7, "displacements differ by {dx} m");
    assert!((fs / fr - 1.0).abs() < 1e-4, "peak contact force {fs} N against {fr} N");
    let e = sim.energy();
    assert!(e.contact > 0.0, "the impacts dissipate");
    assert!(e.error_relative_to_input() < 1e-6, "energy balance error {:e}", e.error_relative_to_input());
}

#[test]
fn a_deck_pounding_on_its_abutment_matches_a_second_method_with_a_linear_contact() {
    compare(ContactLaw::Linear { stiffness: 1e9, restitution: 0.65 });
}

#[test]
fn a_deck_pounding_on_its_abutment_matches_a_second_method_with_a_hertz_contact() {
    compare(ContactLaw::Hertz { stiffness: 1e10, restitution: 0.65, damping: HertzDamping::YeLiZhu });
}
