//! The alternative solver paths give the same motion.
//!
//! The Jacobian only steers Newton's method and the sparse LU only solves
//! its linear systems: the coloured finite-difference Jacobian (evaluated on
//! the rayon pool) and faer's sparse LU must therefore reproduce the default
//! run (analytic Jacobian, block elimination) to within the integration
//! tolerance. The chain exercises bushings, springs and prismatic joints.

use std::sync::Arc;

use quakejoint_solver::reference::chain;
use quakejoint_solver::*;

fn final_state(options: IntegratorOptions) -> (Vec<f64>, Stats) {
    let asm = Arc::new(Assembly::new(&chain(4, 2.0e4), &AssemblyOptions::default()).unwrap());
    let mut sim = Radau5::new(asm, options).unwrap();
    sim.run(1.5, &mut NoObserver).unwrap();
    (sim.positions().to_vec(), sim.stats())
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

#[test]
fn finite_difference_jacobian_and_faer_lu_reproduce_the_default_run() {
    let base = IntegratorOptions::default().scaled_tolerances(1e-2);
    let (reference, stats) = final_state(base.clone());
    assert_eq!(stats.faer_fallbacks, 0);
    let (fd, _) =
        final_state(IntegratorOptions { jacobian: JacobianMode::FiniteDifference { parallel: true }, ..base.clone() });
    let (faer, _) = final_state(IntegratorOptions { linear_solver: LinearSolver::Faer, ..base.clone() });
    let d_fd = max_diff(&reference, &fd);
    let d_faer = max_diff(&reference, &faer);
    eprintln!("finite-difference Jacobian: {d_fd:.1e} m, faer LU: {d_faer:.1e} m");
    assert!(d_fd < 1e-6, "finite-difference Jacobian changed the motion by {d_fd:e} m");
    assert!(d_faer < 1e-9, "faer LU changed the motion by {d_faer:e} m");
}
