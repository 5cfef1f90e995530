//! A frictionless bead on a rod turned at constant angular speed.
//!
//! A driver turns the rod about the origin at `omega`; the bead slides in a
//! prismatic joint along it. In the rotating frame the only radial force is
//! the centrifugal one, `r'' = omega^2 r`, so a bead starting at `r0` at rest
//! relative to the rod moves out as `r(t) = r0 cosh(omega t)`. The driver
//! delivers exactly the energy the bead gains, so the energy balance (with
//! the driver's work) must close.

use std::sync::Arc;

use quakejoint_solver::reference::bead_on_rod;
use quakejoint_solver::*;

struct Radius {
    x: usize,
    y: usize,
    omega: f64,
    r0: f64,
    worst: f64,
}

impl Observer for Radius {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        let r = view.q[self.x].hypot(view.q[self.y]);
        let exact = self.r0 * (self.omega * view.t).cosh();
        self.worst = self.worst.max((r - exact).abs() / exact);
        true
    }
}

#[test]
fn bead_moves_out_as_r0_cosh_omega_t() {
    let (omega, r0) = (1.5, 0.2);
    let (sys, rod, bead) = bead_on_rod(omega, r0);
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    let mut obs = Radius {
        x: asm.coordinate(bead, Coord::X).unwrap(),
        y: asm.coordinate(bead, Coord::Y).unwrap(),
        omega,
        r0,
        worst: 0.0,
    };
    let phi = asm.coordinate(rod, Coord::Phi).unwrap();
    let mut sim = Radau5::new(asm, IntegratorOptions::default()).unwrap();
    sim.run(2.0, &mut obs).unwrap();
    eprintln!(
        "bead: worst relative radius error {:.2e}, energy {:.2e}, {:?}",
        obs.worst,
        sim.energy().relative_error(),
        sim.stats()
    );
    assert!(obs.worst < 1e-6, "radius error {:e}", obs.worst);
    assert!((sim.positions()[phi] - omega * 2.0).abs() < 1e-9, "driver followed");
    let e = sim.energy();
    assert!(e.constraints > 0.0, "the driver does work");
    assert!(e.relative_error() < 1e-6, "energy balance {:e}", e.relative_error());
    let (g, gv) = sim.max_constraint_residuals();
    assert!(g < 1e-8 && gv < 1e-8, "constraint residuals {g:e} {gv:e}");
}
