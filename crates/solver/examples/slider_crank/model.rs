//! A slider-crank with a friction bearing, built from scratch through the
//! solver's public API, and its independent solution. Shared by the example
//! (`main.rs`) and its test (`crates/solver/tests/slider_crank.rs`).
//!
//! The mechanism lies in a horizontal plane (no gravity): a crank of radius
//! `r` turning about the origin (a flywheel, its centre of mass on the
//! pivot), a connecting rod of length `l` from the crank pin to a slider on
//! the x axis, and a bearing pressing the slider with a normal force (Coulomb
//! friction `mu N`, regularised below `v_eps`). A motor drives the crank with
//! the torque `T0 - c omega` (a straight torque-speed line), released from
//! rest at the crank angle `theta0`.
//!
//! The solver sees 3 bodies, 9 coordinates, 8 constraint equations (three
//! revolutes and a prismatic joint). The independent solution is the single
//! degree of freedom `theta`: with the slider at `x(theta) = r cos(theta) +
//! sqrt(l^2 - r^2 sin^2(theta))`, the rod at the angle `beta(theta) =
//! asin(-r sin(theta) / l)` and its centre of mass midway, the kinetic
//! energy is `J(theta) theta'^2 / 2` with
//! `J = I_crank + m_rod |G'|^2 + I_rod beta'^2 + m_slider x'^2` (primes:
//! derivatives with respect to `theta`), and Lagrange's equation is
//!
//! ```text
//! J theta'' + J'/2 theta'^2 = T0 - c theta' - mu N phi(x' theta') x'
//! ```
//!
//! with the friction law `phi(v) = v / max(|v|, v_eps)` (the solver's linear
//! law). It is integrated here with the classical fourth-order Runge-Kutta
//! method at a fixed small step, its derivatives of `J` written out by hand;
//! the dead centres (the slider's velocity reversals, `theta = k pi`) are
//! located on its cubic Hermite interpolant, the friction and motor losses
//! integrated along.

use std::error::Error;
use std::f64::consts::PI;
use std::sync::Arc;

use quakejoint_solver::{
    AppliedLoad, Assembly, AssemblyOptions, Body, BodyId, Constraint, Coord, CoordinateSpring, DenseOutputError,
    EnergyBalance, ForceElement, Friction, FrictionLaw, IntegratorOptions, Observer, OutputTimes, Prismatic, Radau5,
    Revolute, RootTracker, StateBuffer, Stats, StepView, System, TimeFunction,
};

/// The mechanism's parameters (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SliderCrank {
    /// Crank radius [m].
    pub r: f64,
    /// Connecting rod length [m] (more than `r`).
    pub l: f64,
    /// Crank (flywheel) mass [kg], its centre on the pivot.
    pub crank_mass: f64,
    /// Crank inertia about the pivot [kg m^2].
    pub crank_inertia: f64,
    /// Rod mass [kg].
    pub rod_mass: f64,
    /// Rod inertia about its centre of mass [kg m^2].
    pub rod_inertia: f64,
    /// Slider mass [kg].
    pub slider_mass: f64,
    /// Motor torque at standstill [N m].
    pub torque: f64,
    /// Motor torque lost per unit of crank speed [N m s].
    pub motor_damping: f64,
    /// Bearing friction coefficient [-].
    pub mu: f64,
    /// Bearing normal force [N].
    pub normal_force: f64,
    /// Friction regularisation speed [m/s].
    pub v_eps: f64,
    /// Friction law.
    pub law: FrictionLaw,
    /// Initial crank angle [rad] (at rest).
    pub theta0: f64,
}

impl Default for SliderCrank {
    fn default() -> Self {
        let (l, rod_mass) = (0.3, 0.6);
        Self {
            r: 0.1,
            l,
            crank_mass: 2.0,
            crank_inertia: 0.05,
            rod_mass,
            rod_inertia: rod_mass * l * l / 12.0,
            slider_mass: 1.0,
            torque: 3.0,
            motor_damping: 0.1,
            mu: 0.2,
            normal_force: 50.0,
            v_eps: 1e-3,
            law: FrictionLaw::Linear,
            theta0: 0.5,
        }
    }
}

/// The bodies of the built system.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bodies {
    /// The crank.
    pub crank: BodyId,
    /// The connecting rod.
    pub rod: BodyId,
    /// The slider.
    pub slider: BodyId,
}

