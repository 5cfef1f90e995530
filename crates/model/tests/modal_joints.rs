//! Two joints on one bridge given by its modes (`[[joints]]`).
//!
//! The three-span girder bridge of `tests/data/three_span` (OpenSees'
//! modes, symmetric about midspan) carries the small joint of
//! configs/small.toml at each abutment: at the left end with the deck on
//! its +x side, at the right end turned half a turn (`deck_side = "-x"`).
//! Mirroring the bridge about midspan swaps the two joints and reverses
//! the ground motion along the bridge, so the left joint under a record
//! must do exactly what the right joint does under the same record
//! reversed, and the other way round: the same deck-point peaks, joint
//! forces, cell openings and impacts, to the integrator's accuracy. The
//! energy balance (the joints' friction and impacts, the modal and bushing
//! damping against the earthquake's work on the modes and the joints'
//! bodies) must close as it does with one joint.

mod common;

use std::path::PathBuf;

use quakejoint_model::run::{JointResult, RunResult};
use quakejoint_model::verification::modal;

fn root() -> PathBuf {
    common::configs_dir().join("..")
}

fn run(scale: f64) -> RunResult {
    let config = modal::two_joints_on_three_span(&root(), "small.toml", scale, "").unwrap();
    modal::run(&root(), &config).unwrap()
}

/// Largest relative difference of two joints' values.
fn difference(a: &JointResult, b: &JointResult) -> f64 {
    let pairs = [
        (a.sd, b.sd),
        (a.sv, b.sv),
        (a.sa, b.sa),
        (a.peak_joint_force, b.peak_joint_force),
        (a.peak_friction_force, b.peak_friction_force),
        (a.peak_bushing_force, b.peak_bushing_force),
        (a.friction_energy, b.friction_energy),
        (a.max_subgap.unwrap(), b.max_subgap.unwrap()),
        (a.min_subgap.unwrap(), b.min_subgap.unwrap()),
    ];
    pairs.iter().map(|(x, y)| ((x - y) / y).abs()).fold(0.0, f64::max)
}

#[test]
fn mirrored_bridge_swaps_the_two_joints() {
    for scale in [0.15, 0.6] {
        let (a, b) = (run(scale), run(-scale));
        assert_eq!(a.joints.len(), 2);
        let (left_a, right_a) = (a.joints[0].clone(), a.joints[1].clone());
        let (left_b, right_b) = (b.joints[0].clone(), b.joints[1].clone());
        let d1 = difference(&left_a, &right_b);
        let d2 = difference(&right_a, &left_b);
        eprintln!(
            "scale {scale}: left under +a_g: Sd {:.6} m, joint force {:.1} N, widest cell {:.2} mm, {} impacts; \
             right under -a_g: {:.6} m, {:.1} N, {:.2} mm, {} impacts; largest relative differences {d1:.1e}, {d2:.1e}; \
             energy balance {:.1e}, {:.1e}",
            left_a.sd,
            left_a.peak_joint_force,
            left_a.max_subgap.unwrap() * 1e3,
            left_a.pounding.impacts,
            right_b.sd,
            right_b.peak_joint_force,
            right_b.max_subgap.unwrap() * 1e3,
            right_b.pounding.impacts,
            a.energy_error,
            b.energy_error
        );
        // the same equations in mirrored coordinates: equal but for the order of
        // floating-point operations and the modes file's last digits
        let band = 1e-6;
        assert!(d1 < band && d2 < band, "scale {scale}: {d1:e}, {d2:e}");
        assert_eq!(left_a.pounding.impacts > 0, right_b.pounding.impacts > 0);
        assert!(
            a.energy_error < 1e-5 && b.energy_error < 1e-5,
            "energy balance {:e}, {:e}",
            a.energy_error,
            b.energy_error
        );
        // the two ends differ: one opens as the other closes
        assert!((left_a.max_subgap.unwrap() - right_a.max_subgap.unwrap()).abs() > 1e-4);
    }
}

/// The reference joint (configs/paper.toml, 307 bodies) at both ends of the
/// bridge: every factorisation of the iteration matrices stays in the
/// block elimination (a modal deck end of too small a mass makes its block
/// look singular and sends them to faer's sparse LU, 40 times slower).
#[test]
fn reference_joint_factorises_in_blocks() {
    let config = modal::two_joints_on_three_span(&root(), "paper.toml", 1.0, "[simulation]\nduration = 1.5\n").unwrap();
    let r = modal::run(&root(), &config).unwrap();
    assert!(r.stats.factorizations > 0);
    assert_eq!(r.stats.faer_fallbacks, 0, "{:?}", r.stats);
}

