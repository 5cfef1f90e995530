//! With the joint removed, the coupled multibody run is the linear bridge.
//!
//! Disabling the joint leaves the deck on its spring and damper, integrated
//! by the multibody solver; its response must equal the exact linear
//! solution (the piecewise-linear exact step of the ground-motion crate,
//! what `quakejoint simulate --no-joint` prints) to 1e-5 relative in Sa, at
//! several periods.

mod common;

use quakejoint_model::linear::linear_response;
use quakejoint_model::run::{load_records, simulate_records, RunOptions};

#[test]
fn deck_alone_matches_the_exact_linear_solution() {
    let mut config = common::shipped("paper.toml");
    config.joint.enabled = false;
    let rx = load_records(&config, &common::configs_dir()).unwrap().0.record;
    for period in [0.3, 0.9973, 2.5] {
        let w = 2.0 * std::f64::consts::PI / period;
        let mb = simulate_records(&common::at_omega(config.clone(), w), &rx, None, &RunOptions::default()).unwrap();
        let exact = linear_response(&rx, w, config.bridge.damping, false);
        let rel = (mb.sa - exact.sa).abs() / exact.sa;
        eprintln!("T = {period}: Sa {:.7} vs exact {:.7} ({rel:.1e}), {} steps", mb.sa, exact.sa, mb.stats.steps);
        assert!(rel < 1e-5, "T = {period}: Sa {} vs {}", mb.sa, exact.sa);
        assert!((mb.sd - exact.sd).abs() / exact.sd < 1e-5);
        assert!((mb.sv - exact.sv).abs() / exact.sv < 1e-5);
        assert_eq!(mb.t_sa, exact.t_sa);
        assert_eq!(mb.peak_joint_force, 0.0);
    }
}
