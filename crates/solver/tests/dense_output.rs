//! The dense output and the root location against closed forms, and their
//! refusals.
//!
//! A damped linear oscillator on a prismatic joint under gravity, released
//! from `x0` with speed `v0`: `x(t) = e^{-zeta w t} (x0 cos(wd t) + (v0 + zeta
//! w x0) / wd sin(wd t))`, its velocity the derivative, and the joint's
//! multipliers constant (the line carries the weight `m g`, the angle
//! nothing). Sampled at an irregular list of times and at a uniform grid
//! ([`OutputTimes`]), every value must be within a bound a few times the
//! tolerance of the run. Undamped, its zeros and turning points are at
//! `(k pi + pi/2 - phase) / w` and `(k pi - phase) / w`: the located roots
//! ([`RootTracker`], [`StepView::locate_root`]) must be there to the dense
//! output's error over the slope. Outside the step, with slices of the wrong
//! length and with bad arguments, every call returns its error and writes
//! nothing.

use std::f64::consts::PI;
use std::sync::Arc;

use quakejoint_solver::*;

const MASS: f64 = 2.0;
const OMEGA: f64 = 2.0 * PI * 1.3;
const G: f64 = 9.81;
const X0: f64 = 0.1;
const V0: f64 = 0.5;

/// The oscillator: a slider in a prismatic joint along x, a spring and a
/// damper to the ground on x, gravity in -y. Returns the system, its
/// x coordinate's body.
fn oscillator(zeta: f64) -> (System, BodyId) {
    let mut sys = System::new();
    let body = sys.add_body(Body::new("mass", MASS, 0.01, [X0, 0.0, 0.0]).with_velocity([V0, 0.0, 0.0]));
    sys.add_constraint(Constraint::Prismatic(Prismatic {
        slider: body,
        point: [0.0, 0.0],
        base: BodyId::GROUND,
        axis_point: [0.0, 0.0],
        axis_direction: [1.0, 0.0],
    }));
    sys.add_force(ForceElement::CoordinateSpring(CoordinateSpring {
        body,
        coord: Coord::X,
        stiffness: MASS * OMEGA * OMEGA,
        damping: 2.0 * zeta * MASS * OMEGA,
        rest: 0.0,
    }));
    sys.set_excitation(Excitation { gravity: [0.0, -G], ..Default::default() });
    (sys, body)
}

/// Position and velocity of the oscillator at `t` [m, m/s].
fn exact(zeta: f64, t: f64) -> (f64, f64) {
    let wd = OMEGA * (1.0 - zeta * zeta).sqrt();
    let (a, b) = (X0, (V0 + zeta * OMEGA * X0) / wd);
    let decay = (-zeta * OMEGA * t).exp();
    let (s, c) = (wd * t).sin_cos();
    let x = decay * (a * c + b * s);
    let v = decay * (-a * wd * s + b * wd * c) - zeta * OMEGA * x;
    (x, v)
}

/// Samples at requested times: the largest errors of x, v and of the
/// multipliers against their closed forms, how many samples, how many
/// fell strictly inside a step; and the largest errors of x and v at the
/// steps' ends (the integration's own).
struct Samples {
    x: usize,
    zeta: f64,
    times: OutputTimes,
    state: StateBuffer,
    count: usize,
    interior: usize,
    err_x: f64,
    err_v: f64,
    err_lambda: f64,
    end_x: f64,
    end_v: f64,
}

impl Samples {
    fn new(asm: &Assembly, x: usize, zeta: f64, times: OutputTimes) -> Self {
        let state = StateBuffer::new(asm);
        let (count, interior) = (0, 0);
        let (err_x, err_v, err_lambda, end_x, end_v) = (0.0, 0.0, 0.0, 0.0, 0.0);
        Self { x, zeta, times, state, count, interior, err_x, err_v, err_lambda, end_x, end_v }
    }
}

impl Observer for Samples {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        let (x, v) = exact(self.zeta, view.t);
        self.end_x = self.end_x.max((view.q[self.x] - x).abs());
        self.end_v = self.end_v.max((view.v[self.x] - v).abs());
        while let Some(t) = self.times.next_in(view) {
            view.sample(&t, &mut self.state).unwrap();
            let s = &self.state;
            let (x, v) = exact(self.zeta, t.t());
            self.err_x = self.err_x.max((s.q[self.x] - x).abs());
            self.err_v = self.err_v.max((s.v[self.x] - v).abs());
            // the line carries the weight, the angle nothing: |lambda| = (m g, 0)
            let mut l: Vec<f64> = s.lambda.iter().map(|l| l.abs()).collect();
            l.sort_by(f64::total_cmp);
            self.err_lambda = self.err_lambda.max(l[0]).max((l[1] - MASS * G).abs() / (MASS * G));
            self.count += 1;
            self.interior += usize::from(t.t() < view.t);
        }
        true
    }
}

