//! The joint between two bridge segments (`[bridge.far]`).
//!
//! - A far segment made rigid and fixed (1e10 kg at 0.01 s) is the
//!   abutment: the near deck's response must be the abutment case's, and
//!   the joint's force on the segment (the reactions on its body) the
//!   force on the abutment (the reactions on the support beams, turned
//!   round: `peak_abutment_force`).
//! - Two identical segments under the same ground motion move together:
//!   the joint between them is carried along rigidly, so it neither slides
//!   (its friction dissipates next to nothing) nor pounds, the decks stay
//!   together to a fraction of a millimetre, and both respond as the bridge
//!   alone. Only the joint's own mass (36 t on two 1e8 kg decks, 1.8e-4)
//!   separates their Sa from the bare oscillator's.

mod common;

use quakejoint_model::config::FarSegmentConfig;
use quakejoint_model::run::{simulate, RunOptions, RunResult};
use quakejoint_model::Config;

fn run(config: &Config) -> RunResult {
    simulate(config, &common::configs_dir(), &RunOptions::default()).unwrap()
}

fn reference() -> Config {
    let mut config = common::shipped("paper.toml");
    config.simulation.duration = Some(10.0);
    config
}

#[test]
fn a_rigid_fixed_segment_is_the_abutment() {
    let abutment = run(&reference());
    let mut config = reference();
    config.bridge.far =
        Some(FarSegmentConfig { mass: Some(1e10), period: Some(0.01), period_ratio: None, damping: None });
    let segments = run(&config);
    let far = segments.far.expect("a far segment");
    assert!((segments.sa - abutment.sa).abs() < 1e-6 * abutment.sa, "{} against {}", segments.sa, abutment.sa);
    let rel = (segments.friction_energy - abutment.friction_energy).abs() / abutment.friction_energy;
    assert!(rel < 1e-4, "friction energy {} against {}", segments.friction_energy, abutment.friction_energy);
    assert_eq!(segments.validity.flags, abutment.validity.flags);
    // the stiff segment moves with the ground: its Sa is the record's PGA
    assert!((far.sa - far.sa_without).abs() < 1e-3 * far.sa_without, "{far:?}");
    assert!(segments.energy_error < 1e-6);
    // the joint's force on its abutment side, two ways: the reactions of
    // its pivots and welds on the segment's body, and the same reactions
    // on the support beams turned round (peak_abutment_force); and the
    // fixed abutment's, where only the second way exists
    let (f, g) = (segments.peak_abutment_force, far.peak_joint_force);
    assert!((f - g).abs() < 1e-9 * g, "abutment force {f} against the segment's {g}");
    let a = abutment.peak_abutment_force;
    assert!((a - f).abs() < 1e-3 * f, "fixed abutment {a} against the rigid segment {f}");
}

#[test]
fn identical_segments_move_together_and_the_joint_does_nothing() {
    let abutment = run(&reference());
    let mut config = reference();
    config.bridge.far = Some(FarSegmentConfig { mass: None, period: None, period_ratio: Some(1.0), damping: None });
    let segments = run(&config);
    let far = segments.far.expect("a far segment");
    assert!(
        far.max_relative_displacement < 2e-3 * segments.sd,
        "{} m apart, Sd {}",
        far.max_relative_displacement,
        segments.sd
    );
    assert!(
        segments.friction_energy < 1e-3 * abutment.friction_energy,
        "friction {} J against {} J at the abutment",
        segments.friction_energy,
        abutment.friction_energy
    );
    assert_eq!(segments.pounding.impacts, 0);
    for (sa, name) in [(segments.sa, "near"), (far.sa, "far")] {
        assert!((sa - far.sa_without).abs() < 1e-3 * far.sa_without, "{name} Sa {sa} against {}", far.sa_without);
    }
    assert!(segments.energy_error < 1e-6);
}
