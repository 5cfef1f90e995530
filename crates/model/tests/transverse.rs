//! The deck across the bridge (`bridge.transverse_period`) under a
//! transverse record (`[record_y]`).
//!
//! - Without the joint the deck is two uncoupled linear oscillators, x
//!   under `[record]` and y under `[record_y]`, so the multibody run must
//!   give each one's exact linear response (Nigam-Jennings, the spectrum
//!   code): Sa across equals the closed-form `sa_y_without` to the solver's
//!   accuracy, and Sa along the exact x response.
//! - With the joint and the ground still along x, the deck racks the joint
//!   across: the joists turn about their pivots as their boxes move with the
//!   deck. Nothing is lost or created: the energy balance closes, and the
//!   deck's response along x, which only the joint's geometry couples to the
//!   transverse motion, stays orders of magnitude below its response across;
//!   and the reported acceleration across, from the force balance with the
//!   joint's force, agrees with the second difference of the deck's motion
//!   plus the ground's acceleration (four times closer than without the
//!   joint's force in it).

mod common;

use quakejoint_model::run::{simulate_records, RunOptions};
use quakejoint_motion::{load_record, Record, RecordSpec};

fn record(name: &str) -> Record {
    let spec = RecordSpec::new(format!("../ground_motions/{name}"));
    load_record(&spec, &common::configs_dir()).expect("shipped record").record
}

#[test]
fn without_the_joint_the_deck_moves_across_as_the_exact_oscillator() {
    let mut config = common::shipped("paper.toml");
    config.joint.enabled = false;
    config.bridge.transverse_period = Some(0.7);
    config.bridge.transverse_damping = Some(0.03);
    config.simulation.duration = Some(15.0);
    config.simulation.rtol = 1e-8;
    config.simulation.atol = 1e-8;
    let (x, y) = (record("RSN753_LOMAP_CLS090-hor2.AT2"), record("RSN753_LOMAP_CLS000-hor1.AT2"));
    let run = simulate_records(&config, &x, Some(&y), &RunOptions::default()).unwrap();
    let across = run.transverse.expect("the deck moves across");
    assert!((2.0 * std::f64::consts::PI / across.omega - 0.7).abs() < 1e-12);
    let rel = (across.sa - across.sa_without).abs() / across.sa_without;
    assert!(rel < 1e-6, "Sa across {} against the exact {} ({rel:e})", across.sa, across.sa_without);
    let window = quakejoint_model::run::run_window(&config, &x);
    let exact_x = quakejoint_motion::peaks(
        &window.acceleration,
        x.dt,
        config.bridge.natural_period(),
        config.bridge.damping,
        Default::default(),
    );
    assert!((run.sa - exact_x.sa).abs() / exact_x.sa < 1e-6, "Sa along {} against {}", run.sa, exact_x.sa);
}

#[test]
fn a_joint_racked_across_closes_its_energy_balance() {
    let mut config = common::shipped("paper.toml");
    config.bridge.transverse_period = Some(1.0);
    config.simulation.duration = Some(10.0);
    let y = record("RSN753_LOMAP_CLS000-hor1.AT2");
    // the ground at rest along the bridge: the same time step, every sample 0
    let x = Record::new("still", y.dt, vec![0.0; y.acceleration.len()]).unwrap();
    let options = RunOptions { histories: true, ..RunOptions::default() };
    let run = simulate_records(&config, &x, Some(&y), &options).unwrap();
    let across = run.transverse.expect("the deck moves across");
    assert!(run.energy_error < 1e-6, "energy balance error {:e}", run.energy_error);
    assert!(across.sa > 1.0 && across.peak_joint_force > 1e5, "{across:?}");
    assert!(run.sa < 1e-3 * across.sa, "Sa along {} against Sa across {}", run.sa, across.sa);
    // the reported absolute acceleration across (spring, damper and the
    // joint's force, from the force balance) against the motion itself: the
    // second difference of u_y plus the ground's acceleration
    let h = run.histories.expect("histories");
    let dt = y.dt;
    // root mean square over the run: the second difference of a response
    // with the joint's impulsive forces in it is coarse at single samples
    let rms = |term: f64| {
        let mut sum = 0.0;
        for i in 1..h.uy.len() - 1 {
            let second = (h.uy[i + 1] - 2.0 * h.uy[i] + h.uy[i - 1]) / (dt * dt);
            let joint = h.joint_force_y[i] / config.bridge.mass;
            let e = second + y.acceleration[i] - (h.a_abs_y[i] + (term - 1.0) * joint);
            sum += e * e;
        }
        (sum / (h.uy.len() - 2) as f64).sqrt()
    };
    let (with_force, without_force) = (rms(1.0), rms(0.0));
    // 0.0064 m/s^2 with the joint's force, 0.025 without it, 0.049 with it
    // the wrong way round (on this run)
    assert!(
        with_force < 3e-3 * across.sa && with_force < 0.3 * without_force,
        "force balance against the motion: rms {with_force} m/s^2 off, {without_force} without the joint's force"
    );
}