fn run_samples(zeta: f64, options: IntegratorOptions, times: OutputTimes, t_end: f64) -> Samples {
    let (sys, body) = oscillator(zeta);
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let x = asm.coordinate(body, Coord::X).unwrap();
    let mut obs = Samples::new(&asm, x, zeta, times);
    let mut sim = Radau5::new(asm, options.clone()).unwrap();
    assert!(sim.run(t_end, &mut obs).unwrap());
    eprintln!(
        "rtol {:.0e}: {} samples ({} inside a step), {} steps: |x error| <= {:.2e} m, |v error| <= {:.2e} m/s \
         (at the steps' ends {:.2e} m, {:.2e} m/s), lambda {:.2e}",
        options.rtol,
        obs.count,
        obs.interior,
        sim.stats().steps,
        obs.err_x,
        obs.err_v,
        obs.end_x,
        obs.end_v,
        obs.err_lambda
    );
    obs
}

#[test]
fn dense_output_of_a_linear_oscillator_matches_its_closed_form() {
    let zeta = 0.05;
    // irregular times, most of them inside steps, the end included
    let list: Vec<f64> = (1..=400).map(|k| 4.0 * (k as f64 / 400.0).powf(1.3)).collect();
    let n = list.len();
    // (measured: 2.1e-6 m and 9.0e-6 m/s at rtol 1e-6, 3.7e-8 m and 9.3e-8
    // m/s at 1e-9, about 4 and 14 times the errors at the steps' ends)
    let mut errors = Vec::new();
    for (scale, bound_x, bound_v) in [(1.0, 4e-6, 2e-5), (1e-3, 8e-8, 2e-7)] {
        let options = IntegratorOptions::default().scaled_tolerances(scale);
        let s = run_samples(zeta, options.clone(), OutputTimes::list(list.clone()).unwrap(), 4.0);
        assert_eq!(s.count, n, "every requested time is handed out once");
        assert!(s.interior > n / 2, "most requested times fall inside steps: {}", s.interior);
        assert!(s.err_x < bound_x, "rtol {:e}: x error {:e} m", options.rtol, s.err_x);
        assert!(s.err_v < bound_v, "rtol {:e}: v error {:e} m/s", options.rtol, s.err_v);
        assert!(s.err_x < 20.0 * s.end_x, "the dense output is far off the steps' own accuracy");
        assert!(s.err_lambda < 1e-9, "multipliers off by {:e}", s.err_lambda);
        errors.push(s.err_x);
        // a uniform grid: 1 ms, 4000 times after the start
        let s = run_samples(zeta, options, OutputTimes::uniform(0.0, 1e-3).unwrap(), 4.0);
        assert_eq!(s.count, 4000);
        assert!(s.err_x < bound_x && s.err_v < bound_v, "grid: {:e} m, {:e} m/s", s.err_x, s.err_v);
    }
    // an interpolant of order 3 with steps ~ rtol^(1/6): errors ~ rtol^(2/3),
    // 100 times smaller for a 1000 times tighter tolerance (measured: 56)
    assert!(errors[1] < errors[0] / 20.0, "the dense output converges: {errors:?}");
}

