//! Size of the generated models.
//!
//! The reference joint has 27 center beams, a guide and nine joists, which
//! makes 27 + 10 + 270 = 307 bodies and 352 degrees of freedom. Written as
//! the solver gets it (the bearings translate only, `BearingJoint::
//! Translational`): 3 coordinates per beam and 2 per bearing plus the deck's u
//! (652 coordinates), 270 point-on-line (bearing on its support beam), 18
//! revolute, 9 point-on-line (joist box) and 3 weld equations (300 in all).
//! With the spec's prismatic joints (`BearingJoint::Prismatic`) each bearing
//! has a third coordinate and a second equation: 922 coordinates, 570
//! equations, the same 352 degrees of freedom. The small (Nc = 3, guide + 2
//! joists) and medium (Nc = 9, guide + 3 joists) models scale the same way:
//! bodies Nc + Ns + Nc Ns, equations Nc Ns + 3 per joist + 3 per guide.

mod common;

use quakejoint_model::generator::{build, build_with, BearingJoint, Counts, Drive};
use quakejoint_solver::{Assembly, AssemblyOptions};

fn counts(name: &str, joint: BearingJoint) -> Counts {
    let model = build_with(&common::shipped(name), None, Drive::None, joint).unwrap();
    // the solver accepts the system and numbers it the same way
    let asm = Assembly::new(&model.system, &AssemblyOptions::default()).unwrap();
    assert_eq!(asm.coordinates(), model.counts.coordinates);
    assert_eq!(asm.equations(), model.counts.constraints);
    model.counts
}

#[test]
fn reference_model_has_307_bodies_652_coordinates_300_equations_352_dof() {
    let translational = counts("paper.toml", BearingJoint::Translational);
    assert_eq!(translational, Counts { bodies: 307, coordinates: 652, constraints: 300, dof: 352 });
    let prismatic = counts("paper.toml", BearingJoint::Prismatic);
    assert_eq!(prismatic, Counts { bodies: 307, coordinates: 922, constraints: 570, dof: 352 });
}

#[test]
fn small_and_medium_models_scale_with_center_and_support_beams() {
    // small: 3 + 3 + 9 bodies; 9 + 2*3 + 3 equations
    assert_eq!(
        counts("small.toml", BearingJoint::Translational),
        Counts { bodies: 15, coordinates: 37, constraints: 18, dof: 19 }
    );
    // medium: 9 + 4 + 36 bodies; 36 + 3*3 + 3 equations
    assert_eq!(
        counts("medium.toml", BearingJoint::Translational),
        Counts { bodies: 49, coordinates: 112, constraints: 48, dof: 64 }
    );
    assert_eq!(
        counts("medium.toml", BearingJoint::Prismatic),
        Counts { bodies: 49, coordinates: 148, constraints: 84, dof: 64 }
    );
}

#[test]
fn default_config_is_the_reference_model() {
    let text = "[record]\nfile = \"x.AT2\"\n";
    let config = quakejoint_model::Config::from_toml(text, "inline").unwrap();
    let model = build(&config, None, Drive::None).unwrap();
    assert_eq!(model.counts, Counts { bodies: 307, coordinates: 652, constraints: 300, dof: 352 });
    assert_eq!(config.joint, common::shipped("paper.toml").joint);
    assert_eq!(config.bridge.omega(), 6.3);
}

/// The bearings are held to `simulation.bearing_atol_factor` times the
/// absolute tolerances (2 by default), every other body to the tolerances
/// as given.
#[test]
fn bearings_and_only_bearings_carry_the_configured_tolerance_factor() {
    for (extra, factor) in [("", 2.0), ("[simulation]\nbearing_atol_factor = 5.0\n", 5.0)] {
        let model = build(&common::shipped_with("small.toml", extra), None, Drive::None).unwrap();
        let bearings: Vec<_> = model.bearings.iter().flatten().copied().collect();
        assert_eq!(bearings.len(), 9);
        for b in &bearings {
            assert_eq!(model.system.body(*b).tolerance_scale, factor);
        }
        let others =
            model.system.bodies().iter().enumerate().filter(|(i, _)| !bearings.iter().any(|b| b.index() == *i));
        for (_, body) in others {
            assert_eq!(body.tolerance_scale, 1.0, "{}", body.name);
        }
    }
}
