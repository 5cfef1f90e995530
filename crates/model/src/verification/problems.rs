//! The reference problems (module doc of [`super`]).

use std::f64::consts::PI;
use std::path::Path;
use std::sync::Arc;

use quakejoint_motion::{load_record, peaks, RecordSpec, SpectrumOptions};
use quakejoint_solver::reference::andrews::{self, Squeezer};
use quakejoint_solver::reference::closed_form::{self, SignChanges, Watch};
use quakejoint_solver::reference::contact::HeadOn;
use quakejoint_solver::reference::{self, FrictionOscillator};
use quakejoint_solver::{
    Assembly, AssemblyOptions, ContactLaw, Coord, FrictionLaw, IntegratorOptions, NoObserver, Radau5,
};

use super::{Band, Outcome, Problem};
use crate::run::RunOptions;
use crate::runspec::{Named, Overrides, Reference, RunSpec};
use crate::Config;

/// Every reference problem, in the order of the manual.
pub const PROBLEMS: &[Problem] = &[
    Problem {
        id: "pendulum-period",
        layer: "solver",
        title: "a 1 kg bob on a 1 m link (revolute joint) released from horizontal under g = 9.81 m/s^2, for 10 s",
        source: "closed form: T = 4 sqrt(L/g) K(sin(theta0/2)), K the complete elliptic integral of the first kind (Abramowitz and Stegun 17.6), L lengthened by the bob's own inertia I/(m L)",
        quantity: "period from the bottom crossings located on the dense output [s]",
        band: Band::Relative(1e-6),
        run: pendulum_period,
    },
    Problem {
        id: "coulomb-turning-points",
        layer: "solver",
        title: "a 1 kg mass on a 100 N/m spring with 1 N of friction (regularised below 1 mm/s), released at 0.105 m",
        source: "closed form: each half cycle loses 2 F/k of amplitude and the mass stops at the first turning point with |x| <= F/k (Den Hartog 1931); the regularisation shifts a turning point by about v_eps^2/a",
        quantity: "position where the mass stops, its fifth turning point located on the dense output [m]",
        band: Band::Absolute(1.5e-6),
        run: coulomb_turning_points,
    },
    Problem {
        id: "head-on-linear-contact",
        layer: "solver",
        title: "two bodies meeting head on through a linear spring-dashpot contact (k = 1e9 N/m, e = 0.65), released when its force vanishes",
        source: "closed form: a damped oscillator in the penetration released when the force vanishes, e_r = exp(-a t_r)(a/wd sin(wd t_r) - cos(wd t_r)) (Anagnostopoulos 1988)",
        quantity: "coefficient of restitution [-]",
        band: Band::Relative(1e-6),
        run: head_on_linear_contact,
    },
    Problem {
        id: "andrews-squeezer",
        layer: "solver",
        title: "Andrews' squeezing mechanism (Hairer and Wanner VII.7): 7 bodies on 10 revolute joints, a spring and a driving torque of 0.033 N m, from rest to t = 0.03 s at tolerances 1e-12",
        source: "published value: the IVP Test Set's reference solution at t = 0.03 s (Mazzia and Iavernaro, problem andrews; PSIDE at tolerances 1e-14), subroutine andsoln of rforge/bvpsolve pkg/deTestSet/src/Ex_andrews.f; its digits are themselves 1.4e-9 rad off the converged solution of their equations, which a Runge-Kutta integration of the test set's own equations confirms (crates/solver/tests/andrews_squeezer.rs)",
        quantity: "of the seven angles (beta, Theta, gamma, Phi, delta, Omega, epsilon), the one farthest from its published value [rad]",
        band: Band::Absolute(2e-9),
        run: andrews_squeezer,
    },
    Problem {
        id: "resonance-amplitude",
        layer: "motion",
        title: "a damped oscillator (T = 1 s, 5 %) driven at resonance by a sampled sine (1000 samples a cycle) until steady",
        source: "closed form: steady amplitude a0 / (2 zeta w^2) times sinc^2(w dt / 2), the sampled sine's fundamental",
        quantity: "Sd with 8 subdivisions [m]",
        band: Band::Relative(5e-7),
        run: resonance_amplitude,
    },
    Problem {
        id: "spectrum-against-rk4",
        layer: "motion",
        title: "Sa of Loma Prieta Corralitos 090 (first 20 s) at T = 1 s, 5 %",
        source: "second method: classical Runge-Kutta 4 with 1000 fixed sub-steps a sample, on the same piecewise-linear ground motion",
        quantity: "Sa [m/s^2]",
        band: Band::Relative(1e-9),
        run: spectrum_against_rk4,
    },
    Problem {
        id: "spectra-against-eqsig",
        layer: "motion",
        title: "Sa, PSa and Sd of Loma Prieta Corralitos 090 and Imperial Valley El Centro 180 at 21 periods from 0.05 to 5 s, 2 and 5 % damping (126 values each)",
        source: "another program: eqsig 1.2.17, the same exact piecewise-linear integration written apart (its 2 pi truncated to 6.2831853, which alone is 2.5e-8; tests/data/reference_spectra, scripts/reference_spectra.py)",
        quantity: "the value farthest from eqsig's, relative [-]",
        band: Band::Relative(1e-7),
        run: super::programs::spectra_against_eqsig,
    },
    Problem {
        id: "spectra-against-opensees",
        layer: "motion",
        title: "the same 252 values",
        source: "another program: OpenSees 3.7.1 (openseespy), an elastic one-mass model integrated by Newmark's average acceleration at h = 1.25e-4 s on a Path series linear between samples; its h^2 error falls by 4 per halving of h (tests/data/reference_spectra/README.md)",
        quantity: "the value farthest from OpenSees', relative [-]",
        band: Band::Relative(1e-4),
        run: super::programs::spectra_against_opensees,
    },
    Problem {
        id: "published-sa-without-joint",
        layer: "motion",
        title: "Sa of the bridge without the joint (5 %) under Loma Prieta Corralitos 090 at w0 = 6.3 rad/s",
        source: "published value: 5.6 m/s^2, to two digits, in the paper the joint model comes from; the band is wider than the rounding (0.9 %) because the paper names neither its record (Corralitos 090 is the likeliest, docs/model.md) nor its processing",
        quantity: "Sa [m/s^2]",
        band: Band::Relative(0.03),
        run: published_sa_without_joint,
    },
    Problem {
        id: "no-joint-equals-exact",
        layer: "model",
        title: "the reference bridge with its joint disabled, through the multibody solver, under Corralitos 090 at T = 1 s",
        source: "second method: the exact solution of the linear oscillator (Nigam and Jennings 1969) over the same window",
        quantity: "Sa [m/s^2]",
        band: Band::Relative(1e-5),
        run: no_joint_equals_exact,
    },
    Problem {
        id: "energy-balance",
        layer: "model",
        title: "the small joint (3 center beams) with friction under the first 10 s of Corralitos 090",
        source: "conservation law: kinetic and stored energy plus the energy dissipated equal the work of the earthquake load",
        quantity: "energy balance error over the earthquake's work [-]",
        band: Band::Absolute(1e-6),
        run: energy_balance,
    },
    Problem {
        id: "service-friction-work",
        layer: "model",
        title: "the small joint with rigid bushings (1e9 N/m) opened and closed by the service case",
        source: "hand calculation: mu n_s F_N times each bearing's sliding distance, summed (docs/model.md, \"The service case\")",
        quantity: "friction work per cycle [J]",
        band: Band::Relative(5e-3),
        run: service_friction_work,
    },
    Problem {
        id: "small-joint-against-exudyn",
        layer: "model",
        title: "the small joint (3 center beams, 15 bodies) on a light deck (5e4 kg, T = 1 s, 5 %: the joint raises its Sa by 16.7 %) under the first 10 s of Corralitos 090 x 0.15, no pounding, at tolerances 1e-12",
        source: "another program: Exudyn 1.13.6, the same model built apart from the spec (its bodies, prismatic, revolute and point-on-line joints, the bushings and the regularised friction as user functions), generalized-alpha at h = 5e-5 s, converging at second order (tests/data/exudyn, scripts/exudyn/small_joint.py)",
        quantity: "Sa of the deck [m/s^2]",
        band: Band::Relative(1e-6),
        run: super::programs::small_joint_sa_against_exudyn,
    },
    Problem {
        id: "small-joint-friction-against-exudyn",
        layer: "model",
        title: "the same run",
        source: "another program: the same Exudyn run (its bearings' friction power integrated over the run)",
        quantity: "friction energy dissipated by the joint over the run [J]",
        band: Band::Relative(1e-5),
        run: super::programs::small_joint_friction_against_exudyn,
    },
    Problem {
        id: "three-span-against-opensees",
        layer: "model",
        title: "the three-span girder bridge of tests/data/three_span (40-60-40 m on two piers, OpenSees' modes) without joints, 20 modes through the multibody solver (the modes as bodies, the deck end tied to them), under Corralitos 090",
        source: "second method: OpenSees 3.7.1's own linear transient of the same model with 5 % modal damping (tests/data/three_span/README.md)",
        quantity: "peak displacement of the right deck end relative to the ground [m]",
        band: Band::Relative(1e-2),
        run: super::modal::three_span_against_opensees,
    },
    Problem {
        id: "three-span-static-correction",
        layer: "model",
        title: "the three-span bridge with springs of 2e8 and 5e7 N/m from its left and right deck ends to the ground (a stuck joint's order of stiffness), 3 modes and the static correction of the other 121 (bridge.modal.static_correction), under the first 15 s of Corralitos 090",
        source: "second method: OpenSees 3.7.1's own linear transient of the full model with the same springs and the bridge's 5 % modal damping (scripts/opensees/transient.py --end-springs 2e8 5e7); without the correction the 3 modes are 7 % off",
        quantity: "peak displacement of the left deck end relative to the ground [m]",
        band: Band::Relative(1e-2),
        run: super::modal::static_correction_against_opensees,
    },
    Problem {
        id: "three-span-wave-passage",
        layer: "model",
        title: "the three-span bridge with a spring of 2e8 N/m from its left deck end to an abutment the ground motion reaches 0.2 s late (wave passage, [[joints]] abutment_lag: the abutment driven by u_g(t - 0.2) - u_g(t)), all 124 modes, under the first 15 s of Corralitos 090",
        source: "second method: OpenSees 3.7.1's own linear transient of the full model with the same spring, the abutment node's displacement imposed from numpy's exact integration of the record (scripts/opensees/transient.py --lagged-spring 2e8 0.2); ignoring the lag is 166 % off",
        quantity: "peak displacement of the left deck end relative to the ground [m]",
        band: Band::Relative(1e-3),
        run: super::modal::wave_passage_against_opensees,
    },
    Problem {
        id: "one-mode-equals-single-dof",
        layer: "model",
        title: "the small joint (3 center beams) on a bridge of one mode (T = 1 s, 5 %, phi = 1/sqrt(M), Gamma = sqrt(M), M = 2e6 kg) under Corralitos 090 x 0.15",
        source: "second method: the same joint on the single-DOF deck of mass M, period 1 s and 5 % damping",
        quantity: "Sa of the deck [m/s^2]",
        band: Band::Relative(2e-3),
        run: super::modal::one_mode_equals_single_dof,
    },
    Problem {
        id: "mirrored-joints",
        layer: "model",
        title: "the small joint at both ends of the three-span bridge (20 modes; the right one turned half a turn) under 8 s of Corralitos 090 x 0.6, pounding",
        source: "symmetry: mirroring the bridge about midspan swaps the joints and reverses the ground motion, so the left joint under the record does what the right joint does under the record reversed",
        quantity: "peak force of the left joint on the deck, against the right joint's under the reversed record [N]",
        band: Band::Relative(1e-6),
        run: super::modal::mirrored_joints,
    },
];

