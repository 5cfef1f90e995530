//! Wave passage: a joint's abutment that the ground motion reaches later
//! than the bridge's other supports (`[[joints]] abutment_lag`).
//!
//! Relative to the ground the bridge's coordinates are measured from, such
//! an abutment moves by `d(t) = u_g(t - lag) - u_g(t)`, `u_g` the ground's
//! displacement integrated exactly from the record (the abutment is a body
//! driven along x; `LaggedGround` checks the double integral against a
//! closed form).
//!
//! - Against OpenSees: the three-span bridge with a linear spring (2e8 N/m)
//!   from its left deck end to an abutment reached 0.2 s late (a wave
//!   crossing 140 m at 700 m/s), under Corralitos 090; OpenSees imposes the
//!   abutment node's displacement (an sp constraint following `d`, from
//!   numpy's own exact integration, `scripts/opensees/at2.py`) on top of its
//!   uniform excitation (`transient.py --lagged-spring 2e8 0.2`). Every point's
//!   displacement agrees; ignoring the lag it does not.
//! - With the small joint at both ends, pounding: the energy balance closes
//!   with the earthquake's work through the lagged abutment (its driver's
//!   work) counted.
//! - Bad values are refused, naming the field.

mod common;

use std::path::{Path, PathBuf};

use quakejoint_model::modal::ModalBridge;
use quakejoint_model::run::{load_records, RunOptions};
use quakejoint_model::runspec::{Overrides, RunSpec};
use quakejoint_model::verification::modal::{
    corralitos, end_springs_run, two_joints_on_three_span, EndSpring, LAGGED_SPRING,
};

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn data() -> PathBuf {
    root().join("tests/data/three_span")
}

fn opensees() -> (Vec<f64>, Vec<Vec<f64>>) {
    common::opensees_csv("opensees_corralitos090_lagged_spring.csv")
}

#[test]
fn a_spring_to_a_late_abutment_agrees_with_opensees() {
    let bridge = ModalBridge::read(&data().join("modes.toml")).unwrap();
    let (t, os) = opensees();
    let ground = corralitos(root()).unwrap();
    let dt = ground.times()[1];
    assert!((t[1] - t[0] - dt).abs() < 1e-12);
    let duration = 15.0;
    let n = (duration / dt).round() as usize;
    let (stiffness, lag) = LAGGED_SPRING;
    let error = |u: &[Vec<f64>]| {
        (0..4)
            .map(|p| {
                let os = &os[2 * p][1..=n];
                let peak = os.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                u[p][..n].iter().zip(os).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / peak
            })
            .fold(0.0, f64::max)
    };
    let mut table = Vec::new();
    for (count, corrected, lag) in [(124, false, lag), (3, true, lag), (124, false, 0.0)] {
        let kept = bridge.kept(Some(count), 1.0, 0.05);
        let spring = EndSpring { end: 0, stiffness, lag };
        let u = end_springs_run(&bridge, &kept, corrected, &ground, &[spring], (duration, dt)).unwrap();
        let e = error(&u);
        eprintln!(
            "{count:>3} modes, correction {corrected:>5}, lag {lag} s: every point's u within {:.3} % of OpenSees' peaks",
            e * 100.0
        );
        table.push(e);
    }
    assert!(table[0] < 1e-3, "all modes: {:e}", table[0]);
    assert!(table[1] < 1e-2, "3 modes corrected: {:e}", table[1]);
    // the lag matters: without it the same bridge is far off
    assert!(table[2] > 0.05, "without the lag: {:e}", table[2]);
}

#[test]
fn joints_with_a_late_abutment_close_their_energy_balance() {
    let lagged = "[[joints]]\nname = \"left\"\ndeck_point = \"left end\"\ndeck_side = \"+x\"\nabutment_lag = 0.2\n\
                  [[joints]]\nname = \"right\"\ndeck_point = \"right end\"\ndeck_side = \"-x\"\n";
    let mut results = Vec::new();
    for lag in [false, true] {
        let mut config = two_joints_on_three_span(root(), "small.toml", 0.6, "[simulation]\nduration = 8.0\n").unwrap();
        if lag {
            let extra = quakejoint_model::Config::from_toml(
                &format!("[bridge]\n[bridge.modal]\nmodes = \"m\"\n{lagged}"),
                "lagged",
            )
            .unwrap();
            config.joints = extra.joints;
            config.load_modes(&data()).unwrap();
        }
        let (x, _) = load_records(&config, root()).unwrap();
        let r =
            RunSpec::new(config, &Overrides::default()).unwrap().run(&x.record, None, &RunOptions::default()).unwrap();
        eprintln!(
            "lag {lag}: joint forces {:.3} and {:.3} MN, earthquake work {:.1} kJ, energy balance {:.1e}, widest cell {:.1} mm",
            r.peak_joint_force / 1e6,
            r.joints.last().unwrap().peak_joint_force / 1e6,
            r.earthquake_work / 1e3,
            r.energy_error,
            r.max_subgap.unwrap() * 1e3
        );
        assert!(r.energy_error < 1e-5, "energy balance {:e}", r.energy_error);
        results.push(r);
    }
    // the late abutment pushes the left joint otherwise
    let (a, b) = (&results[0], &results[1]);
    assert!((a.peak_joint_force - b.peak_joint_force).abs() > 1e-3 * a.peak_joint_force);
    assert!((a.max_subgap.unwrap() - b.max_subgap.unwrap()).abs() > 1e-5);
}

#[test]
fn bad_lags_are_refused_naming_the_field() {
    for (line, want) in [
        ("abutment_lag = 20.0", "must be between 0 and 10 s"),
        ("abutment_lag = nan", "must be between 0 and 10 s"),
        ("abutment_lag = -0.2", "must be between 0 and 10 s"),
        ("abutment_lag = 0.1\nabutment_point = \"pier 1 top\"", "in-span hinge"),
    ] {
        let text = format!(
            "[bridge]\n[bridge.modal]\nmodes = \"modes.toml\"\n[[joints]]\nname = \"left\"\ndeck_point = \"left end\"\n\
             deck_side = \"+x\"\n{line}\n"
        );
        // (refused with the config, before its modes file is read)
        let e = quakejoint_model::Config::from_toml(&text, "lag.toml").unwrap_err().to_string();
        assert!(e.contains("joints[0].abutment_lag") && e.contains(want), "{line}: {e}");
    }
}