/// A sdof under a ground motion sampled every 10 ms: every sample is a
/// breakpoint, so every step ends on an output time and [`StepView::sample`]
/// gives the integrator's own end state there, bit for bit.
#[test]
fn output_times_on_breakpoints_are_the_step_ends_state() {
    struct EndState {
        times: OutputTimes,
        state: StateBuffer,
        at_ends: usize,
        handed: Vec<f64>,
    }
    impl Observer for EndState {
        fn step(&mut self, view: &mut StepView<'_>) -> bool {
            while let Some(t) = self.times.next_in(view) {
                view.sample(&t, &mut self.state).unwrap();
                if t.t() == view.t {
                    assert_eq!(self.state.q, view.q);
                    assert_eq!(self.state.v, view.v);
                    assert_eq!(self.state.t, view.t);
                    self.at_ends += 1;
                }
                assert_eq!(t.index() as usize, self.handed.len());
                self.handed.push(t.t());
            }
            true
        }
    }
    let dt = 0.01;
    let ground: Vec<f64> = (0..101).map(|i| (i as f64 * dt * 7.0).sin()).collect();
    let (sys, _) = reference::sdof(1.0, 0.5, 0.05, TimeSeries::uniform(0.0, dt, ground).unwrap());
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let mut obs = EndState {
        times: OutputTimes::uniform(0.0, dt).unwrap(),
        state: StateBuffer::new(&asm),
        at_ends: 0,
        handed: Vec::new(),
    };
    let mut sim = Radau5::new(asm, IntegratorOptions::default()).unwrap();
    sim.run(1.0, &mut obs).unwrap();
    assert_eq!(obs.handed.len(), 100);
    assert_eq!(obs.at_ends, 100, "each record sample ends a step");
    for (j, t) in obs.handed.iter().enumerate() {
        assert_eq!(*t, (j + 1) as f64 * dt);
    }
}

/// Zeros (x = 0) and turning points (v = 0) of the undamped oscillator.
struct Roots {
    x: usize,
    zeros: RootTracker,
    turns: RootTracker,
    state: StateBuffer,
    zero_times: Vec<Root>,
    turn_times: Vec<(f64, f64)>,
    /// What [`StepView::locate_root`] finds in each step on its own.
    single: Vec<f64>,
}

impl Observer for Roots {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        let x = self.x;
        while let Some(root) = self.zeros.next(view, &mut self.state, |s| s.q[x]).unwrap() {
            assert!(root.t >= view.t_prev && root.t <= view.t);
            assert_eq!(self.state.t, root.t, "the state is left at the root");
            self.zero_times.push(root);
        }
        while let Some(root) = self.turns.next(view, &mut self.state, |s| s.v[x]).unwrap() {
            self.turn_times.push((root.t, self.state.q[x]));
        }
        if let Some(root) = view.locate_root(1e-12, &mut self.state, |s| s.q[x]).unwrap() {
            self.single.push(root.t);
        }
        true
    }
}

#[test]
fn located_roots_match_the_closed_form_zeros_and_turning_points() {
    let (sys, body) = oscillator(0.0);
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let x = asm.coordinate(body, Coord::X).unwrap();
    let options = IntegratorOptions::default().scaled_tolerances(1e-3);
    let mut sim = Radau5::new(asm.clone(), options).unwrap();
    let tol = 1e-12;
    let (mut zeros, mut turns) = (RootTracker::new(tol).unwrap(), RootTracker::new(tol).unwrap());
    zeros.start(0.0, X0);
    turns.start(0.0, V0);
    let mut obs = Roots {
        x,
        zeros,
        turns,
        state: StateBuffer::new(&asm),
        zero_times: Vec::new(),
        turn_times: Vec::new(),
        single: Vec::new(),
    };
    let t_end = 3.0;
    sim.run(t_end, &mut obs).unwrap();
    // x = A cos(w t + phase)
    let amplitude = (X0 * X0 + (V0 / OMEGA).powi(2)).sqrt();
    let phase = (-V0 / OMEGA).atan2(X0);
    let expected_zeros: Vec<f64> =
        (0..20).map(|k| (k as f64 * PI + PI / 2.0 - phase) / OMEGA).filter(|t| *t > 0.0 && *t < t_end).collect();
    let expected_turns: Vec<f64> =
        (0..20).map(|k| (k as f64 * PI - phase) / OMEGA).filter(|t| *t > 0.0 && *t < t_end).collect();
    assert_eq!(obs.zero_times.len(), expected_zeros.len(), "{:?}", obs.zero_times);
    assert_eq!(obs.turn_times.len(), expected_turns.len());
    let mut worst_zero = 0.0f64;
    for (k, (root, t)) in obs.zero_times.iter().zip(&expected_zeros).enumerate() {
        worst_zero = worst_zero.max((root.t - t).abs());
        // cos(w t + phase) falls through its first zero
        assert_eq!(root.rising, k % 2 == 1, "direction of zero {k}");
    }
    let mut worst_turn = 0.0f64;
    let mut worst_extreme = 0.0f64;
    for ((t, xt), te) in obs.turn_times.iter().zip(&expected_turns) {
        worst_turn = worst_turn.max((t - te).abs());
        worst_extreme = worst_extreme.max((xt.abs() - amplitude).abs());
    }
    eprintln!(
        "{} zeros within {worst_zero:.2e} s, {} turning points within {worst_turn:.2e} s (|x| within {worst_extreme:.2e} \
         m of the amplitude)",
        expected_zeros.len(),
        expected_turns.len()
    );
    // the dense output is within 8e-8 m and 2e-7 m/s at this tolerance (the
    // first test): over the slopes A w = 0.8 m/s of x at a zero and A w^2 =
    // 6.7 m/s^2 of v at a turning point, within 1e-7 and 3e-8 s (measured:
    // 4.5e-10 and 7.7e-10 s, the extremes' |x| within 2.5e-8 m)
    assert!(worst_zero < 1e-8, "zeros off by {worst_zero:e} s");
    assert!(worst_turn < 1e-8, "turning points off by {worst_turn:e} s");
    assert!(worst_extreme < 8e-8, "extremes off by {worst_extreme:e} m");
    // the stateless search finds the same zeros (no zero is near a step end here)
    assert_eq!(obs.single.len(), obs.zero_times.len());
    for (a, b) in obs.single.iter().zip(&obs.zero_times) {
        assert!((a - b.t).abs() <= 2.0 * tol, "{a} against {}", b.t);
    }
}

