//! The reference pendulum: 1 kg on a 1 m link released from horizontal.
//! Prints the period found by the integrator, the exact one (elliptic
//! integral) and the energy drift.
//!
//! `cargo run --release -p quakejoint-solver --example pendulum`

use std::f64::consts::PI;
use std::sync::Arc;

use quakejoint_solver::reference::closed_form::{pendulum_period, SignChanges, Watch};
use quakejoint_solver::reference::pendulum;
use quakejoint_solver::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (sys, bob) = pendulum(1.0, 1.0, 9.81, PI / 2.0);
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default())?);
    let x = asm.coordinate(bob, Coord::X).ok_or("bob has no x")?;
    let mut sim = Radau5::new(asm.clone(), IntegratorOptions::default())?;
    // the bob passes the bottom where x = 0, located on the dense output
    let mut obs = SignChanges::new(&asm, Watch::Position(x), x, (0.0, sim.positions()[x]), 1e-12)?;
    sim.run(10.0, &mut obs)?;
    if let Some(e) = obs.error {
        return Err(e.into());
    }
    let times = obs.times();
    let n = times.len();
    let period = 2.0 * (times[n - 1] - times[0]) / (n - 1) as f64;
    let exact = pendulum_period(1.0, 9.81, PI / 2.0);
    println!(
        "period        {period:.6} s (exact {exact:.6} s, small-angle {:.6} s)",
        2.0 * PI * (1.0f64 / 9.81).sqrt()
    );
    println!("energy drift  {:.2e} of the energy scale over 10 s", sim.energy().relative_error());
    let (g, gv) = sim.max_constraint_residuals();
    println!("constraints   |g| <= {g:.1e} m, |G v| <= {gv:.1e} m/s");
    println!("solver        {:?}", sim.stats());
    Ok(())
}