/// The solver's state at one output time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Time [s].
    pub t: f64,
    /// Crank angle [rad].
    pub theta: f64,
    /// Crank speed [rad/s].
    pub omega: f64,
    /// Slider position [m].
    pub x: f64,
    /// Rod angle [rad].
    pub beta: f64,
}

/// What the solver's run gives.
#[derive(Debug, Clone)]
pub struct Run {
    /// The state at every output time.
    pub samples: Vec<Sample>,
    /// The slider's velocity reversals located on the dense output: time
    /// [s] and crank angle [rad] there.
    pub reversals: Vec<(f64, f64)>,
    /// The run's energy balance [J].
    pub energy: EnergyBalance,
    /// The integrator's counters.
    pub stats: Stats,
}

/// The independent solution at the same output times.
#[derive(Debug, Clone, Default)]
pub struct Reference {
    /// Crank angle [rad] and speed [rad/s] at each output time.
    pub samples: Vec<(f64, f64)>,
    /// Times at which the crank passes `k pi` (the dead centres) [s].
    pub dead_centres: Vec<f64>,
    /// Energy dissipated by the bearing up to the end [J].
    pub friction_work: f64,
    /// Energy lost to the motor's speed-proportional torque [J].
    pub motor_loss: f64,
}

impl SliderCrank {
    fn trig(&self, theta: f64) -> (f64, f64, f64) {
        let (s, c) = theta.sin_cos();
        (s, c, (self.l * self.l - self.r * self.r * s * s).sqrt())
    }

    /// The slider's position at the crank angle `theta` [m].
    pub fn slider_x(&self, theta: f64) -> f64 {
        let (_, c, d) = self.trig(theta);
        self.r * c + d
    }

    /// The rod's angle at the crank angle `theta` [rad].
    pub fn rod_angle(&self, theta: f64) -> f64 {
        let (s, _, d) = self.trig(theta);
        (-self.r * s).atan2(d)
    }

    /// `x'(theta)` [m/rad]: the slider's speed per unit crank speed.
    pub fn slider_rate(&self, theta: f64) -> f64 {
        let (s, c, d) = self.trig(theta);
        -self.r * s - self.r * self.r * s * c / d
    }

    /// `J(theta)` [kg m^2] and `J'(theta) / 2` [kg m^2/rad].
    pub fn inertia(&self, theta: f64) -> (f64, f64) {
        let (r, (s, c, d)) = (self.r, self.trig(theta));
        let x1 = -r * s - r * r * s * c / d;
        let x2 = -r * c - r * r * (c * c - s * s) / d - r.powi(4) * s * s * c * c / d.powi(3);
        let b1 = -r * c / d;
        let b2 = r * s / d - r.powi(3) * s * c * c / d.powi(3);
        let (gx1, gy1) = (0.5 * (-r * s + x1), 0.5 * r * c);
        let (gx2, gy2) = (0.5 * (-r * c + x2), -0.5 * r * s);
        let j = self.crank_inertia
            + self.rod_mass * (gx1 * gx1 + gy1 * gy1)
            + self.rod_inertia * b1 * b1
            + self.slider_mass * x1 * x1;
        let half_dj = self.rod_mass * (gx1 * gx2 + gy1 * gy2) + self.rod_inertia * b1 * b2 + self.slider_mass * x1 * x2;
        (j, half_dj)
    }

    /// Kinetic energy of the mechanism [J].
    pub fn kinetic_energy(&self, theta: f64, omega: f64) -> f64 {
        0.5 * self.inertia(theta).0 * omega * omega
    }

    /// The bearing's friction force on the slider moving at `v` [N].
    fn friction(&self, v: f64) -> f64 {
        let scale = match self.law {
            FrictionLaw::Linear => v.abs().max(self.v_eps),
            FrictionLaw::Smooth => v.hypot(self.v_eps),
        };
        -self.mu * self.normal_force * v / scale
    }

    /// `theta''` of the reduced equation [rad/s^2], and the power dissipated
    /// by the bearing and by the motor's damping [W].
    fn rates(&self, theta: f64, omega: f64) -> (f64, f64, f64) {
        let (j, half_dj) = self.inertia(theta);
        let x1 = self.slider_rate(theta);
        let f = self.friction(x1 * omega);
        let alpha = (self.torque - self.motor_damping * omega + f * x1 - half_dj * omega * omega) / j;
        (alpha, -f * x1 * omega, self.motor_damping * omega * omega)
    }

