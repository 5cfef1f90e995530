//! Size of the generated models.
//!
//! The reference joint has 27 center beams, a guide and nine joists, which
//! makes 27 + 10 + 270 = 307 bodies, 921 body coordinates plus the deck's u
//! (922 coordinates), 540 prismatic, 18 revolute, 9 point-on-line and 3 weld
//! equations (570 in all) and 352 degrees of freedom. The small (Nc = 3, guide +
//! 2 joists) and medium (Nc = 9, guide + 3 joists) models scale the same way:
//! bodies Nc + Ns + Nc Ns, equations 2 Nc Ns + 3 per joist + 3 per guide.

mod common;

use quakejoint_model::generator::{build, Counts, Drive};
use quakejoint_solver::{Assembly, AssemblyOptions};

fn counts(name: &str) -> Counts {
    let model = build(&common::shipped(name), None, Drive::None).unwrap();
    // the solver accepts the system and numbers it the same way
    let asm = Assembly::new(&model.system, &AssemblyOptions::default()).unwrap();
    assert_eq!(asm.coordinates(), model.counts.coordinates);
    assert_eq!(asm.equations(), model.counts.constraints);
    model.counts
}

#[test]
fn reference_model_has_307_bodies_922_coordinates_570_equations_352_dof() {
    assert_eq!(counts("paper.toml"), Counts { bodies: 307, coordinates: 922, constraints: 570, dof: 352 });
}

#[test]
fn small_and_medium_models_scale_with_center_and_support_beams() {
    // small: 3 + 3 + 9 bodies; 2*9 + 2*3 + 3 equations
    assert_eq!(counts("small.toml"), Counts { bodies: 15, coordinates: 46, constraints: 27, dof: 19 });
    // medium: 9 + 4 + 36 bodies; 2*36 + 3*3 + 3 equations
    assert_eq!(counts("medium.toml"), Counts { bodies: 49, coordinates: 148, constraints: 84, dof: 64 });
}

#[test]
fn default_config_is_the_reference_model() {
    let text = "[record]\nfile = \"x.AT2\"\n";
    let config = quakejoint_model::Config::from_toml(text, "inline").unwrap();
    let model = build(&config, None, Drive::None).unwrap();
    assert_eq!(model.counts, Counts { bodies: 307, coordinates: 922, constraints: 570, dof: 352 });
    assert_eq!(config.joint, common::shipped("paper.toml").joint);
    assert_eq!(config.bridge.omega(), 6.3);
}
