//! Energy conservation of a frictionless, undamped chain.
//!
//! Rods joined end to end by stiff bushings, each carrying a slider in a
//! prismatic joint, sliders tied by springs to the next rod, the first rod
//! pinned, falling from horizontal under gravity. No element dissipates, so
//! kinetic plus stored energy (springs, bushings, gravity) must stay at its
//! initial value; over 10 s of violent motion the balance must close to
//! 1e-6 of the energy scale, with the constraints held throughout.

use std::sync::Arc;

use quakejoint_solver::reference::chain;
use quakejoint_solver::*;

#[test]
fn undamped_chain_conserves_energy_over_ten_seconds() {
    let sys = chain(6, 2.0e4);
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let mut sim = Radau5::new(asm, IntegratorOptions::default()).unwrap();
    sim.run(10.0, &mut NoObserver).unwrap();
    let e = sim.energy();
    eprintln!(
        "chain: energy error {:.2e} (scale {:.1} J, kinetic now {:.1} J), constraints {:?}, {:?}",
        e.relative_error(),
        e.max_scale,
        e.kinetic,
        sim.max_constraint_residuals(),
        sim.stats()
    );
    assert!(e.kinetic > 0.1 * e.max_scale, "the chain is moving");
    assert!(e.relative_error() < 1e-6, "energy error {:e}", e.relative_error());
    let (g, gv) = sim.max_constraint_residuals();
    assert!(g < 1e-8 && gv < 1e-8);
}
