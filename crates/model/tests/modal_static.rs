//! The static correction for the modes left out (residual flexibility),
//! against the full model: its closed-form static answer and OpenSees'
//! transient.
//!
//! The three-span bridge of `tests/data/three_span/` gets a linear spring
//! along x from each deck end to the ground (`K_L`, `K_R`), as a stuck joint
//! would hold it, and is shaken along x.
//!
//! - Static: under a constant ground acceleration `a` the full model sits
//!   at `u = a g - F_{:,P} K u_P` (`g` and `F` the modes file's `[static]`
//!   table, OpenSees' unit-load analyses), so
//!   `u_P = (I + F_PP K)^-1 a g_P` at the ends and the rest follows. The
//!   kept modes alone miss the flexibility of the modes left out (with 3
//!   modes, all of the deck's stretching between its ends); with the
//!   static correction any number of modes reaches the full model's answer
//!   (to 2e-6 of it: the ground's push on the deck ends' own light masses,
//!   `DECK_END_MASS_RATIO`).
//! - Transient: OpenSees' own linear transient of the same bridge with the
//!   springs (`scripts/opensees/transient.py --end-springs`, its modal
//!   damping the bridge's own 124 modes', the springs undamped) under
//!   Corralitos 090. All 124 modes through the multibody solver agree with
//!   it (the same equations); with few modes the correction brings the ends'
//!   displacement close to it. The errors are printed against the modes.

mod common;

use std::path::{Path, PathBuf};

use quakejoint_model::modal::ModalBridge;
use quakejoint_model::verification::modal::{corralitos, end_springs, end_springs_run, END_SPRINGS as SPRINGS};
use quakejoint_solver::TimeSeries;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn data() -> PathBuf {
    root().join("tests/data/three_span")
}

fn bridge() -> ModalBridge {
    ModalBridge::read(&data().join("modes.toml")).unwrap()
}

/// The full model's static displacement at every point under a constant
/// ground acceleration `a` with the springs, from the `[static]` table.
fn full_static(bridge: &ModalBridge, a: f64) -> Vec<f64> {
    let s = bridge.static_response.as_ref().unwrap();
    let (l, r) = (0, 1);
    assert_eq!((bridge.points[l].name.as_str(), bridge.points[r].name.as_str()), ("left end", "right end"));
    let f = &s.flexibility;
    // (I + F_PP K) u_P = a g_P, two by two
    let m = [[1.0 + f[l][l] * SPRINGS[0], f[l][r] * SPRINGS[1]], [f[r][l] * SPRINGS[0], 1.0 + f[r][r] * SPRINGS[1]]];
    let b = [a * s.ground_x[l], a * s.ground_x[r]];
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let up = [(b[0] * m[1][1] - m[0][1] * b[1]) / det, (m[0][0] * b[1] - m[1][0] * b[0]) / det];
    (0..bridge.points.len())
        .map(|o| a * s.ground_x[o] - f[o][l] * SPRINGS[0] * up[0] - f[o][r] * SPRINGS[1] * up[1])
        .collect()
}

/// Under a constant ground acceleration the bridge settles (its modes damped
/// at 90 % to settle fast) where the full model's statics put it: exactly
/// with the correction, whatever the number of modes kept; far from it
/// without, where the deck's stretching between the springs is missing.
#[test]
fn corrected_modes_settle_at_the_full_models_static_answer() {
    let bridge = bridge();
    let a = 1.0;
    let full = full_static(&bridge, a);
    for count in [1, 3, 5, 20] {
        let mut kept = bridge.kept(Some(count), 1.0, 0.05);
        for k in &mut kept {
            k.damping = 0.9;
        }
        let mut errors = [0.0f64; 2];
        for (corrected, error) in [false, true].into_iter().zip(&mut errors) {
            let ground = TimeSeries::uniform(0.0, 1.0, vec![a; 2]).unwrap().hold_last(true);
            let u = end_springs_run(&bridge, &kept, corrected, &ground, &end_springs(), (8.0, 1.0)).unwrap();
            for (p, want) in full.iter().enumerate() {
                *error = error.max((u[p].last().unwrap() - want).abs() / want.abs());
            }
        }
        eprintln!(
            "{count:>3} modes: static displacement {:.4} % from the full model's without the correction, {:.2e} % with",
            errors[0] * 100.0,
            errors[1] * 100.0
        );
        assert!(errors[1] < 1e-5, "{count} modes corrected: {:e}", errors[1]);
        if count <= 5 {
            assert!(errors[0] > 1e-3, "{count} modes: the correction should matter ({:e})", errors[0]);
        }
    }
}

