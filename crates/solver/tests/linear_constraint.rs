//! A linear constraint over three bodies, against the closed form of the
//! two-degree-of-freedom system it leaves.
//!
//! Bodies a, b and c move in x only; a and b hang on springs `ka`, `kb` to
//! the ground, and c follows them through `x_c = alpha x_a + beta x_b`
//! ([`Linear`] with the coefficients `(-alpha, -beta, 1)`). In the
//! coordinates `(x_a, x_b)` the system has the mass matrix
//! `M = [[ma + alpha^2 mc, alpha beta mc], [alpha beta mc, mb + beta^2 mc]]`
//! and the stiffness `diag(ka, kb)`; started with the velocity of one of its
//! modes it moves in that mode alone, `x(t) = phi (V / w) sin(w t)`. Every
//! body's motion, the constraint's force on c (`mc x_c''`, which c receives
//! only through the constraint) and the energy are checked against it.
//!
//! The second test is the base excitation of a modal coordinate: a body of
//! mass 1 with `base_mass` `Gamma` under a constant ground acceleration `a`
//! settles about the static displacement `-Gamma a / k` (undamped: it
//! oscillates between 0 and twice that).

use std::sync::Arc;

use quakejoint_solver::*;

const MA: f64 = 2.0;
const MB: f64 = 3.0;
const MC: f64 = 1.5;
const KA: f64 = 200.0;
const KB: f64 = 500.0;
const ALPHA: f64 = 0.7;
const BETA: f64 = -1.3;
/// The bodies' positions at rest [m].
const X0: [f64; 3] = [0.0, 1.0, 5.0];

