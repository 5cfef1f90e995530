//! The bridge given by its modes (`[bridge.modal]`), against two
//! independent solutions.
//!
//! **One mode is the single-DOF deck.**
//! A deck of mass `M`, period `T` and damping ratio `zeta` is, as a modal
//! bridge, one mode of period `T` and damping `zeta` with the
//! mass-normalised shape `phi = 1/sqrt(M)` at its end and the participation
//! factor `Gamma = phi M 1 = sqrt(M)`. With the joint on it, the two
//! descriptions are the same equations in other coordinates (the modal
//! coordinate, a deck end tied to it by a linear constraint and of mass
//! 1e-6 M): the deck's spectral values, the joint's forces, friction work,
//! openings and impacts must agree to the integrator's accuracy, and
//! closer at tighter tolerances. Checked on the small joint (configs/small.toml)
//! on a light deck where the joint matters, with the record scaled so that
//! the joint stays open, and under the full record, where it pounds.
//!
//! **Without the joint, the multibody modes are the exact modal
//! superposition.** Two modes (one symmetric, one antisymmetric at the two
//! deck ends) integrated by Radau IIA as bodies tied to the deck end by the
//! linear constraint, with the joint disabled, against each mode's exact
//! piecewise-linear response (Nigam and Jennings) summed with its shape.

mod common;

use quakejoint_model::run::{simulate, RunOptions, RunResult};
use quakejoint_model::runspec::{Overrides, RunSpec};
use quakejoint_model::Config;

const MASS: f64 = 2.0e6;
const PERIOD: f64 = 1.0;
const DAMPING: f64 = 0.05;