    /// The classical Runge-Kutta method on `(theta, omega, friction work,
    /// motor loss)` with the step `h` [s] to `t_end`, the state kept at every
    /// multiple of `out_dt` (a multiple of `h`) after the start.
    pub fn runge_kutta(&self, t_end: f64, h: f64, out_dt: f64) -> Reference {
        let f = |y: [f64; 4]| {
            let (a, pf, pc) = self.rates(y[0], y[1]);
            [y[1], a, pf, pc]
        };
        let per_output = (out_dt / h).round() as usize;
        let steps = (t_end / h).round() as usize;
        let mut y = [self.theta0, 0.0, 0.0, 0.0];
        let mut out = Reference::default();
        let mut next_centre = (self.theta0 / PI).floor() + 1.0;
        for i in 0..steps {
            let k1 = f(y);
            let k2 = f(std::array::from_fn(|k| y[k] + 0.5 * h * k1[k]));
            let k3 = f(std::array::from_fn(|k| y[k] + 0.5 * h * k2[k]));
            let k4 = f(std::array::from_fn(|k| y[k] + h * k3[k]));
            let y1: [f64; 4] = std::array::from_fn(|k| y[k] + h / 6.0 * (k1[k] + 2.0 * k2[k] + 2.0 * k3[k] + k4[k]));
            // a dead centre in this step: on the cubic Hermite interpolant
            while y1[0] >= next_centre * PI {
                let t0 = i as f64 * h;
                let target = next_centre * PI;
                let hermite = |s: f64| {
                    let (s2, s3) = (s * s, s * s * s);
                    (2.0 * s3 - 3.0 * s2 + 1.0) * y[0]
                        + (s3 - 2.0 * s2 + s) * h * y[1]
                        + (-2.0 * s3 + 3.0 * s2) * y1[0]
                        + (s3 - s2) * h * y1[1]
                        - target
                };
                let (mut a, mut b) = (0.0, 1.0);
                for _ in 0..60 {
                    let m = 0.5 * (a + b);
                    if hermite(m) < 0.0 {
                        a = m;
                    } else {
                        b = m;
                    }
                }
                out.dead_centres.push(t0 + 0.5 * (a + b) * h);
                next_centre += 1.0;
            }
            y = y1;
            if (i + 1) % per_output == 0 {
                out.samples.push((y[0], y[1]));
            }
        }
        (out.friction_work, out.motor_loss) = (y[2], y[3]);
        out
    }

    /// The mechanism as a solver system: bodies in their closed-form
    /// positions at `theta0`, at rest.
    pub fn system(&self) -> (System, Bodies) {
        let (r, l, theta0) = (self.r, self.l, self.theta0);
        let mut sys = System::new();
        let crank = sys.add_body(Body::new("crank", self.crank_mass, self.crank_inertia, [0.0, 0.0, theta0]));
        let (pin_x, pin_y) = (r * theta0.cos(), r * theta0.sin());
        let xb = self.slider_x(theta0);
        let rod = sys.add_body(Body::new(
            "rod",
            self.rod_mass,
            self.rod_inertia,
            [0.5 * (pin_x + xb), 0.5 * pin_y, self.rod_angle(theta0)],
        ));
        let slider = sys.add_body(Body::new("slider", self.slider_mass, 0.01, [xb, 0.0, 0.0]));
        let pin =
            |body_a, point_a, body_b, point_b| Constraint::Revolute(Revolute { body_a, point_a, body_b, point_b });
        sys.add_constraint_named("main bearing", pin(crank, [0.0, 0.0], BodyId::GROUND, [0.0, 0.0]));
        sys.add_constraint_named("crank pin", pin(crank, [r, 0.0], rod, [-0.5 * l, 0.0]));
        sys.add_constraint_named("gudgeon pin", pin(rod, [0.5 * l, 0.0], slider, [0.0, 0.0]));
        sys.add_constraint_named(
            "slideway",
            Constraint::Prismatic(Prismatic {
                slider,
                point: [0.0, 0.0],
                base: BodyId::GROUND,
                axis_point: [0.0, 0.0],
                axis_direction: [1.0, 0.0],
            }),
        );
        sys.add_force_named(
            "bearing friction",
            ForceElement::Friction(Friction {
                slider,
                point: [0.0, 0.0],
                base: BodyId::GROUND,
                mu: self.mu,
                normal_force: self.normal_force,
                surfaces: 1.0,
                v_eps: self.v_eps,
                law: self.law,
            }),
        );
        sys.add_force_named(
            "motor",
            ForceElement::AppliedLoad(AppliedLoad {
                body: crank,
                point: [0.0, 0.0],
                fx: TimeFunction::Constant(0.0),
                fy: TimeFunction::Constant(0.0),
                torque: TimeFunction::Constant(self.torque),
            }),
        );
        sys.add_force_named(
            "motor losses",
            ForceElement::CoordinateSpring(CoordinateSpring {
                body: crank,
                coord: Coord::Phi,
                stiffness: 0.0,
                damping: self.motor_damping,
                rest: 0.0,
            }),
        );
        (sys, Bodies { crank, rod, slider })
    }

