//! Free vibration of a mass on a spring with Coulomb friction.
//!
//! With friction force `F` and spring `k`, each half cycle ends at a turning
//! point whose amplitude is `2 F / k` smaller than the previous one (Den
//! Hartog 1931); the motion stops at the first turning point with
//! `|x| < F / k`, because the spring can no longer overcome static friction.
//! The regularised law is viscous below `v_eps`, so for the time `2 v_eps / a`
//! the mass spends near each turning point (`a` its acceleration there) the
//! friction is weaker than Coulomb's; the turning points shift by about
//! `v_eps^2 / a`. The amplitudes must match the closed form within that
//! tolerance, which shrinks with `v_eps`; the friction work must equal the
//! spring energy lost.

use std::sync::Arc;

use quakejoint_solver::reference::closed_form::{den_hartog_turning_points, SignChanges, Watch};
use quakejoint_solver::reference::FrictionOscillator;
use quakejoint_solver::*;

/// The turning points: where the velocity changes sign, located on the
/// dense output to 1e-12 s (released from rest, the velocity's first sign
/// is not a turning point), with the position there.
fn turning_points(asm: &Assembly, x: usize) -> SignChanges {
    SignChanges::new(asm, Watch::Velocity(x), x, (0.0, 0.0), 1e-12).unwrap()
}

fn turning_point_errors(v_eps: f64) -> (f64, f64) {
    let (m, k, f, x0) = (1.0, 100.0, 1.0, 0.105);
    let oscillator =
        FrictionOscillator { mass: m, stiffness: k, friction_force: f, v_eps, law: FrictionLaw::Linear, x0 };
    let (sys, body) = oscillator.on_coordinate();
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let x = asm.coordinate(body, Coord::X).unwrap();
    let mut sim = Radau5::new(asm.clone(), IntegratorOptions::default().scaled_tolerances(1e-2)).unwrap();
    let mut obs = turning_points(&asm, x);
    // stop just after the last turning point, before the regularised creep
    sim.run(1.6, &mut obs).unwrap();
    assert!(obs.error.is_none(), "dense output: {:?}", obs.error);
    let expected = den_hartog_turning_points(x0, f / k);
    assert_eq!(expected.len(), 5);
    assert!(obs.found.len() >= 5, "turning points {:?}", obs.found);
    let mut worst = 0.0f64;
    for (e, got) in expected.iter().zip(&obs.found) {
        worst = worst.max((got.1 - e).abs());
    }
    // smallest acceleration at a turning point: (k |x| - F)/m at the last one
    let a_min = (k * 0.025 - f) / m;
    let allowed = 2.0 * v_eps * v_eps / a_min + 1e-6 * v_eps.sqrt();
    eprintln!("v_eps {v_eps:e}: worst turning-point error {worst:.2e} m (allowed {allowed:.2e})");
    assert!(worst < allowed, "v_eps {v_eps}: error {worst:e} > {allowed:e}; got {:?}", obs.found);
    // energy: friction work equals the spring energy lost (plus kinetic now)
    let e = sim.energy();
    assert!(e.relative_error() < 1e-5, "energy balance {:e}", e.relative_error());
    (worst, e.friction)
}

#[test]
fn amplitude_drops_by_two_friction_displacements_per_half_cycle() {
    let mut last = f64::INFINITY;
    for v_eps in [1e-2, 3e-3, 1e-3] {
        let (worst, friction_work) = turning_point_errors(v_eps);
        assert!(worst < last, "error must shrink with v_eps");
        last = worst;
        // spring energy 1/2 k (x0^2 - x_stop^2) dissipated by friction
        let lost = 0.5 * 100.0 * (0.105f64.powi(2) - 0.005f64.powi(2));
        assert!((friction_work - lost).abs() / lost < 1e-3, "friction work {friction_work} vs {lost}");
    }
}