/// A joint at an in-span hinge: both its sides move with points of the
/// bridge (its abutment side with "pier 1 top", its deck side with "left
/// end"), so it works only on their relative motion and its forces act on
/// the bridge at both points. The energy balance must close as for a
/// joint on the ground, with the joint's friction taking work out, and its
/// cells are measured from its moving abutment side (from the ground, the
/// pier's sway of 0.11 m looked like cells 75 mm beyond their capacity).
#[test]
fn a_joint_at_an_in_span_hinge_closes_its_energy_balance() {
    let hinge = "[[joints]]\nname = \"hinge\"\ndeck_point = \"left end\"\ndeck_side = \"+x\"\n\
                 abutment_point = \"pier 1 top\"\n";
    let mut config =
        modal::two_joints_on_three_span(&root(), "small.toml", 0.6, "[simulation]\nduration = 8.0\n").unwrap();
    let extra: quakejoint_model::Config =
        quakejoint_model::Config::from_toml(&format!("[bridge]\n[bridge.modal]\nmodes = \"m\"\n{hinge}"), "hinge")
            .unwrap();
    config.joints = extra.joints;
    config.load_modes(&modal::three_span_data(&root())).unwrap();
    let r = modal::run(&root(), &config).unwrap();
    eprintln!(
        "hinge: friction {:.1} J, earthquake work {:.1} J, energy balance {:.1e}, widest cell {:.2} mm, joint force {:.1} N",
        r.friction_energy,
        r.earthquake_work,
        r.energy_error,
        r.max_subgap.unwrap() * 1e3,
        r.peak_joint_force
    );
    assert!(r.energy_error < 1e-5, "energy balance {:e}", r.energy_error);
    assert!(r.friction_energy > 0.0 && r.peak_joint_force > 0.0);
    assert_eq!(r.joints.len(), 1);
    // the two points move within millimetres of each other, and the cells
    // (measured from the moving abutment side's edge beam) follow them:
    // none near its capacity, none closed, the run valid
    assert!(r.validity.flags.is_ok(), "{:?}", r.validity);
    let (lo, hi) = (r.min_subgap.unwrap(), r.max_subgap.unwrap());
    assert!(lo > 0.02 && hi < 0.06, "sub-gaps {lo} .. {hi} m");
}

/// The bridge kept to its 3 longest modes: the modes move its two ends
/// almost alike, so a deck end's block of the iteration matrix holds a
/// stiffness of 1e15 beside a constraint's pivot of 1e-2. Measured against
/// the block's largest entry that pivot looked singular and every
/// factorisation fell back to faer (12 to 15 times the CPU of 20 modes);
/// measured against its own row (scaled partial pivoting) it is what it is,
/// and the factorisations stay in the block elimination. The energy
/// balance closes as with more modes.
#[test]
fn few_modes_factorise_in_blocks() {
    let mut config =
        modal::two_joints_on_three_span(&root(), "small.toml", 1.0, "[simulation]\nduration = 1.5\n").unwrap();
    config.bridge.modal.as_mut().unwrap().modes_used = Some(3);
    let r = modal::run(&root(), &config).unwrap();
    assert!(r.stats.factorizations > 0);
    assert_eq!(r.stats.faer_fallbacks, 0, "{:?}", r.stats);
    assert!(r.energy_error < 1e-5, "energy balance {:e}", r.energy_error);
}

/// A mode that does not move the points the file gives (a vertical mode
/// of a planar frame moves them along x by 1e-13 per unit): its coordinate,
/// the displacement at its largest point, would give it a mass of 1e26 kg
/// and a singular iteration matrix at the first step, whatever else the
/// run keeps. Here mode 23 of the three-span bridge has its shape at the
/// points scaled down to 8e-14: with every mode kept the run goes through,
/// and the points' peaks are those of the run without that mode (it
/// cannot move them) to the integrator's accuracy.
#[test]
fn a_mode_that_does_not_move_the_points_runs_and_changes_nothing_there() {
    let mut config =
        modal::two_joints_on_three_span(&root(), "small.toml", 1.0, "[simulation]\nduration = 1.5\n").unwrap();
    let m = config.bridge.modal.as_mut().unwrap();
    let mut bridge = (**m.loaded.as_ref().unwrap()).clone();
    let n = bridge.modes.len();
    bridge.modes[22].shape.iter_mut().for_each(|v| *v *= 1e-7);
    assert!(bridge.modes[22].shape.iter().all(|v| v.abs() < 1e-13));
    m.modes_used = Some(n);
    let mut without = config.clone();
    config.attach_modes(std::sync::Arc::new(bridge.clone())).unwrap();
    let with_all = modal::run(&root(), &config).unwrap();
    bridge.modes.remove(22);
    let wm = without.bridge.modal.as_mut().unwrap();
    wm.modes_used = Some(n - 1);
    without.attach_modes(std::sync::Arc::new(bridge)).unwrap();
    let reference = modal::run(&root(), &without).unwrap();
    for (a, b) in with_all.points.iter().zip(&reference.points) {
        eprintln!("{}: sd {:.9e} against {:.9e}, sa {:.9e} against {:.9e}", a.name, a.sd, b.sd, a.sa, b.sa);
        assert!((a.sd / b.sd - 1.0).abs() < 1e-6 && (a.sa / b.sa - 1.0).abs() < 1e-6, "{}", a.name);
    }
}

