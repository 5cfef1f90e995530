//! The joint results converge with the tolerances, and reversals of the
//! bearings cost no failed Newton attempts.
//!
//! The run settings of the joint (`run::integrator_options`: the Jacobian kept
//! while Newton contracts by 0.2, Newton stopped at 0.2 of the tolerance, the
//! bearings solved locally with the regularisation zone's slope in the
//! iteration matrix, and held to twice the absolute tolerance) trade
//! iterations for speed. Whatever they trade must stay
//! below the error the tolerances allow: the same run at 100 times tighter
//! tolerances (rtol and atol 1e-8, and the bearings held like every other
//! body instead of to twice `atol`) is the reference for the peak deck
//! acceleration (the 0.5 % target; 1e-4 asserted), the friction
//! energy and the peak joint force (the latter from the multipliers, which the
//! error test does not see: an unconverged multiplier once grew into a 40 kN
//! spike). The small model runs the first 10 s of Corralitos 090 (its strong
//! motion) at three bridge periods. Every bearing reverses many times in these
//! runs; before the local friction solve each reversal cost failed Newton
//! attempts (5375 on the whole small run), now none may. Contact is left out
//! (the small joint pounds at T = 1 s): the convergence of pounding runs is
//! `pounding_convergence.rs`.

mod common;

use quakejoint_model::run::{simulate, RunOptions};

#[test]
fn small_joint_results_converge_with_tolerance_and_reversals_cost_no_failures() {
    let base = {
        let mut c = common::shipped("small.toml");
        c.simulation.duration = Some(10.0);
        c.joint.contact.enabled = false;
        c.joint.capacity.max_subgap = 0.5;
        c
    };
    let mut tight = base.clone();
    tight.simulation.rtol = 1e-8;
    tight.simulation.atol = 1e-8;
    tight.simulation.atol_rotation = 1e-8;
    tight.simulation.bearing_atol_factor = 1.0;
    for period in [0.3, 1.0, 3.0] {
        let (options, w) = (RunOptions::default(), 2.0 * std::f64::consts::PI / period);
        let d = simulate(&common::at_omega(base.clone(), w), &common::configs_dir(), &options).unwrap();
        let t = simulate(&common::at_omega(tight.clone(), w), &common::configs_dir(), &options).unwrap();
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
        let (sa, ef, fj) =
            (rel(d.sa, t.sa), rel(d.friction_energy, t.friction_energy), rel(d.peak_joint_force, t.peak_joint_force));
        eprintln!(
            "T = {period} s: Sa {sa:.1e}, friction energy {ef:.1e}, peak joint force {fj:.1e}; \
             {} steps, {} failed, {} factorisations (tight: {} steps)",
            d.stats.steps, d.stats.failed_attempts, d.stats.factorizations, t.stats.steps
        );
        assert!(sa < 1e-4, "T = {period}: Sa {} vs {} (tight)", d.sa, t.sa);
        assert!(ef < 1e-3, "T = {period}: friction energy {} vs {}", d.friction_energy, t.friction_energy);
        assert!(fj < 1e-3, "T = {period}: peak joint force {} vs {}", d.peak_joint_force, t.peak_joint_force);
        assert_eq!(d.stats.failed_attempts, 0, "T = {period}: failed Newton attempts");
        assert!(d.friction_energy > 1e3, "the bearings slide (friction energy {})", d.friction_energy);
    }
}