fn config(root: &Path, name: &str) -> Result<Config, String> {
    Config::from_file(&root.join("configs").join(name)).map_err(|e| e.to_string())
}

fn pendulum_period(_root: &Path) -> Result<Outcome, String> {
    let (length, mass, g, angle0) = (1.0, 1.0, 9.81, PI / 2.0);
    let (sys, bob) = reference::pendulum(mass, length, g, angle0);
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).map_err(|e| e.to_string())?);
    let x = asm.coordinate(bob, Coord::X).ok_or("no x of the bob")?;
    let mut sim = Radau5::new(asm.clone(), IntegratorOptions::default()).map_err(|e| e.to_string())?;
    let mut bottom =
        SignChanges::new(&asm, Watch::Position(x), x, (0.0, sim.positions()[x]), 1e-12).map_err(|e| e.to_string())?;
    sim.run(10.0, &mut bottom).map_err(|e| e.to_string())?;
    if let Some(e) = bottom.error {
        return Err(e.to_string());
    }
    let times = bottom.times();
    if times.len() < 2 {
        return Err(format!("the bob passed the bottom {} times in 10 s", times.len()));
    }
    // crossings every half period
    let computed = 2.0 * (times[times.len() - 1] - times[0]) / (times.len() - 1) as f64;
    let equivalent = length + sys.body(bob).inertia / (mass * length);
    Ok(Outcome { computed, reference: closed_form::pendulum_period(equivalent, g, angle0) })
}

