//! Failures are typed errors, never panics.
//!
//! - Redundant constraints that over-determine a body are found when the
//!   system is compiled (no free coordinate is left for an equation).
//! - Constraints that are structurally fine but dependent at the given
//!   configuration make the iteration matrix singular: the block
//!   elimination and the faer fallback both detect it and the run refuses to
//!   start.
//! - A force law that produces NaN part way makes every attempt at that time
//!   fail; after the configured number of attempts the run ends with the
//!   time and the cause.
//! - Initial positions far off the constraints are refused, naming the
//!   constraint; bad parameters are refused naming the parameter.

use std::sync::Arc;

use quakejoint_solver::reference::pendulum;
use quakejoint_solver::*;

fn pinned_body() -> (System, BodyId) {
    let mut sys = System::new();
    let b = sys.add_body(Body::new("plate", 2.0, 0.5, [1.0, 0.0, 0.0]));
    sys.add_constraint_named(
        "pin",
        Constraint::Revolute(Revolute { body_a: b, point_a: [-1.0, 0.0], body_b: BodyId::GROUND, point_b: [0.0, 0.0] }),
    );
    sys.set_excitation(Excitation { gravity: [0.0, -9.81], ..Default::default() });
    (sys, b)
}

#[test]
fn structurally_redundant_constraints_are_a_build_error() {
    let (mut sys, b) = pinned_body();
    sys.add_constraint_named(
        "second pin",
        Constraint::Revolute(Revolute { body_a: b, point_a: [1.0, 0.0], body_b: BodyId::GROUND, point_b: [2.0, 0.0] }),
    );
    let err = Assembly::new(&sys, &AssemblyOptions::default()).unwrap_err();
    match &err {
        BuildError::RedundantConstraints { constraint, .. } => assert!(constraint.contains("pin"), "{err}"),
        other => panic!("unexpected error {other:?}"),
    }
    assert!(err.to_string().contains("redundant"), "{err}");
}

#[test]
fn numerically_dependent_constraints_give_a_singular_matrix_error() {
    // The pivot point must also stay on a ground line through the pivot:
    // its gradient is a combination of the revolute's, so G loses rank.
    let (mut sys, b) = pinned_body();
    sys.add_constraint_named(
        "rail through pivot",
        Constraint::PointOnLine(PointOnLine {
            body: b,
            point: [-1.0, 0.0],
            line_body: BodyId::GROUND,
            line_point: [0.0, 0.0],
            line_direction: [1.0, 1.0],
        }),
    );
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).expect("structurally solvable"));
    match Radau5::new(asm, IntegratorOptions::default()) {
        Err(SolverError::Initialisation(LinalgError::Singular { .. } | LinalgError::NonFinite)) => {}
        Err(other) => panic!("unexpected error {other}"),
        Ok(_) => panic!("a singular system must not start"),
    }
}

/// A spring that breaks (returns NaN) after `t_break`.
struct BreakingSpring {
    body: BodyId,
    t_break: f64,
}

impl CustomForce for BreakingSpring {
    fn bodies(&self) -> (BodyId, BodyId) {
        (self.body, BodyId::GROUND)
    }
    fn force(&self, t: f64, a: &BodyState, _: &BodyState) -> ([f64; 3], [f64; 3]) {
        let f = if t > self.t_break { f64::NAN } else { -10.0 * a.pose[1] };
        ([0.0, f, 0.0], [0.0; 3])
    }
}