fn opensees() -> (Vec<f64>, Vec<Vec<f64>>) {
    common::opensees_csv("opensees_corralitos090_end_springs.csv")
}

#[test]
fn end_springs_agree_with_opensees_and_the_correction_needs_fewer_modes() {
    let bridge = bridge();
    let (t, os) = opensees();
    let ground = corralitos(root()).unwrap();
    let dt = ground.times()[1];
    // the first 15 s hold the peaks (OpenSees' file runs to 45 s)
    let duration = 15.0;
    let n = (duration / dt).round() as usize;
    assert!((t[1] - t[0] - dt).abs() < 1e-12);
    let error = |u: &[Vec<f64>], p: usize| {
        let os = &os[2 * p][1..=n];
        let peak = os.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        u[p][..n].iter().zip(os).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / peak
    };
    let mut table = Vec::new();
    for (count, corrected) in [(3, false), (3, true), (5, false), (5, true), (10, false), (10, true), (124, false)] {
        let kept = bridge.kept(Some(count), 1.0, 0.05);
        let u = end_springs_run(&bridge, &kept, corrected, &ground, &end_springs(), (duration, dt)).unwrap();
        let ends = error(&u, 0).max(error(&u, 1));
        let piers = error(&u, 2).max(error(&u, 3));
        eprintln!(
            "{count:>3} modes, correction {corrected:>5}: deck ends' u within {:.3} %, pier tops' {:.3} % of OpenSees' peaks",
            ends * 100.0,
            piers * 100.0
        );
        table.push((count, corrected, ends, piers));
    }
    // all modes: the same equations as OpenSees'
    let all = table.last().unwrap();
    assert!(all.2 < 1e-3 && all.3 < 1e-3, "all modes: {all:?}");
    // the correction: within 1 % with 3 modes, and better than without at each count
    for pair in table[..6].chunks(2) {
        let (without, with) = (pair[0], pair[1]);
        assert!(with.2 < without.2, "{} modes: ends {} corrected vs {}", with.0, with.2, without.2);
    }
    assert!(table[1].2 < 0.01 && table[1].3 < 0.01, "3 modes corrected: {:?}", table[1]);
}

/// The small joint at both ends of the three-span bridge, pounding, with 3
/// modes and the correction, through a config (`bridge.modal.
/// static_correction`): the energy balance closes with the pseudo-modes in
/// it, the run does not warn about the flexibility it now has (it does
/// without the correction), and a modes file without `[static]` is refused
/// before any run, naming the field and the file.
#[test]
fn a_corrected_run_of_two_joints_closes_its_energy_balance_and_does_not_warn() {
    use quakejoint_model::run::{load_records, RunOptions};
    use quakejoint_model::runspec::{Overrides, RunSpec};
    use quakejoint_model::verification::modal::two_joints_on_three_span;
    let mut warned = Vec::new();
    for corrected in [false, true] {
        let mut config = two_joints_on_three_span(root(), "small.toml", 0.6, "[simulation]\nduration = 8.0\n").unwrap();
        let m = config.bridge.modal.as_mut().unwrap();
        m.modes_used = Some(3);
        m.static_correction = Some(corrected);
        let (x, _) = load_records(&config, root()).unwrap();
        let spec = RunSpec::new(config, &Overrides::default()).unwrap();
        let r = spec.run(&x.record, None, &RunOptions::default()).unwrap();
        eprintln!(
            "3 modes, correction {corrected}: joint forces {:.2} and {:.2} MN, energy balance {:.1e}",
            r.peak_joint_force / 1e6,
            r.joints.last().map_or(f64::NAN, |j| j.peak_joint_force) / 1e6,
            r.energy_error
        );
        assert!(r.energy_error < 1e-5, "energy balance {:e}", r.energy_error);
        let (_, warnings) = r.mode_check.unwrap();
        warned.push(warnings.iter().any(|w| w.contains("static flexibility")));
    }
    assert_eq!(warned, [true, false]);

    let dir = std::env::temp_dir().join(format!("qj-static-missing-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(data().join("modes.toml")).unwrap();
    std::fs::write(dir.join("modes.toml"), &text[..text.find("[static]").unwrap()]).unwrap();
    let mut config = two_joints_on_three_span(root(), "small.toml", 0.6, "").unwrap();
    config.bridge.modal.as_mut().unwrap().static_correction = Some(true);
    let e = config.load_modes(&dir).unwrap_err().to_string();
    assert!(e.contains("bridge.modal.static_correction") && e.contains("modes.toml"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