fn coulomb_turning_points(_root: &Path) -> Result<Outcome, String> {
    let (stiffness, friction_force, x0) = (100.0, 1.0, 0.105);
    let oscillator =
        FrictionOscillator { mass: 1.0, stiffness, friction_force, v_eps: 1e-3, law: FrictionLaw::Linear, x0 };
    let (sys, body) = oscillator.on_coordinate();
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).map_err(|e| e.to_string())?);
    let x = asm.coordinate(body, Coord::X).ok_or("no x of the mass")?;
    let options = IntegratorOptions::default().scaled_tolerances(1e-2);
    let mut sim = Radau5::new(asm.clone(), options).map_err(|e| e.to_string())?;
    // released from rest: the velocity's first sign is not a turning point
    let mut turning = SignChanges::new(&asm, Watch::Velocity(x), x, (0.0, 0.0), 1e-12).map_err(|e| e.to_string())?;
    // until just after the stop, before the regularised law's creep
    sim.run(1.6, &mut turning).map_err(|e| e.to_string())?;
    if let Some(e) = turning.error {
        return Err(e.to_string());
    }
    let expected = closed_form::den_hartog_turning_points(x0, friction_force / stiffness);
    let (Some(&reference), Some(found)) = (expected.last(), turning.found.get(expected.len() - 1)) else {
        return Err(format!("{} turning points found, {} expected", turning.found.len(), expected.len()));
    };
    Ok(Outcome { computed: found.1, reference })
}

