//! The two ways of writing a bearing's sliding joint give the same motion.
//!
//! The spec's prismatic joint (`BearingJoint::Prismatic`: the bearing a full
//! body x, y, phi, with an angle equation keeping it parallel to its support
//! beam and one keeping its centre on the beam's axis) makes the bearing turn
//! with its beam. Nothing else acts on its rotation (the bushing and the
//! friction act at its centre), so the angle equation can be solved by hand:
//! the bearing translates only, its moment of inertia turns with the beam
//! (added to the beam's), and one point-on-line equation keeps it on the axis
//! (`BearingJoint::Translational`, the default, 540 unknowns fewer in the
//! reference model). Both are the same differential-algebraic system written
//! in different coordinates, so their results may differ only by integration
//! error: at tolerances 1e-9 the small joint under the strong first 10 s of
//! Corralitos 090, whose bearings reverse hundreds of times, must agree in the
//! peak deck acceleration (1e-6), the friction energy (1e-5), the peak joint
//! force (1e-4, from the multipliers) and the sub-gaps (1 um); and both
//! forms' energy balances close, so the lumped inertia neither creates nor
//! loses energy. The joint's support beams swivel (the small joint's joists,
//! at 13 and 17 degrees, turn as the gap opens), so the bearings' rotation does enter.

mod common;

use quakejoint_model::generator::BearingJoint;
use quakejoint_model::run::{simulate, RunOptions};

#[test]
fn translational_bearings_move_as_the_prismatic_joint_of_the_spec() {
    let mut config = common::shipped("small.toml");
    config.simulation.duration = Some(10.0);
    config.joint.contact.enabled = false;
    config.joint.capacity.max_subgap = 0.5;
    config.simulation.rtol = 1e-9;
    config.simulation.atol = 1e-9;
    config.simulation.atol_rotation = 1e-9;
    for period in [0.5, 2.0] {
        let run = |bearing_joint| {
            let config = common::at_omega(config.clone(), 2.0 * std::f64::consts::PI / period);
            simulate(&config, &common::configs_dir(), &RunOptions { bearing_joint, ..RunOptions::default() }).unwrap()
        };
        let (t, p) = (run(BearingJoint::Translational), run(BearingJoint::Prismatic));
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
        eprintln!(
            "T = {period} s: Sa {:.1e}, friction energy {:.1e}, peak joint force {:.1e}, sub-gaps {:.1e} / {:.1e} m; \
             energy errors {:.1e} / {:.1e}; steps {} / {}",
            rel(t.sa, p.sa),
            rel(t.friction_energy, p.friction_energy),
            rel(t.peak_joint_force, p.peak_joint_force),
            (t.min_subgap.unwrap() - p.min_subgap.unwrap()).abs(),
            (t.max_subgap.unwrap() - p.max_subgap.unwrap()).abs(),
            t.energy_error,
            p.energy_error,
            t.stats.steps,
            p.stats.steps,
        );
        assert!(t.friction_energy > 1e3, "the bearings slide ({} J)", t.friction_energy);
        assert!(rel(t.sa, p.sa) < 1e-6, "T = {period}: Sa {} vs {}", t.sa, p.sa);
        assert!(rel(t.friction_energy, p.friction_energy) < 1e-5, "{} vs {}", t.friction_energy, p.friction_energy);
        assert!(rel(t.peak_joint_force, p.peak_joint_force) < 1e-4, "{} vs {}", t.peak_joint_force, p.peak_joint_force);
        for (a, b) in [(t.min_subgap, p.min_subgap), (t.max_subgap, p.max_subgap)] {
            assert!((a.unwrap() - b.unwrap()).abs() < 1e-6, "sub-gap {a:?} vs {b:?}");
        }
        assert!(t.energy_error < 1e-6 && p.energy_error < 1e-6, "{} {}", t.energy_error, p.energy_error);
    }
}
