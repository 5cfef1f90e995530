//! Friction work per cycle of the service case against a hand calculation
//! and a closed form of the bushings' compliance.
//!
//! Driving the deck through opening and closing cycles, each bearing slides
//! along its support beam by the change of its distance from the pivot; the
//! hand calculation sums `mu n_s F_N` times those sliding distances over all
//! bearings (docs/model.md). That is exact for rigid bushings: with
//! stiff bushings (1e9 N/m) the simulated work must match it within 0.5 %,
//! on the small model too.
//!
//! With compliant bushings each center beam lags its intercept position
//! while sliding, the lag flips at each reversal and the bearings stick
//! meanwhile; the closed form (`compliance_deficit`, a 3 x 3 equilibrium
//! per beam) gives the loss per cycle. It was checked independently by a
//! quasi-static stick-slip solver written apart from this code (numpy;
//! exact Coulomb friction, bearings massless): small model 5,219 J per
//! cycle at A = 0.2 m and 2,018 J at A = 0.1 m against the hand
//! calculation's 7,009 J and 3,514 J, where the closed form says 28 % and
//! 51 % less (its linear lag is an upper estimate). The simulation must lie
//! between the hand calculation minus the closed-form deficit and the hand
//! calculation (inertia at the rounded reversals carries the beams part of
//! the way, so it is closer to the hand value than the quasi-static
//! solution). In every case the friction work must equal the area of the
//! hysteresis loop (the work the deck does on the joint, less the little the
//! bushing dampers take) within the loop's quadrature error (1 %).
//!
//! The hand calculation is for a joint whose sub-gaps stay open; the small
//! model's four sub-gaps of 40 mm cannot take a closing of 0.2 m, and with
//! contact its beams are pressed into each other (a run flagged
//! `penetration` and `capacity_exceeded`). Contact is left out here, so
//! that the comparison is about friction alone.

mod common;

use quakejoint_model::scenario::Scenario;
use quakejoint_model::service::{compliance_deficit, service as service_of};

/// The service case of `config`.
fn service(config: &Config) -> Result<quakejoint_model::service::ServiceResult, quakejoint_model::ModelError> {
    service_of(&Scenario::new(config.clone())?)
}
use quakejoint_model::Config;

fn check(config: &Config, what: &str) -> (f64, f64) {
    let mut config = config.clone();
    config.joint.contact.enabled = false;
    let config = &config;
    let r = service(config).unwrap();
    let hand = r.hand_calculation;
    let deficit = compliance_deficit(config).unwrap().unwrap();
    let rel = (r.friction_work_per_cycle - hand) / hand;
    eprintln!(
        "{what}: {:.1} J per cycle, hand {:.1} J ({:+.2} %), closed-form deficit {:.1} J ({:.2} %)",
        r.friction_work_per_cycle,
        hand,
        100.0 * rel,
        deficit,
        100.0 * deficit / hand
    );
    assert!(
        r.friction_work_per_cycle <= hand * 1.002 && r.friction_work_per_cycle >= hand - deficit - 0.01 * hand,
        "{what}: the friction work lies outside [hand - deficit, hand]"
    );
    // the loop is a trapezoid over 1000 samples of the cycle, which cuts the
    // corners at the reversals: 0.3 to 0.5 % high on the small model, where
    // the solver's own account of the drive's work closes exactly (friction
    // 5557.5 J + dampers 4.0 J + stored 5.4 J = 5567.0 J)
    let rel_loop = (r.loop_work_per_cycle - r.friction_work_per_cycle).abs() / r.friction_work_per_cycle;
    assert!(rel_loop < 1e-2, "{what}: loop {} J, friction {} J", r.loop_work_per_cycle, r.friction_work_per_cycle);
    let res = r.residuals;
    assert!(res.position < 1e-8 && res.angle < 1e-8 && res.velocity < 1e-8 && res.angular_velocity < 1e-8, "{what}");
    (rel, deficit / hand)
}

#[test]
fn friction_work_per_cycle_matches_the_hand_calculation_within_the_compliance_deficit() {
    // rigid limit: the hand calculation itself
    for model in ["small.toml", "medium.toml"] {
        let mut stiff = common::shipped(model);
        stiff.joint.bushing.kx = 1e9;
        stiff.joint.bushing.ky = 1e9;
        let (rel, deficit) = check(&stiff, &format!("{model}, bushings 1e9 N/m"));
        assert!(rel.abs() < 0.005 && deficit < 0.005, "{model}: {rel} {deficit}");
        stiff.joint.contact.enabled = false;
        assert!(service(&stiff).unwrap().warnings.is_empty());
    }
    // the small model with the reference bushings: a quarter of the work is
    // lost to sticking at reversals, and the run says why
    let mut small = common::shipped("small.toml");
    small.joint.contact.enabled = false;
    let (rel, deficit) = check(&small, "small.toml");
    assert!((deficit - 0.28).abs() < 0.01, "closed form {deficit} against 28 % by hand");
    assert!(rel < -0.15, "{rel}");
    let warnings = service(&small).unwrap().warnings;
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("assumes rigid bushings"), "{warnings:?}");
    // half the amplitude and speed: the loss per reversal is the same, so
    // the relative loss about doubles
    let mut slow = small.clone();
    (slow.service.speed, slow.service.amplitude, slow.service.cycles) = (0.1, 0.1, 3);
    let (rel_slow, deficit_slow) = check(&slow, "small.toml, A = 0.1 m, v = 0.1 m/s");
    assert!((deficit_slow - 0.51).abs() < 0.015 && rel_slow < rel, "{deficit_slow} {rel_slow}");
    // the medium model: a few per cent
    let (rel, deficit) = check(&common::shipped("medium.toml"), "medium.toml");
    assert!(rel < 0.0 && rel > -0.05 && (deficit - 0.0385).abs() < 0.003, "{rel} {deficit}");
}