/// The lower mode of the closed form: circular frequency [rad/s] and shape
/// `(phi_a, phi_b)` with `phi_a = 1`.
fn lower_mode() -> (f64, [f64; 2]) {
    let m = [[MA + ALPHA * ALPHA * MC, ALPHA * BETA * MC], [ALPHA * BETA * MC, MB + BETA * BETA * MC]];
    // det(K - w^2 M) = 0: a quadratic in s = w^2
    let a = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let b = -(KA * m[1][1] + KB * m[0][0]);
    let c = KA * KB;
    let s = (-b - (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
    // first row: (KA - s m00) phi_a - s m01 phi_b = 0
    let phi_b = (KA - s * m[0][0]) / (s * m[0][1]);
    (s.sqrt(), [1.0, phi_b])
}

struct Check {
    w: f64,
    amp: [f64; 3],
    coords: [usize; 3],
    eq: usize,
    err_x: f64,
    err_force: f64,
    steps: usize,
}

impl Observer for Check {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        let s = (self.w * view.t).sin();
        for ((&c, x0), amp) in self.coords.iter().zip(X0).zip(self.amp) {
            self.err_x = self.err_x.max((view.q[c] - x0 - amp * s).abs());
        }
        // the constraint's force on c is -c_c lambda = -lambda; it is c's only force
        let acc_c = -self.amp[2] * self.w * self.w * s;
        self.err_force = self.err_force.max((-view.lambda[self.eq] - MC * acc_c).abs());
        self.steps += 1;
        true
    }
}

/// Errors of a run over ten periods: (displacement / amplitude, force /
/// peak, energy drift, steps).
fn three_body_run(options: IntegratorOptions) -> (f64, f64, f64, usize) {
    let (w, phi) = lower_mode();
    let v = 0.2; // [m/s] x_a' at t = 0
    let va = [v * phi[0], v * phi[1], v * (ALPHA * phi[0] + BETA * phi[1])];
    let mut sys = System::new();
    let mut body = |name: &str, m: f64, k: usize| {
        sys.add_body(Body::new(name, m, 1.0, [X0[k], 0.0, 0.0]).only(&[Coord::X]).with_velocity([va[k], 0.0, 0.0]))
    };
    let (a, b, c) = (body("a", MA, 0), body("b", MB, 1), body("c", MC, 2));
    for (body, k, rest) in [(a, KA, X0[0]), (b, KB, X0[1])] {
        sys.add_force(ForceElement::CoordinateSpring(CoordinateSpring {
            body,
            coord: Coord::X,
            stiffness: k,
            damping: 0.0,
            rest,
        }));
    }
    let link = sys.add_constraint(Constraint::Linear(Linear {
        terms: vec![(a, Coord::X, -ALPHA), (b, Coord::X, -BETA), (c, Coord::X, 1.0)],
    }));
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let coords = [a, b, c].map(|x| asm.coordinate(x, Coord::X).unwrap());
    // its only equation
    let eq = 0;
    assert_eq!(asm.equation_constraint(eq), link.index());
    let amp = va.map(|x| x / w);
    let mut check = Check { w, amp, coords, eq, err_x: 0.0, err_force: 0.0, steps: 0 };
    let mut sim = Radau5::new(asm.clone(), options).unwrap();
    sim.run(10.0 * 2.0 * std::f64::consts::PI / w, &mut check).unwrap();
    let (g, gv) = sim.max_constraint_residuals();
    assert!(g < 1e-10 && gv < 1e-8, "constraint residuals {g:e}, {gv:e}");
    let scale = amp.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let force_scale = MC * amp[2].abs() * w * w;
    (check.err_x / scale, check.err_force / force_scale, sim.energy().relative_error(), check.steps)
}

#[test]
fn three_body_linear_constraint_moves_in_the_closed_form_mode() {
    let (x, f, e, steps) = three_body_run(IntegratorOptions::default());
    let (xt, ft, et, steps_t) = three_body_run(IntegratorOptions::default().scaled_tolerances(1e-2));
    eprintln!(
        "linear constraint over 10 periods: |x error| / amplitude {x:.1e}, |force error| / peak {f:.1e}, \
         energy drift {e:.1e} ({steps} steps); 100x tighter: {xt:.1e}, {ft:.1e}, {et:.1e} ({steps_t} steps)"
    );
    assert!(steps > 20);
    assert!(x < 2e-4 && f < 2e-4 && e < 5e-4, "at the default tolerances: {x:e}, {f:e}, {e:e}");
    // discretisation errors: they shrink with the tolerance
    assert!(xt < x / 20.0 && ft < f / 20.0 && et < e / 20.0, "100x tighter: {xt:e}, {ft:e}, {et:e}");
}

#[test]
fn base_mass_is_what_the_ground_acceleration_acts_on() {
    let (gamma, k, acc) = (40.0, 25.0, 0.5);
    let mut sys = System::new();
    let q = sys
        .add_body(Body::new("mode", 1.0, 1.0, [0.0; 3]).only(&[Coord::X]).with_base_mass([[gamma, 0.0], [0.0, 0.0]]));
    sys.add_force(ForceElement::CoordinateSpring(CoordinateSpring {
        body: q,
        coord: Coord::X,
        stiffness: k,
        damping: 0.0,
        rest: 0.0,
    }));
    sys.set_excitation(Excitation { ground_x: Some(TimeFunction::Constant(acc)), ..Default::default() });
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let x = asm.coordinate(q, Coord::X).unwrap();
    let w = k.sqrt();
    // x(t) = -(Gamma a / k) (1 - cos w t)
    let mut sim = Radau5::new(asm, IntegratorOptions::default()).unwrap();
    let stat = gamma * acc / k;
    let mut obs = Static { x, w, stat, worst: 0.0 };
    sim.run(10.0, &mut obs).unwrap();
    let worst = obs.worst;
    assert!(worst / stat < 1e-4, "error {worst:e} of the static displacement {stat:e}");
    // the earthquake's work is -Gamma a integrated over the velocity
    let e = sim.energy();
    assert!(e.relative_error() < 1e-5, "energy balance {:e}", e.relative_error());
}

struct Static {
    x: usize,
    w: f64,
    stat: f64,
    worst: f64,
}

impl Observer for Static {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        let exact = -self.stat * (1.0 - (self.w * view.t).cos());
        self.worst = self.worst.max((view.q[self.x] - exact).abs());
        true
    }
}
