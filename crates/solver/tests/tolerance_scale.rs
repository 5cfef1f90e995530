//! A body's tolerance scale multiplies the absolute tolerances of its
//! coordinates and velocities (RADAU5's per-component `ATOL`, Hairer and
//! Wanner IV.8). The error test weighs each component by
//! `atol + rtol |x|`, so a linear oscillator whose body is held 4 times less
//! tightly must take exactly the steps, and reach exactly the state, of the
//! same oscillator with every absolute tolerance 4 times larger (4 is a power
//! of two: both products round alike), and fewer steps than at its own
//! tolerances.

use std::f64::consts::PI;
use std::sync::Arc;

use quakejoint_solver::reference::sdof;
use quakejoint_solver::*;

/// Free end state and counters of the oscillator under a few seconds of a
/// two-harmonic base acceleration sampled every 0.5 s.
fn run(scale: f64, atol: f64) -> (f64, f64, Stats) {
    let dt = 0.5;
    let ag: Vec<f64> = (0..13).map(|j| 3.0 * (2.0 * PI * 0.3 * j as f64 * dt).sin() + (j % 3) as f64).collect();
    let (mut sys, body) = sdof(1.0, 0.8, 0.02, TimeSeries::uniform(0.0, dt, ag).unwrap());
    sys.body_mut(body).tolerance_scale = scale;
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let x = asm.coordinate(body, Coord::X).unwrap();
    let opts = IntegratorOptions {
        rtol: 1e-6,
        atol_translation: atol,
        atol_velocity: atol,
        atol_rotation: atol,
        atol_angular_velocity: atol,
        ..IntegratorOptions::default()
    };
    let mut sim = Radau5::new(asm, opts).unwrap();
    sim.run(6.0, &mut NoObserver).unwrap();
    (sim.positions()[x], sim.velocities()[x], sim.stats())
}

#[test]
fn a_bodys_tolerance_scale_is_a_factor_on_its_absolute_tolerances() {
    let scaled = run(4.0, 1e-6);
    let larger_atol = run(1.0, 4e-6);
    assert_eq!(scaled.2, larger_atol.2, "counters");
    assert_eq!((scaled.0, scaled.1), (larger_atol.0, larger_atol.1), "end state");
    let unscaled = run(1.0, 1e-6);
    assert!(
        scaled.2.steps < unscaled.2.steps,
        "held 4 times less tightly: {} steps, as given: {}",
        scaled.2.steps,
        unscaled.2.steps
    );
}

#[test]
fn a_tolerance_scale_that_is_not_positive_is_named() {
    for bad in [0.0, -1.0, f64::NAN] {
        let (mut sys, body) = sdof(1.0, 1.0, 0.05, TimeSeries::uniform(0.0, 0.1, vec![0.0; 3]).unwrap());
        sys.body_mut(body).tolerance_scale = bad;
        let err = Assembly::new(&sys, &AssemblyOptions::default()).unwrap_err();
        assert!(err.to_string().contains("tolerance_scale") && err.to_string().contains("deck"), "{err}");
    }
}