#[test]
fn a_force_that_turns_nan_ends_the_run_with_time_and_cause() {
    let (mut sys, b) = pinned_body();
    sys.add_force(ForceElement::Custom(CustomElement(Arc::new(BreakingSpring { body: b, t_break: 0.5 }))));
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let mut sim = Radau5::new(asm, IntegratorOptions::default()).unwrap();
    match sim.run(2.0, &mut NoObserver) {
        Err(err @ SolverError::StepFailed { .. }) => {
            let SolverError::StepFailed { time, cause, .. } = &err else { unreachable!() };
            assert!((time - 0.5).abs() < 1e-6, "failed at {time}");
            assert_eq!(*cause, StepFailure::NonFinite, "{err}");
            assert!(err.to_string().contains("t = 0.5"), "{err}");
        }
        other => panic!("expected a step failure, got {other:?}"),
    }
    // the state reached before the failure is kept
    assert!(sim.time() > 0.49 && sim.time() <= 0.5);
    assert!(sim.stats().failed_attempts > 1, "failures were retried with smaller steps first");
}

#[test]
fn step_and_wall_clock_limits_are_typed_errors() {
    let (sys, _) = pendulum(1.0, 1.0, 9.81, 1.0);
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let opts = IntegratorOptions { max_steps: 10, ..Default::default() };
    let mut sim = Radau5::new(asm.clone(), opts).unwrap();
    assert!(matches!(sim.run(5.0, &mut NoObserver), Err(SolverError::StepLimit { limit: 10, .. })));
    let opts = IntegratorOptions { max_wall_time: Some(0.0), ..Default::default() };
    let mut sim = Radau5::new(asm, opts).unwrap();
    sim.run(1e-3, &mut NoObserver).ok();
    assert!(matches!(sim.run(5.0, &mut NoObserver), Err(SolverError::WallClockLimit { .. })));
}

#[test]
fn out_of_range_integrator_options_are_named() {
    let (sys, _) = pendulum(1.0, 1.0, 9.81, 1.0);
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let cases: [(IntegratorOptions, &str); 6] = [
        (IntegratorOptions { rtol: -1e-6, ..Default::default() }, "rtol"),
        (IntegratorOptions { rtol: 1.5, ..Default::default() }, "rtol"),
        (IntegratorOptions { atol_velocity: f64::NAN, ..Default::default() }, "atol_velocity"),
        (IntegratorOptions { h_max: 0.0, ..Default::default() }, "h_max"),
        (IntegratorOptions { newton_tolerance: Some(2.0), ..Default::default() }, "newton_tolerance"),
        (IntegratorOptions { max_newton: 1, ..Default::default() }, "max_newton"),
    ];
    for (opts, name) in cases {
        match Radau5::new(asm.clone(), opts) {
            Err(SolverError::Build(BuildError::InvalidParameter { name: got, .. })) => assert_eq!(got, name),
            other => panic!("{name}: expected InvalidParameter, got {:?}", other.err()),
        }
    }
}

#[test]
fn inconsistent_initial_positions_and_bad_parameters_are_named() {
    let (mut sys, b) = pinned_body();
    sys.body_mut(b).pose = [1.1, 0.0, 0.0];
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    match Radau5::new(asm, IntegratorOptions::default()) {
        Err(SolverError::Build(BuildError::InconsistentInitialState { constraint, residual, .. })) => {
            assert_eq!(constraint, "pin");
            assert!((residual - 0.1).abs() < 1e-12);
        }
        other => panic!("unexpected {:?}", other.err()),
    }
    let (mut sys, b) = pinned_body();
    sys.body_mut(b).mass = -1.0;
    let err = Assembly::new(&sys, &AssemblyOptions::default()).unwrap_err();
    assert!(err.to_string().contains("plate") && err.to_string().contains("mass"), "{err}");
    let mut sys = System::new();
    let a = sys.add_body(Body::new("a", 1.0, 1.0, [0.0; 3]));
    sys.add_force(ForceElement::Friction(Friction {
        slider: a,
        point: [0.0, 0.0],
        base: BodyId::GROUND,
        mu: 0.1,
        normal_force: 1.0,
        surfaces: 1.0,
        v_eps: 0.0,
        law: FrictionLaw::Linear,
    }));
    let err = Assembly::new(&sys, &AssemblyOptions::default()).unwrap_err();
    assert!(err.to_string().contains("v_eps"), "{err}");
}
