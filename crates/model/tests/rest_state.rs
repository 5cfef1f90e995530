//! The reference state is an equilibrium.
//!
//! At rest, with no excitation, every bushing is undeflected, no bearing
//! slides, the bridge spring is unstretched and every constraint is
//! satisfied: all generalised forces and constraint residuals vanish, and a
//! run with a record of zeros leaves every body where it is.

mod common;

use quakejoint_model::generator::{build, Drive};
use quakejoint_model::run::{simulate_records, RunOptions};
use quakejoint_motion::Record;
use quakejoint_solver::{Assembly, AssemblyOptions};

#[test]
fn forces_and_constraint_residuals_vanish_at_the_reference_state() {
    let model = build(&common::shipped("paper.toml"), None, Drive::None).unwrap();
    let asm = Assembly::new(&model.system, &AssemblyOptions::default()).unwrap();
    let (q, v) = asm.initial_state();
    assert!(v.iter().all(|&x| x == 0.0));
    let mut ws = asm.workspace();
    asm.residual(&mut ws, 0.0, &q, &v, &vec![0.0; asm.equations()]);
    let f = ws.forces().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let g = ws.constraints().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(f < 1e-9, "largest generalised force at rest {f:e} N");
    assert!(g < 1e-13, "largest constraint residual at rest {g:e}");
    assert_eq!(ws.velocity_constraints().iter().fold(0.0f64, |m, x| m.max(x.abs())), 0.0);
}

#[test]
fn nothing_moves_without_excitation() {
    let config = common::shipped("paper.toml");
    let zeros = Record::new("zeros", 0.005, vec![0.0; 401]).unwrap();
    let r = simulate_records(&config, &zeros, None, &RunOptions::default()).unwrap();
    assert!(r.sd < 1e-12 && r.sv < 1e-12 && r.sa < 1e-9, "deck moved: {} {} {}", r.sd, r.sv, r.sa);
    assert!(r.peak_joint_force < 1e-6, "joint force {}", r.peak_joint_force);
    assert!(r.peak_bushing_force < 1e-6 && r.friction_energy.abs() < 1e-9);
    let (lo, hi) = (r.min_subgap.unwrap(), r.max_subgap.unwrap());
    assert!((lo - 0.04).abs() < 1e-12 && (hi - 0.04).abs() < 1e-12, "sub-gaps {lo} {hi}");
}
