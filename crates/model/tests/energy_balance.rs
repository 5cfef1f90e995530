//! The energy balance of earthquake runs closes.
//!
//! Kinetic plus stored energy (bridge spring, bushings) plus the energy
//! dissipated (dampers, friction) must equal the work of the earthquake load
//! on every body. Without friction and bushing damping only the bridge damper
//! dissipates; with friction the friction energy is positive and the balance
//! still closes. The small model runs the first 10 s of Corralitos 090.

mod common;

use quakejoint_model::run::{simulate, RunOptions};

#[test]
fn balance_closes_without_friction_and_bushing_damping() {
    let mut c = common::shipped("small.toml");
    c.joint.friction.mu = 0.0;
    c.joint.bushing.cx = 0.0;
    c.joint.bushing.cy = 0.0;
    c.simulation.duration = Some(10.0);
    let r = simulate(&c, &common::configs_dir(), &RunOptions::default()).unwrap();
    eprintln!("no friction: energy error {:.2e}, earthquake work {:.3e} J", r.energy_error, r.earthquake_work);
    assert!(r.friction_energy.abs() < 1e-9);
    assert!(r.energy_error < 1e-6, "energy error {:e}", r.energy_error);
}

#[test]
fn friction_dissipates_and_the_balance_still_closes() {
    let mut c = common::shipped("small.toml");
    c.simulation.duration = Some(10.0);
    let r = simulate(&c, &common::configs_dir(), &RunOptions::default()).unwrap();
    eprintln!(
        "friction: {:.3e} J of {:.3e} J earthquake work, energy error {:.2e}",
        r.friction_energy, r.earthquake_work, r.energy_error
    );
    assert!(r.friction_energy > 1e3, "friction energy {}", r.friction_energy);
    assert!(r.energy_error < 1e-6, "energy error {:e}", r.energy_error);
    let res = r.residuals;
    assert!(
        res.position < 1e-8 && res.angle < 1e-8 && res.velocity < 1e-8 && res.angular_velocity < 1e-8,
        "constraint residuals {res:?}"
    );
}