fn run(modal: bool, scale: f64, tolerance_factor: f64) -> RunResult {
    let dir = std::env::temp_dir().join(format!("qj-modal-one-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let modes = dir.join("one_mode.toml");
    let phi = 1.0 / MASS.sqrt();
    std::fs::write(
        &modes,
        format!(
            "format = \"quakejoint-modes-1\"\nsource = \"the single-DOF deck\"\ntotal_mass_x = {MASS:e}\n\
             [[point]]\nname = \"deck end\"\ndirection = \"x\"\n\
             [[mode]]\nperiod = {PERIOD}\ndamping = {DAMPING}\nparticipation_x = {:e}\nshape = [{phi:e}]\n",
            MASS.sqrt()
        ),
    )
    .unwrap();
    let bridge = if modal {
        format!("[bridge.modal]\nmodes = \"{}\"\njoint_point = \"deck end\"\n", modes.display())
    } else {
        String::new()
    };
    let text = std::fs::read_to_string(common::configs_dir().join("small.toml")).unwrap();
    let text = text.replace("[record]\n", &format!("[record]\nscale = {scale}\n"));
    let mut config = Config::from_toml(
        &format!(
            "{text}\n[bridge]\nmass = {MASS:e}\nperiod = {PERIOD}\ndamping = {DAMPING}\n{bridge}\n\
             [simulation]\nrtol = {t:e}\natol = {t:e}\natol_rotation = {t:e}\n",
            t = 1e-6 * tolerance_factor,
        ),
        "small.toml",
    )
    .unwrap();
    config.load_modes(&dir).unwrap();
    simulate(&config, &common::configs_dir(), &RunOptions::default()).unwrap()
}

/// Largest relative difference of the compared values (the deck's, the
/// friction work, the earthquake's work and the widest cell).
fn difference(a: &RunResult, b: &RunResult) -> f64 {
    let pairs = [
        (a.sa, b.sa),
        (a.sd, b.sd),
        (a.friction_energy, b.friction_energy),
        (a.earthquake_work, b.earthquake_work),
        (a.max_subgap.unwrap(), b.max_subgap.unwrap()),
    ];
    pairs.iter().map(|(x, y)| ((x - y) / y).abs()).fold(0.0, f64::max)
}

#[test]
fn one_mode_is_the_single_dof_deck_with_the_joint_on_it() {
    for scale in [0.15, 1.0] {
        let (sdof, modal) = (run(false, scale, 1.0), run(true, scale, 1.0));
        let d = difference(&modal, &sdof);
        let (sdof_t, modal_t) = (run(false, scale, 0.01), run(true, scale, 0.01));
        let dt = difference(&modal_t, &sdof_t);
        eprintln!(
            "scale {scale}: Sa {:.6} vs {:.6} m/s^2, joint force {:.1} vs {:.1} N, impacts {} vs {}; largest relative \
             difference {d:.1e}, at 100x tighter tolerances {dt:.1e}",
            modal.sa,
            sdof.sa,
            modal.peak_joint_force,
            sdof.peak_joint_force,
            modal.pounding.impacts,
            sdof.pounding.impacts
        );
        assert!(d < 2e-3, "scale {scale}: relative difference {d:e}");
        // the peak joint force of a pounding run is an impact's spike, as
        // sensitive to the impact's timing as the two runs' own
        // tolerances make it
        let df = ((modal_t.peak_joint_force - sdof_t.peak_joint_force) / sdof_t.peak_joint_force).abs();
        assert!(df < 1e-2, "scale {scale}: peak joint force differs by {df:e} at tight tolerances");
        assert!(dt < 2e-4 && dt < d, "scale {scale}: at tighter tolerances {dt:e} (default {d:e})");
        assert_eq!(modal.pounding.impacts > 0, sdof.pounding.impacts > 0);
    }
}

const TWO_MODES: &str = "format = \"quakejoint-modes-1\"
source = \"two modes by hand\"
[[point]]
name = \"left end\"
direction = \"x\"
[[point]]
name = \"right end\"
direction = \"x\"
[[mode]]
period = 1.0
damping = 0.05
participation_x = 1300.0
shape = [7e-4, 7e-4]
[[mode]]
period = 0.3
participation_x = 300.0
shape = [5e-4, -5e-4]
";

#[test]
fn without_the_joint_the_multibody_modes_are_the_exact_superposition() {
    let dir = std::env::temp_dir().join(format!("qj-modal-two-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("two.toml"), TWO_MODES).unwrap();
    let text = std::fs::read_to_string(common::configs_dir().join("small.toml")).unwrap();
    for point in ["left end", "right end"] {
        let mut config = Config::from_toml(
            &format!(
                "{text}\n[bridge]\ndamping = 0.02\n[bridge.modal]\nmodes = \"{}\"\njoint_point = \"{point}\"\n",
                dir.join("two.toml").display()
            ),
            "small.toml",
        )
        .unwrap();
        config.load_modes(&dir).unwrap();
        config.joint.enabled = false;
        let (x, _) = quakejoint_model::run::load_records(&config, &common::configs_dir()).unwrap();
        let multibody =
            quakejoint_model::run::simulate_records(&config, &x.record, None, &RunOptions::default()).unwrap();
        let exact = RunSpec::new(config, &Overrides { alone: true, ..Default::default() })
            .unwrap()
            .run(&x.record, None, &RunOptions::default())
            .unwrap();
        let (da, dd) = ((multibody.sa - exact.sa).abs() / exact.sa, (multibody.sd - exact.sd).abs() / exact.sd);
        eprintln!(
            "{point}: Sa {:.6} (multibody) vs {:.6} m/s^2 (exact), Sd {:.6} vs {:.6} m; relative {da:.1e}, {dd:.1e}",
            multibody.sa, exact.sa, multibody.sd, exact.sd
        );
        assert!(da < 1e-3 && dd < 1e-3, "{point}: Sa {da:e}, Sd {dd:e}");
        assert!(multibody.energy_error < 1e-4, "energy balance {:e}", multibody.energy_error);
    }
}

/// A modes file that cannot be right is refused with the file and the
/// field named; a joint point the file does not have lists its points.
#[test]
fn bad_modes_files_name_the_file_and_the_field() {
    use quakejoint_model::modal::ModalBridge;
    let cases = [
        (TWO_MODES.replace("period = 0.3", "period = -0.3"), "m.toml: mode[1].period"),
        (TWO_MODES.replace("shape = [5e-4, -5e-4]", "shape = [5e-4]"), "m.toml: mode[1].shape"),
        (TWO_MODES.replace("name = \"right end\"", "name = \"left end\""), "m.toml: point[1].name"),
        (TWO_MODES.replace("quakejoint-modes-1", "modes-2"), "m.toml: format"),
        (TWO_MODES.replace("damping = 0.05", "damping = 1.5"), "m.toml: mode[0].damping"),
        (TWO_MODES.replace("participation_x = 300.0", "participation_x = nan"), "m.toml: mode[1].participation_x"),
    ];
    for (text, field) in cases {
        let e = ModalBridge::parse(&text, "m.toml").unwrap_err().to_string();
        assert!(e.starts_with(field), "{field}: {e}");
    }
    let ok = ModalBridge::parse(TWO_MODES, "m.toml").unwrap();
    let e = ok.point("middle", quakejoint_model::modal::Direction::X, "bridge.modal.joint_point").unwrap_err();
    let e = e.to_string();
    assert!(e.contains("bridge.modal.joint_point") && e.contains("\"left end\"") && e.contains("\"right end\""), "{e}");
    // the longest periods first, each scaled
    let kept = ok.kept(Some(1), 2.0, 0.02);
    assert_eq!(kept.len(), 1);
    assert!((kept[0].omega - std::f64::consts::PI).abs() < 1e-12 && kept[0].damping == 0.05);
    assert_eq!(ok.kept(None, 1.0, 0.02)[1].damping, 0.02);
}

/// The static correction of a file with two modes keeping one: the full
/// model's flexibility is both modes' `sum phi phi^T / w^2`, so what is left
/// is mode 2 alone, and its one pseudo-mode is mode 2 taken statically: the
/// spring `w2^2 / |phi2|^2` on the coordinate along `phi2 / |phi2|`, pushed
/// by the ground through `Gamma2 / |phi2|` (by hand). Without a `[static]`
/// table, or with one that holds less than the kept mode, the correction is
/// refused, naming the field and the file.
#[test]
fn static_correction_of_two_modes_keeping_one_is_the_second_mode_taken_statically() {
    use quakejoint_model::modal::ModalBridge;
    let w = [2.0 * std::f64::consts::PI, 2.0 * std::f64::consts::PI / 0.3];
    let phi = [[7e-4, 7e-4], [5e-4, -5e-4]];
    let gamma = [1300.0, 300.0];
    let f = |a: usize, b: usize| (0..2).map(|i| phi[i][a] * phi[i][b] / (w[i] * w[i])).sum::<f64>();
    let g = |a: usize| -(0..2).map(|i| phi[i][a] * gamma[i] / (w[i] * w[i])).sum::<f64>();
    let table = format!(
        "[static]\nflexibility = [[{:e}, {:e}], [{:e}, {:e}]]\nground_x = [{:e}, {:e}]\n",
        f(0, 0),
        f(0, 1),
        f(1, 0),
        f(1, 1),
        g(0),
        g(1)
    );
    let bridge = ModalBridge::parse(&format!("{TWO_MODES}{table}"), "m.toml").unwrap();
    let kept = bridge.kept(Some(1), 1.0, 0.05);
    let c = bridge.static_correction(&kept, &[0, 1], 1.0, "m.toml").unwrap();
    assert_eq!(c.pseudo.len(), 1);
    let p = &c.pseudo[0];
    let norm = (phi[1][0] * phi[1][0] + phi[1][1] * phi[1][1]).sqrt();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs();
    assert!(close(p.stiffness, w[1] * w[1] / (norm * norm)), "{}", p.stiffness);
    // (the eigenvector's sign is free: shape and ground push flip together)
    let sign = p.shape[0].signum() * phi[1][0].signum();
    assert!(close(sign * p.shape[0], phi[1][0] / norm) && close(sign * p.shape[1], phi[1][1] / norm));
    assert!(close(sign * p.base_mass, gamma[1] / norm), "{}", p.base_mass);
    assert!(c.ground.iter().all(|&x| x == 0.0));
    // every mode kept: nothing left
    let all = bridge.static_correction(&bridge.kept(None, 1.0, 0.05), &[0, 1], 1.0, "m.toml").unwrap();
    assert!(all.pseudo.is_empty());

    // without ground_x: the flexibility alone, and the run says so
    let flexible = table.split("ground_x").next().unwrap().to_string();
    let only = ModalBridge::parse(&format!("{TWO_MODES}{flexible}"), "m.toml").unwrap();
    let c = only.static_correction(&kept, &[0, 1], 1.0, "m.toml").unwrap();
    assert!(close(c.pseudo[0].stiffness, w[1] * w[1] / (norm * norm)) && c.pseudo[0].base_mass == 0.0);
    let warned = only.mode_check(&kept, &[0, 1]).warnings(&only, &[0, 1], true, true);
    assert!(warned.iter().any(|w| w.contains("no ground_x")), "{warned:?}");

    let none = ModalBridge::parse(TWO_MODES, "m.toml").unwrap();
    let e = none.static_correction(&kept, &[0], 1.0, "m.toml").unwrap_err().to_string();
    assert!(e.contains("bridge.modal.static_correction") && e.contains("m.toml") && e.contains("[static]"), "{e}");
    // a table with less flexibility than the kept modes' does not belong to
    // them; halved at one point it is no flexibility matrix at all (not
    // positive semi-definite) and the file is refused as it is read
    let small = table.replacen(&format!("{:e}", f(0, 0)), &format!("{:e}", f(0, 0) * 0.5), 1);
    let e = ModalBridge::parse(&format!("{TWO_MODES}{small}"), "m.toml").unwrap_err().to_string();
    assert!(e.contains("m.toml: static.flexibility") && e.contains("positive semi-definite"), "{e}");
    let less = table.replacen(&format!("{:e}", f(1, 1)), &format!("{:e}", f(1, 1) * 0.9), 1);
    let wrong = ModalBridge::parse(&format!("{TWO_MODES}{less}"), "m.toml").unwrap();
    let e = wrong.static_correction(&kept, &[0, 1], 1.0, "m.toml").unwrap_err().to_string();
    assert!(e.contains("does not belong to these modes"), "{e}");
}

/// Across the bridge: two modes, one along x and one across (each with its
/// own point "deck end" in its direction, `phi = 1/sqrt(M)`, `Gamma =
/// sqrt(M)` in its direction only), are the single-DOF deck with its
/// transverse degree of freedom (`bridge.transverse_period`), the small
/// joint on it, Corralitos 090 along and 000 across: the joint's force on
/// the deck across and the deck's Sa across agree to the integrator's
/// accuracy.
#[test]
fn a_mode_across_is_the_decks_transverse_dof() {
    let (mass, tx, ty) = (2.0e6f64, 1.0, 0.6);
    let dir = std::env::temp_dir().join(format!("qj-modal-across-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (phi, gamma) = (1.0 / mass.sqrt(), mass.sqrt());
    std::fs::write(
        dir.join("xy.toml"),
        format!(
            "format = \"quakejoint-modes-1\"\n\
             [[point]]\nname = \"deck end\"\ndirection = \"x\"\n[[point]]\nname = \"deck end\"\ndirection = \"y\"\n\
             [[mode]]\nperiod = {tx}\nparticipation_x = {gamma:e}\nshape = [{phi:e}, 0.0]\n\
             [[mode]]\nperiod = {ty}\nparticipation_x = 0.0\nparticipation_y = {gamma:e}\nshape = [0.0, {phi:e}]\n"
        ),
    )
    .unwrap();
    let small = std::fs::read_to_string(common::configs_dir().join("small.toml")).unwrap();
    let joint = &small[small.find("\n[joint]\n").unwrap()..small.find("\n[record]\n").unwrap()];
    let records = format!(
        "[record]\nfile = \"{0}/RSN753_LOMAP_CLS090-hor2.AT2\"\nscale = 0.15\n\
         [record_y]\nfile = \"{0}/RSN753_LOMAP_CLS000-hor1.AT2\"\nscale = 0.15\n[simulation]\nduration = 15.0\n",
        common::configs_dir().join("../ground_motions").display()
    );
    let sdof_text = format!(
        "{joint}\n{records}[bridge]\nmass = {mass:e}\nperiod = {tx}\ntransverse_period = {ty}\ndamping = 0.05\n"
    );
    let modal_text = format!(
        "{joint}\n{records}[bridge]\ndamping = 0.05\n[bridge.modal]\nmodes = \"xy.toml\"\n\
         joint_point = \"deck end\"\njoint_point_y = \"deck end\"\n"
    );
    let run = |text: &str, modal: bool| {
        let mut c = Config::from_toml(text, "across.toml").unwrap();
        if modal {
            c.load_modes(&dir).unwrap();
        }
        let (x, y) = quakejoint_model::run::load_records(&c, &common::configs_dir()).unwrap();
        let y = y.unwrap();
        RunSpec::new(c, &Overrides::default()).unwrap().run(&x.record, Some(&y.record), &RunOptions::default()).unwrap()
    };
    let (sdof, modal) = (run(&sdof_text, false), run(&modal_text, true));
    let (a, b) = (sdof.transverse.unwrap(), modal.transverse.unwrap());
    let rel = |x: f64, y: f64| ((x - y) / y).abs();
    eprintln!(
        "across: Sa {:.6} (modal) vs {:.6} m/s^2, joint force {:.2} vs {:.2} N, Sd {:.6} vs {:.6} m; without the joint \
         {:.6} vs {:.6}",
        b.sa, a.sa, b.peak_joint_force, a.peak_joint_force, b.sd, a.sd, b.sa_without, a.sa_without
    );
    assert!(rel(b.sa, a.sa) < 2e-3 && rel(b.sd, a.sd) < 2e-3, "Sa {:e}, Sd {:e}", rel(b.sa, a.sa), rel(b.sd, a.sd));
    assert!(rel(b.peak_joint_force, a.peak_joint_force) < 1e-2);
    assert!(rel(b.sa_without, a.sa_without) < 1e-6, "without the joint: {} vs {}", b.sa_without, a.sa_without);
    assert!(rel(modal.sa, sdof.sa) < 2e-3);
}
