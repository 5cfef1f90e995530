//! Friction work per cycle of the service case against a hand calculation.
//!
//! Driving the deck through opening and closing cycles, each bearing slides
//! along its support beam by the change of its distance from the pivot; the
//! hand calculation sums `mu n_s F_N` times those sliding distances over all
//! bearings (docs/model.md). Where the intercept theorem holds (stiff
//! bushings) the simulated friction work of a cycle must match it within
//! 2 %. With the reference stiffness the center beams lag their intercept
//! positions at each reversal (the drift the model description estimates at
//! millimetres), so the bearings slide a little less: the shortfall must
//! shrink with the stiffness. In both cases the friction work must equal the
//! area of the hysteresis loop (the work the deck does on the joint, less
//! the little the bushing dampers take).

mod common;

use quakejoint_model::service::service;

#[test]
fn friction_work_per_cycle_matches_the_hand_calculation() {
    let mut stiff = common::shipped("medium.toml");
    stiff.joint.bushing.kx = 1e8;
    stiff.joint.bushing.ky = 1e8;
    let r = service(&stiff).unwrap();
    let rel = (r.friction_work_per_cycle - r.hand_calculation) / r.hand_calculation;
    eprintln!(
        "stiff bushings: {:.1} J per cycle vs hand {:.1} J ({:+.2} %)",
        r.friction_work_per_cycle,
        r.hand_calculation,
        100.0 * rel
    );
    assert!(rel.abs() < 0.02, "friction work {} vs hand calculation {}", r.friction_work_per_cycle, r.hand_calculation);
    assert!((r.loop_work_per_cycle - r.friction_work_per_cycle).abs() / r.friction_work_per_cycle < 5e-3);

    let reference = service(&common::shipped("medium.toml")).unwrap();
    let rel_ref = (reference.friction_work_per_cycle - reference.hand_calculation) / reference.hand_calculation;
    eprintln!("reference bushings: {:+.2} % against the hand calculation", 100.0 * rel_ref);
    assert!(rel_ref < 0.0 && rel_ref.abs() > rel.abs() && rel_ref.abs() < 0.05, "shortfall {rel_ref}");
    assert!(
        (reference.loop_work_per_cycle - reference.friction_work_per_cycle).abs() / reference.friction_work_per_cycle
            < 5e-3
    );
    assert!(reference.max_position_residual < 1e-8 && reference.max_velocity_residual < 1e-8);
}