fn head_on_linear_contact(_root: &Path) -> Result<Outcome, String> {
    let e = 0.65;
    let case = HeadOn {
        mass_a: 900.0,
        mass_b: 600.0,
        speed_a: 0.4,
        speed_b: -0.1,
        gap: 0.002,
        law: ContactLaw::Linear { stiffness: 1e9, restitution: e },
    };
    let (sys, a, b) = case.system();
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).map_err(|e| e.to_string())?);
    let (ca, cb) = (asm.coordinate(a, Coord::X).ok_or("no x of a")?, asm.coordinate(b, Coord::X).ok_or("no x of b")?);
    let options =
        IntegratorOptions { rtol: 1e-9, atol_translation: 1e-11, atol_velocity: 1e-9, ..IntegratorOptions::default() };
    let mut sim = Radau5::new(asm, options).map_err(|e| e.to_string())?;
    sim.run(case.gap / case.approach_speed() + 0.05, &mut NoObserver).map_err(|e| e.to_string())?;
    let v = sim.velocities();
    let computed = -(v[ca] - v[cb]) / case.approach_speed();
    let w = (1e9 / case.reduced_mass()).sqrt();
    let zeta = -f64::ln(e) / (PI.powi(2) + f64::ln(e).powi(2)).sqrt();
    let (decay, wd) = (zeta * w, w * (1.0 - zeta * zeta).sqrt());
    let tr = (PI - (2.0 * decay * wd / (w * w - 2.0 * decay * decay)).atan()) / wd;
    let reference = (-decay * tr).exp() * (decay / wd * (wd * tr).sin() - (wd * tr).cos());
    Ok(Outcome { computed, reference })
}

fn andrews_squeezer(_root: &Path) -> Result<Outcome, String> {
    let run = Squeezer::default().simulate(andrews::options(1e-12), andrews::END_TIME).map_err(|e| e.to_string())?;
    let (k, _) = run.worst();
    Ok(Outcome { computed: run.angles[k], reference: andrews::REFERENCE_ANGLES[k] })
}

fn resonance_amplitude(_root: &Path) -> Result<Outcome, String> {
    let (period, a0, zeta, per_cycle) = (1.0, 1.5, 0.05, 1000usize);
    let w = 2.0 * PI / period;
    // transients decay as exp(-zeta w t): 30 e-foldings
    let cycles = (30.0 / (zeta * w * period)).ceil() as usize + 2;
    let dt = period / per_cycle as f64;
    let acc: Vec<f64> = (0..=per_cycle * cycles).map(|i| a0 * (w * i as f64 * dt).sin()).collect();
    let p = peaks(&acc, dt, period, zeta, SpectrumOptions { subdivisions: 8 });
    let x = w * dt / 2.0;
    Ok(Outcome { computed: p.sd, reference: a0 / (2.0 * zeta * w * w) * (x.sin() / x).powi(2) })
}

