//! The reference pendulum: 1 kg on a 1 m link released from horizontal.
//! Prints the period found by the integrator, the exact one (elliptic
//! integral) and the energy drift.
//!
//! `cargo run --release -p quakejoint-solver --example pendulum`

use std::f64::consts::PI;
use std::sync::Arc;

use quakejoint_solver::reference::pendulum;
use quakejoint_solver::*;

struct Bottom {
    x: usize,
    last: f64,
    times: Vec<f64>,
}

impl Observer for Bottom {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        let x = view.q[self.x];
        if x.signum() != self.last.signum() {
            // linear interpolation is enough for a printout
            let t = view.t_prev + (view.t - view.t_prev) * self.last / (self.last - x);
            self.times.push(t);
        }
        self.last = x;
        true
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (sys, bob) = pendulum(1.0, 1.0, 9.81, PI / 2.0);
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default())?);
    let x = asm.coordinate(bob, Coord::X).ok_or("bob has no x")?;
    let mut sim = Radau5::new(asm, IntegratorOptions::default())?;
    let mut obs = Bottom { x, last: 1.0, times: Vec::new() };
    sim.run(10.0, &mut obs)?;
    let n = obs.times.len();
    let period = 2.0 * (obs.times[n - 1] - obs.times[0]) / (n - 1) as f64;
    // K(1/sqrt 2) by the arithmetic-geometric mean
    let (mut a, mut b) = (1.0f64, 0.5f64.sqrt());
    for _ in 0..30 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    let exact = 4.0 * (1.0f64 / 9.81).sqrt() * PI / (2.0 * a);
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
