//! The reference pendulum: 1 kg on a 1 m link released from horizontal.
//! Prints the period found by the integrator, the exact one (elliptic
//! integral) and the energy drift.
//!
//! `cargo run --release -p quakejoint-solver --example pendulum`

use std::f64::consts::PI;
use std::sync::Arc;

use quakejoint_solver::reference::pendulum;
use quakejoint_solver::*;

/// The times the bob passes the bottom (x = 0), located on the dense output.
struct Bottom {
    x: usize,
    tracker: RootTracker,
    state: StateBuffer,
    times: Vec<f64>,
    error: Option<DenseOutputError>,
}

impl Observer for Bottom {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        let x = self.x;
        loop {
            match self.tracker.next(view, &mut self.state, |s| s.q[x]) {
                Ok(Some(root)) => self.times.push(root.t),
                Ok(None) => return true,
                Err(e) => {
                    self.error = Some(e);
                    return false;
                }
            }
        }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (sys, bob) = pendulum(1.0, 1.0, 9.81, PI / 2.0);
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default())?);
    let x = asm.coordinate(bob, Coord::X).ok_or("bob has no x")?;
    let mut sim = Radau5::new(asm.clone(), IntegratorOptions::default())?;
    let mut tracker = RootTracker::new(1e-12)?;
    tracker.start(0.0, sim.positions()[x]);
    let mut obs = Bottom { x, tracker, state: StateBuffer::new(&asm), times: Vec::new(), error: None };
    sim.run(10.0, &mut obs)?;
    if let Some(e) = obs.error {
        return Err(e.into());
    }
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