/// Several zeros in one step: scanned at 16 parts per step, a tracker finds
/// every zero of `sin(200 t)` (not a function of the state, but of the
/// time: the tracker only sees the values) at its closed-form time.
#[test]
fn a_tracker_scanning_each_step_finds_several_zeros_per_step() {
    struct Fast {
        tracker: RootTracker,
        state: StateBuffer,
        roots: Vec<f64>,
        max_per_step: usize,
    }
    impl Observer for Fast {
        fn step(&mut self, view: &mut StepView<'_>) -> bool {
            let mut n = 0;
            while let Some(root) = self.tracker.next(view, &mut self.state, |s| (200.0 * s.t).sin()).unwrap() {
                self.roots.push(root.t);
                n += 1;
            }
            self.max_per_step = self.max_per_step.max(n);
            true
        }
    }
    let (sys, _) = oscillator(0.0);
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let mut tracker = RootTracker::new(1e-13).unwrap().with_samples(16).unwrap();
    tracker.start(0.0, 0.0);
    let mut obs = Fast { tracker, state: StateBuffer::new(&asm), roots: Vec::new(), max_per_step: 0 };
    let mut sim = Radau5::new(asm, IntegratorOptions::default()).unwrap();
    sim.run(1.0, &mut obs).unwrap();
    let expected: Vec<f64> = (1..).map(|k| k as f64 * PI / 200.0).take_while(|t| *t < 1.0).collect();
    assert!(obs.max_per_step > 1, "the steps are long enough to hold several zeros");
    assert_eq!(obs.roots.len(), expected.len(), "{:?}", obs.roots);
    for (a, b) in obs.roots.iter().zip(&expected) {
        assert!((a - b).abs() < 1e-12, "{a} against {b}");
    }
}