/// A joint turned half a turn (`deck_side = "-x"`, the right abutment)
/// reports its history in its own x: its deck point's motion opens it
/// with `u > 0`, and the ground's acceleration `ag` beside it is turned
/// too (-1 times the record's), so that `a_abs - ag` is its deck point's
/// acceleration relative to the ground in the same axis.
#[test]
fn a_joint_turned_half_a_turn_reports_the_ground_in_its_own_x() {
    let config = modal::two_joints_on_three_span(&root(), "small.toml", 0.3, "[simulation]\nduration = 1.0\n").unwrap();
    let (x, _) = quakejoint_model::run::load_records(&config, &root()).unwrap();
    let options = quakejoint_model::run::RunOptions { histories: true, ..Default::default() };
    let r = quakejoint_model::run::simulate_records(&config, &x.record, None, &options).unwrap();
    let left = r.histories.as_ref().unwrap();
    let right = r.joints[1].histories.as_ref().unwrap();
    assert_eq!(left.t, right.t);
    assert!(left.ag.iter().any(|a| *a != 0.0));
    for (a, b) in left.ag.iter().zip(&right.ag) {
        assert_eq!(*b, -*a);
    }
}

/// Every point of the modes file has its history, with the joints and
/// without, not only the first joint's deck point: the first joint's deck
/// end ("left end", its own x the bridge's) moves as the run's `u` and
/// `a_abs` say, and without the joints every point's series are the bridge
/// alone's, which `--no-joint` (the bridge alone, exactly) reports as its
/// own.
#[test]
fn every_point_has_its_history_with_the_joints_and_without() {
    use quakejoint_model::runspec::{Overrides, RunSpec};
    let config = modal::two_joints_on_three_span(&root(), "small.toml", 0.3, "[simulation]\nduration = 1.0\n").unwrap();
    let (x, _) = quakejoint_model::run::load_records(&config, &root()).unwrap();
    let options = quakejoint_model::run::RunOptions { histories: true, ..Default::default() };
    let with = RunSpec::new(config.clone(), &Overrides::default()).unwrap().run(&x.record, None, &options).unwrap();
    let alone = RunSpec::new(config, &Overrides { alone: true, ..Default::default() })
        .unwrap()
        .run(&x.record, None, &options)
        .unwrap();
    let (h, a) = (with.histories.unwrap(), alone.histories.unwrap());
    assert_eq!(h.points_u.len(), 4);
    assert!(h.points_u.iter().chain(&h.points_u_without_joint).all(|s| s.len() == h.t.len()));
    // the left end is the first joint's deck point
    let close = |x: &[f64], y: &[f64]| {
        let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        x.iter().zip(y).all(|(a, b)| (a - b).abs() <= 1e-9 * scale)
    };
    assert!(close(&h.points_u[0], &h.u) && close(&h.points_a_abs[0], &h.a_abs));
    assert_eq!(h.points_a_abs_without_joint[0], h.a_abs_without_joint);
    // the bridge alone reports every point as its own and as without
    assert_eq!(a.points_u, a.points_u_without_joint);
    assert_eq!(a.points_u_without_joint, h.points_u_without_joint);
    // the joints change the bridge's motion
    assert!(h.points_u[1] != h.points_u_without_joint[1]);
}

/// Each joint's friction power history is its own, not the whole
/// system's: integrated over the run (trapezoids at the record's 5 ms
/// samples) it gives that joint's friction energy, which the solver
/// integrates inside every step for its group of bodies, to the sampling's
/// accuracy, and the two joints' histories sum to the system's dissipation.
#[test]
fn each_joints_friction_power_history_is_its_own() {
    let config = modal::two_joints_on_three_span(&root(), "small.toml", 1.0, "[simulation]\nduration = 3.0\n").unwrap();
    let (x, _) = quakejoint_model::run::load_records(&config, &root()).unwrap();
    let options = quakejoint_model::run::RunOptions { histories: true, ..Default::default() };
    let r = quakejoint_model::run::simulate_records(&config, &x.record, None, &options).unwrap();
    let integral = |h: &quakejoint_model::run::Histories| {
        h.t.windows(2).zip(h.friction_power.windows(2)).map(|(t, p)| 0.5 * (p[0] + p[1]) * (t[1] - t[0])).sum::<f64>()
    };
    let histories = [r.histories.as_ref().unwrap(), r.joints[1].histories.as_ref().unwrap()];
    let mut sum = 0.0;
    for (h, joint) in histories.iter().zip(&r.joints) {
        let e = integral(h);
        eprintln!("{}: history {e:.1} J, friction_energy {:.1} J", joint.name, joint.friction_energy);
        assert!(joint.friction_energy > 1.0, "{}: {}", joint.name, joint.friction_energy);
        assert!(
            (e / joint.friction_energy - 1.0).abs() < 0.03,
            "{}: {e} against {}",
            joint.name,
            joint.friction_energy
        );
        sum += e;
    }
    assert!((sum / r.friction_energy - 1.0).abs() < 0.03, "{sum} against the system's {}", r.friction_energy);
}
