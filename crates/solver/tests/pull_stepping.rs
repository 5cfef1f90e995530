//! Driving the integrator step by step ([`Radau5::advance`], pull-style)
//! takes the very steps [`Radau5::run`] takes with an observer: the same
//! times, states and contact events, bit for bit. The system is a mass on
//! a spring along x that pounds a stiff contact at the ground and slides on
//! a regularised Coulomb friction element, so that the steps hold contact
//! onsets and releases, friction reversals and step rejections.

use std::sync::Arc;

use quakejoint_solver::*;

fn pounding_slider() -> Arc<Assembly> {
    let mut sys = System::new();
    let body =
        sys.add_body(Body::new("mass", 1.0, 1.0, [0.2, 0.0, 0.0]).with_velocity([-1.0, 0.0, 0.0]).only(&[Coord::X]));
    sys.add_force(ForceElement::CoordinateSpring(CoordinateSpring {
        body,
        coord: Coord::X,
        stiffness: 40.0,
        damping: 0.1,
        rest: 0.0,
    }));
    // the ground's edge at x = -0.1, its free side toward +x
    sys.add_force(ForceElement::Contact(Contact {
        body,
        point: [0.0, 0.0],
        base: BodyId::GROUND,
        edge_point: [-0.1, 0.0],
        edge_normal: [1.0, 0.0],
        law: ContactLaw::Linear { stiffness: 1e6, restitution: 0.7 },
        reduced_mass: None,
    }));
    sys.add_force(ForceElement::Friction(Friction {
        slider: body,
        point: [0.0, 0.0],
        base: BodyId::GROUND,
        mu: 0.2,
        normal_force: 10.0,
        surfaces: 1.0,
        v_eps: 1e-3,
        law: FrictionLaw::Linear,
    }));
    Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap())
}

/// One step: its end time's bits, its state's and its events' (contact,
/// time).
type Step = (u64, Vec<u64>, Vec<(usize, u64)>);

/// Every step.
#[derive(Default, PartialEq, Debug)]
struct Trace(Vec<Step>);

impl Trace {
    fn push(&mut self, view: &StepView<'_>) {
        let state = view.q.iter().chain(view.v).map(|x| x.to_bits()).collect();
        let events = view.events.iter().map(|e| (e.contact, e.time.to_bits())).collect();
        self.0.push((view.t.to_bits(), state, events));
    }
}

impl Observer for Trace {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        self.push(view);
        true
    }
}

#[test]
fn advancing_step_by_step_takes_the_steps_run_takes() {
    let mut by_run = Trace::default();
    let mut sim = Radau5::new(pounding_slider(), IntegratorOptions::default()).unwrap();
    assert!(sim.run(2.0, &mut by_run).unwrap());
    let mut pulled = Trace::default();
    let mut sim = Radau5::new(pounding_slider(), IntegratorOptions::default()).unwrap();
    while let Some(view) = sim.advance(2.0).unwrap() {
        pulled.push(&view);
    }
    assert!(by_run.0.len() > 20, "{} steps", by_run.0.len());
    assert!(by_run.0.iter().any(|(_, _, e)| !e.is_empty()), "no contact event: the test needs some");
    assert_eq!(by_run, pulled);
    // at the end it stays: no step, and no error
    assert!(sim.advance(2.0).unwrap().is_none());
    assert!(matches!(sim.advance(1.0), Err(SolverError::EndBeforeStart { .. })));
}