/// The refusals, checked on one step in the middle of a run.
#[test]
fn requests_outside_the_step_or_with_wrong_lengths_are_errors() {
    struct Refusals {
        checked: bool,
        n: usize,
        m: usize,
    }
    impl Observer for Refusals {
        fn step(&mut self, view: &mut StepView<'_>) -> bool {
            if view.t < 0.1 {
                return true;
            }
            let (n, m) = (self.n, self.m);
            let (t0, t1) = (view.t_prev, view.t);
            let h = t1 - t0;
            let (mut q, mut v, mut l) = (vec![7.0; n], vec![7.0; n], vec![7.0; m]);
            // inside, the ends included
            for t in [t0, 0.5 * (t0 + t1), t1] {
                assert!(view.interpolate(t, &mut q, &mut v, &mut l).is_ok());
            }
            // outside: before, after, far, not a number
            for t in [t0 - 1e-3 * h, t1 + 1e-3 * h, t1 + 1.0, f64::NAN] {
                let (mut q, mut v, mut l) = (vec![7.0; n], vec![7.0; n], vec![7.0; m]);
                match view.interpolate(t, &mut q, &mut v, &mut l) {
                    Err(DenseOutputError::OutsideStep { start, end, .. }) => {
                        assert_eq!((start, end), (t0, t1));
                    }
                    other => panic!("t = {t}: {other:?}"),
                }
                assert!(q.iter().chain(&v).chain(&l).all(|x| *x == 7.0), "nothing written");
            }
            // wrong lengths, each slice in turn
            let tm = 0.5 * (t0 + t1);
            let (mut q2, mut v2, mut l2) = (vec![0.0; n + 1], vec![0.0; n - 1], vec![0.0; m + 2]);
            let e = view.interpolate(tm, &mut q2, &mut v, &mut l).unwrap_err();
            assert_eq!(e, DenseOutputError::WrongLength { what: "q", len: n + 1, expected: n });
            let e = view.interpolate(tm, &mut q, &mut v2, &mut l).unwrap_err();
            assert_eq!(e, DenseOutputError::WrongLength { what: "v", len: n - 1, expected: n });
            let e = view.interpolate(tm, &mut q, &mut v, &mut l2).unwrap_err();
            assert_eq!(e, DenseOutputError::WrongLength { what: "lambda", len: m + 2, expected: m });
            assert!(e.to_string().contains("lambda has 4 entries, the system has 2"), "{e}");
            // a buffer of another system
            let mut wrong = StateBuffer { t: -1.0, q: vec![0.0; n + 3], v: vec![0.0; n], lambda: vec![0.0; m] };
            assert!(matches!(view.state_at(tm, &mut wrong), Err(DenseOutputError::WrongLength { what: "q", .. })));
            assert!(view.end_state(&mut wrong).is_err());
            assert_eq!(wrong.t, -1.0, "nothing written");
            // root location with a tolerance that is not positive
            let mut s = StateBuffer { t: 0.0, q, v, lambda: l };
            for tol in [0.0, -1.0, f64::NAN, f64::INFINITY] {
                assert!(matches!(
                    view.locate_root(tol, &mut s, |s| s.q[0]),
                    Err(DenseOutputError::InvalidArgument { name: "tolerance", .. })
                ));
            }
            // a grid started late hands out a time before the step: refused
            let mut late = OutputTimes::uniform(0.0, 1e-3).unwrap();
            let first = late.next_in(view).unwrap();
            assert!(first.t() < t0);
            assert!(matches!(view.sample(&first, &mut s), Err(DenseOutputError::OutsideStep { .. })));
            self.checked = true;
            false
        }
    }
    let (sys, _) = oscillator(0.05);
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let (n, m) = (asm.coordinates(), asm.equations());
    assert_eq!((n, m), (3, 2));
    let mut obs = Refusals { checked: false, n, m };
    let mut sim = Radau5::new(asm, IntegratorOptions::default()).unwrap();
    assert!(!sim.run(1.0, &mut obs).unwrap());
    assert!(obs.checked);
}

#[test]
fn bad_output_times_and_trackers_are_refused() {
    for dt in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
        assert!(matches!(OutputTimes::uniform(0.0, dt), Err(DenseOutputError::InvalidArgument { name: "dt", .. })));
    }
    assert!(OutputTimes::uniform(f64::NAN, 1.0).is_err());
    assert!(OutputTimes::list(vec![0.1, 0.1]).is_err(), "not strictly increasing");
    assert!(OutputTimes::list(vec![0.2, 0.1]).is_err());
    assert!(OutputTimes::list(vec![0.1, f64::NAN]).is_err());
    let e = OutputTimes::list(vec![0.1, 0.3, 0.2]).unwrap_err();
    assert_eq!(e.to_string(), "times = 0.2 is invalid (must increase strictly)");
    assert!(OutputTimes::list(Vec::new()).unwrap().peek().is_none());
    let t = OutputTimes::list(vec![0.1, 0.3, 0.35]).unwrap();
    assert!((t.snap() - 5e-11).abs() < 1e-24, "1e-9 of the smallest spacing: {}", t.snap());
    assert!(t.clone().with_snap(-1.0).is_err());
    assert!(t.clone().with_snap(f64::NAN).is_err());
    assert_eq!(t.with_snap(0.0).unwrap().snap(), 0.0);
    let u = OutputTimes::uniform(1.0, 0.25).unwrap();
    assert_eq!((u.peek(), u.snap(), u.handed_out()), (Some(1.25), 0.25e-9, 0));
    for tol in [0.0, -1e-9, f64::NAN] {
        assert!(RootTracker::new(tol).is_err());
    }
    assert!(RootTracker::new(1e-9).unwrap().with_samples(0).is_err());
}
