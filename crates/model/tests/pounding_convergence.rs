//! A pounding run converges with the tolerances.
//!
//! The small joint under the first 10 s of Corralitos 090 at T = 1 s closes
//! its sub-gaps dozens of times. Every impact is an event located on the
//! dense output, so the same run at 100 times tighter tolerances (the
//! bearings held like every other body, not to twice `atol`) must find
//! the same impacts (at 5 cm/s or faster: after some impacts a beam settles
//! against its neighbour in bounces of mm/s, as many as the tolerances
//! resolve, which are listed but not counted), and agree on the peak deck acceleration (1e-4), the
//! energy the impacts dissipate (1e-3) and the peak contact force (1e-3,
//! taken at step ends, where the steps inside an impact are short); the
//! energy balance, contact dissipation included, closes to 1e-6 of the
//! earthquake's work in both.

mod common;

use quakejoint_model::run::{simulate, RunOptions};

#[test]
fn a_pounding_run_converges_with_the_tolerances() {
    let base = {
        let mut c = common::shipped("small.toml");
        c.simulation.duration = Some(10.0);
        c
    };
    let mut tight = base.clone();
    tight.simulation.rtol = 1e-8;
    tight.simulation.atol = 1e-8;
    tight.simulation.atol_rotation = 1e-8;
    tight.simulation.bearing_atol_factor = 1.0;
    let (options, w) = (RunOptions::default(), 2.0 * std::f64::consts::PI);
    let d = simulate(&common::at_omega(base.clone(), w), &common::configs_dir(), &options).unwrap();
    let t = simulate(&common::at_omega(tight.clone(), w), &common::configs_dir(), &options).unwrap();
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    let (p, q) = (d.pounding, t.pounding);
    eprintln!(
        "impacts {} ({} tight), Sa {:.1e}, contact energy {:.1e}, peak contact force {:.1e}; {} steps ({} tight), {} \
         failed",
        p.impacts,
        q.impacts,
        rel(d.sa, t.sa),
        rel(p.contact_energy, q.contact_energy),
        rel(p.peak_contact_force, q.peak_contact_force),
        d.stats.steps,
        t.stats.steps,
        d.stats.failed_attempts
    );
    assert!(p.impacts >= 10, "the joint pounds: {p:?}");
    assert_eq!(p.impacts, q.impacts, "the same impacts");
    assert!(rel(d.sa, t.sa) < 1e-4, "Sa {} vs {}", d.sa, t.sa);
    assert!(rel(p.contact_energy, q.contact_energy) < 1e-3, "{} vs {}", p.contact_energy, q.contact_energy);
    assert!(
        rel(p.peak_contact_force, q.peak_contact_force) < 1e-3,
        "{} vs {}",
        p.peak_contact_force,
        q.peak_contact_force
    );
    assert!(d.energy_error < 1e-6 && t.energy_error < 1e-6, "{} {}", d.energy_error, t.energy_error);
}