    /// The integrator options of the example: tolerances 1e-9, and the
    /// bearing's friction in the global Newton iteration rather than solved
    /// locally. The local solve ([`IntegratorOptions::local_friction`])
    /// serves a slider held along its line by force elements, as the
    /// expansion joint's bearings are, free to stick while the rest moves;
    /// this slider is carried by the rod, and with the local solve the run
    /// takes about 9 000 steps and 14 000 failed Newton attempts (at
    /// tolerances 1e-8) instead of 535 steps and 27.
    pub fn options() -> IntegratorOptions {
        IntegratorOptions { local_friction: false, ..IntegratorOptions::default().scaled_tolerances(1e-3) }
    }

    /// Runs the solver to `t_end` [s], the state every `out_dt` [s] on the
    /// dense output, the slider's velocity reversals located to 1e-12 s.
    pub fn simulate(&self, options: IntegratorOptions, t_end: f64, out_dt: f64) -> Result<Run, Box<dyn Error>> {
        let (sys, bodies) = self.system();
        let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default())?);
        let coordinate = |body, coord| asm.coordinate(body, coord).ok_or("a coordinate is missing");
        let mut watch = Watch {
            theta: coordinate(bodies.crank, Coord::Phi)?,
            x: coordinate(bodies.slider, Coord::X)?,
            beta: coordinate(bodies.rod, Coord::Phi)?,
            times: OutputTimes::uniform(0.0, out_dt)?,
            reversals: RootTracker::new(1e-12)?,
            state: StateBuffer::new(&asm),
            run: Vec::new(),
            found: Vec::new(),
            error: None,
        };
        // released from rest: the slider's velocity has no sign yet
        watch.reversals.start(0.0, 0.0);
        let mut sim = Radau5::new(asm, options)?;
        let done = sim.run(t_end, &mut watch)?;
        if let Some(e) = watch.error {
            return Err(e.into());
        }
        if !done {
            return Err("the run stopped early".into());
        }
        Ok(Run { samples: watch.run, reversals: watch.found, energy: *sim.energy(), stats: sim.stats() })
    }
}

/// The observer: samples at the output times, reversals as events.
struct Watch {
    theta: usize,
    x: usize,
    beta: usize,
    times: OutputTimes,
    reversals: RootTracker,
    state: StateBuffer,
    run: Vec<Sample>,
    found: Vec<(f64, f64)>,
    error: Option<DenseOutputError>,
}

impl Watch {
    fn record(&mut self, view: &StepView<'_>) -> Result<(), DenseOutputError> {
        while let Some(t) = self.times.next_in(view) {
            view.sample(&t, &mut self.state)?;
            let (q, v) = (&self.state.q, &self.state.v);
            let (theta, x, beta) = (self.theta, self.x, self.beta);
            self.run.push(Sample { t: t.t(), theta: q[theta], omega: v[theta], x: q[x], beta: q[beta] });
        }
        let x = self.x;
        while let Some(root) = self.reversals.next(view, &mut self.state, |s| s.v[x])? {
            self.found.push((root.t, self.state.q[self.theta]));
        }
        Ok(())
    }
}

impl Observer for Watch {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        match self.record(view) {
            Ok(()) => true,
            Err(e) => {
                self.error = Some(e);
                false
            }
        }
    }
}