/// The same oscillator, but the mass is a free body held on the x axis by a
/// prismatic joint, so its friction is solved locally at every Newton
/// iteration ([`IntegratorOptions::local_friction`]); with and without the
/// local solve the turning points must follow Den Hartog, and the local
/// solve must not need a single failed Newton attempt.
#[test]
fn prismatic_slider_with_local_friction_solve_follows_den_hartog() {
    let (m, k, f, x0, v_eps) = (1.0, 100.0, 1.0, 0.105, 1e-3);
    let oscillator =
        FrictionOscillator { mass: m, stiffness: k, friction_force: f, v_eps, law: FrictionLaw::Linear, x0 };
    let (sys, body) = oscillator.on_prismatic();
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let x = asm.coordinate(body, Coord::X).unwrap();
    let expected = den_hartog_turning_points(x0, f / k);
    let mut failed = Vec::new();
    for local_friction in [true, false] {
        let opts = IntegratorOptions { local_friction, ..IntegratorOptions::default().scaled_tolerances(1e-2) };
        let mut sim = Radau5::new(asm.clone(), opts).unwrap();
        let mut obs = turning_points(&asm, x);
        sim.run(1.6, &mut obs).unwrap();
        assert!(obs.error.is_none(), "dense output: {:?}", obs.error);
        assert!(obs.found.len() >= 5, "turning points {:?}", obs.found);
        let worst = expected.iter().zip(&obs.found).map(|(e, got)| (got.1 - e).abs()).fold(0.0, f64::max);
        let allowed = 2.0 * v_eps * v_eps / (k * 0.025 - f) * m + 1e-6 * v_eps.sqrt();
        assert!(worst < allowed, "local {local_friction}: error {worst:e} > {allowed:e}; got {:?}", obs.found);
        assert!(sim.energy().relative_error() < 1e-5, "energy balance {:e}", sim.energy().relative_error());
        eprintln!("local friction solve {local_friction}: worst turning-point error {worst:.2e} m, {:?}", sim.stats());
        failed.push(sim.stats().failed_attempts);
    }
    assert_eq!(failed[0], 0, "failed Newton attempts with the local solve (without: {})", failed[1]);
}

/// Two friction oscillators in one system, each in its own group of bodies
/// (`System::set_group`): each group's friction energy must be what its own
/// oscillator lost, `k x0^2 / 2 - (k x^2 + m v^2) / 2` at the end (each
/// conserves energy apart from its friction: a balance per oscillator, not
/// the integrator's own sum), and the groups' energies must add up to the
/// system's friction energy to round-off.
#[test]
fn friction_energy_per_group_is_each_oscillators_own() {
    let (m, k) = (1.0, 100.0);
    let a = FrictionOscillator {
        mass: m,
        stiffness: k,
        friction_force: 1.0,
        v_eps: 1e-3,
        law: FrictionLaw::Linear,
        x0: 0.105,
    };
    let b = FrictionOscillator { friction_force: 0.4, x0: -0.06, ..a };
    let mut sys = System::new();
    let (ba, bb) = (a.add_on_coordinate(&mut sys), b.add_on_coordinate(&mut sys));
    sys.set_group(ba, 0);
    sys.set_group(bb, 1);
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    assert_eq!(asm.group_count(), 2);
    let mut sim = Radau5::new(asm.clone(), IntegratorOptions::default().scaled_tolerances(1e-2)).unwrap();
    sim.run(2.0, &mut NoObserver).unwrap();
    let groups = sim.group_friction_energy().to_vec();
    for (osc, body, got) in [(&a, ba, groups[0]), (&b, bb, groups[1])] {
        let c = asm.coordinate(body, Coord::X).unwrap();
        let (x, v) = (sim.positions()[c], sim.velocities()[c]);
        let lost = 0.5 * k * osc.x0 * osc.x0 - 0.5 * (k * x * x + m * v * v);
        eprintln!("group: friction energy {got:.9} J, energy lost {lost:.9} J");
        assert!((got - lost).abs() < 1e-5 * lost, "{got} against {lost}");
    }
    let total = sim.energy().friction;
    assert!((groups[0] + groups[1] - total).abs() <= 1e-12 * total, "{groups:?} against {total}");
}