/// Classical RK4 on u'' = -a_g - 2 zeta w u' - w^2 u, a_g linear between
/// samples, `sub` steps a sample interval, from rest: the largest absolute
/// acceleration at the sample times.
fn rk4_sa(accel: &[f64], dt: f64, period: f64, zeta: f64, sub: usize) -> f64 {
    let w = 2.0 * PI / period;
    let (w2, c) = (w * w, 2.0 * zeta * w);
    let h = dt / sub as f64;
    let f = |u: f64, v: f64, a: f64| (v, -a - c * v - w2 * u);
    let (mut u, mut v, mut sa) = (0.0f64, 0.0f64, 0.0f64);
    for win in accel.windows(2) {
        let slope = (win[1] - win[0]) / dt;
        for k in 0..sub {
            let t = k as f64 * h;
            let (ag0, agm, ag1) = (win[0] + slope * t, win[0] + slope * (t + 0.5 * h), win[0] + slope * (t + h));
            let (k1u, k1v) = f(u, v, ag0);
            let (k2u, k2v) = f(u + 0.5 * h * k1u, v + 0.5 * h * k1v, agm);
            let (k3u, k3v) = f(u + 0.5 * h * k2u, v + 0.5 * h * k2v, agm);
            let (k4u, k4v) = f(u + h * k3u, v + h * k3v, ag1);
            u += h / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u);
            v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        }
        sa = sa.max((w2 * u + c * v).abs());
    }
    sa
}

fn spectrum_against_rk4(root: &Path) -> Result<Outcome, String> {
    let spec = RecordSpec::new("RSN753_LOMAP_CLS090-hor2.AT2");
    let rec = load_record(&spec, &root.join("ground_motions")).map_err(|e| e.to_string())?.record;
    let accel = &rec.acceleration[..4000];
    let computed = peaks(accel, rec.dt, 1.0, 0.05, SpectrumOptions::default()).sa;
    Ok(Outcome { computed, reference: rk4_sa(accel, rec.dt, 1.0, 0.05, 1000) })
}

fn published_sa_without_joint(root: &Path) -> Result<Outcome, String> {
    let spec = RecordSpec::new("RSN753_LOMAP_CLS090-hor2.AT2");
    let rec = load_record(&spec, &root.join("ground_motions")).map_err(|e| e.to_string())?.record;
    let period = 2.0 * PI / 6.3;
    let computed = peaks(&rec.acceleration, rec.dt, period, 0.05, SpectrumOptions::default()).sa;
    Ok(Outcome { computed, reference: 5.6 })
}

fn no_joint_equals_exact(root: &Path) -> Result<Outcome, String> {
    let mut base = config(root, "paper.toml")?;
    base.joint.enabled = false;
    let overrides = Overrides { period: Some(Named::new(1.0, "period")), ..Overrides::default() };
    let spec = RunSpec::new(base, &overrides).map_err(|e| e.to_string())?;
    let (x, _) = crate::run::load_records(spec.config(), &root.join("configs")).map_err(|e| e.to_string())?;
    let computed = spec.run(&x.record, None, &RunOptions::default()).map_err(|e| e.to_string())?.sa;
    let reference = Reference::for_run(spec.config(), &x.record, &x.record).peaks(1.0, spec.config().bridge.damping).sa;
    Ok(Outcome { computed, reference })
}

fn energy_balance(root: &Path) -> Result<Outcome, String> {
    let mut c = config(root, "small.toml")?;
    c.simulation.duration = Some(10.0);
    let r = crate::run::simulate(&c, &root.join("configs"), &RunOptions::default()).map_err(|e| e.to_string())?;
    Ok(Outcome { computed: r.energy_error, reference: 0.0 })
}

fn service_friction_work(root: &Path) -> Result<Outcome, String> {
    let mut c = config(root, "small.toml")?;
    (c.joint.bushing.kx, c.joint.bushing.ky) = (1e9, 1e9);
    c.joint.contact.enabled = false;
    let scenario = crate::scenario::Scenario::new(c).map_err(|e| e.to_string())?;
    let r = crate::service::service(&scenario).map_err(|e| e.to_string())?;
    Ok(Outcome { computed: r.friction_work_per_cycle, reference: r.hand_calculation })
}
