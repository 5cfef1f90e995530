//! The three-span bridge of `tests/data/three_span/` against OpenSees.
//!
//! A continuous girder of 40-60-40 m on two piers, built in openseespy
//! (`scripts/opensees/three_span.py`), its 124 modes exported to
//! `tests/data/three_span/modes.toml` and its response to Loma Prieta
//! Corralitos 090 computed by OpenSees' own linear transient analysis with
//! 5 % modal damping (`opensees_corralitos090.csv`; its README says how
//! each file was made). Without joints, the deck ends' displacement and
//! absolute acceleration from the modes file must agree with OpenSees' to
//! 1 % of their peaks with enough modes: by exact modal superposition and
//! through the multibody solver (the modes as bodies, the deck end tied to
//! them). The errors are printed against the number of modes.

mod common;

use std::path::PathBuf;

use quakejoint_model::linear::modal_history;
use quakejoint_model::modal::{Direction, ModalBridge};
use quakejoint_model::run::{load_records, simulate_records, RunOptions};
use quakejoint_model::Config;

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/three_span")
}

fn opensees() -> (Vec<f64>, Vec<Vec<f64>>) {
    common::opensees_csv("opensees_corralitos090.csv")
}

/// max |a - b| over the common samples / max |b| there.
fn error(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let peak = b[..n].iter().fold(0.0f64, |m, x| m.max(x.abs()));
    a[..n].iter().zip(&b[..n]).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())) / peak
}

fn config(modes_used: usize, point: &str) -> Config {
    let text = format!(
        "[record]\nfile = \"{}\"\n[bridge]\ndamping = 0.05\n[bridge.modal]\nmodes = \"modes.toml\"\n\
         joint_point = \"{point}\"\nmodes_used = {modes_used}\n[joint]\nenabled = false\n",
        common::configs_dir().join("../ground_motions/RSN753_LOMAP_CLS090-hor2.AT2").display()
    );
    let mut c = Config::from_toml(&text, "three_span.toml").unwrap();
    c.load_modes(&data()).unwrap();
    c
}

#[test]
fn deck_ends_agree_with_opensees_without_joints() {
    let bridge = ModalBridge::read(&data().join("modes.toml")).unwrap();
    let (t, os) = opensees();
    let (x, _) = load_records(&config(124, "left end"), &common::configs_dir()).unwrap();
    let record = &x.record;
    assert!((t[1] - t[0] - record.dt).abs() < 1e-12, "OpenSees' output step is the record's");
    let mut table = Vec::new();
    for count in [1, 3, 5, 10, 20, bridge.modes.len()] {
        let kept = bridge.kept(Some(count), 1.0, 0.05);
        let mut worst = (0.0f64, 0.0f64);
        for (k, name) in ["left end", "right end"].into_iter().enumerate() {
            let p = bridge.point(name, Direction::X, "point").unwrap();
            let h = modal_history(record, &kept, p);
            worst.0 = worst.0.max(error(&h.u, &os[2 * k]));
            worst.1 = worst.1.max(error(&h.a_abs, &os[2 * k + 1]));
        }
        table.push((count, worst));
    }
    for (count, (u, a)) in &table {
        eprintln!(
            "{count:>4} modes: deck ends' u within {:.3} %, a_abs within {:.3} % of their peaks",
            u * 100.0,
            a * 100.0
        );
    }
    // three modes are enough for 1 %; all of them reach OpenSees' own time-stepping error
    let three = table[1].1;
    assert!(three.0 < 0.01 && three.1 < 0.01, "3 modes: {three:?}");
    let all = table.last().unwrap().1;
    assert!(all.0 < 1e-3 && all.1 < 1e-3, "all modes: {all:?}");

    // the multibody solver with 20 modes: the deck end's peaks
    let multibody = config(20, "right end");
    let r = simulate_records(&multibody, record, None, &RunOptions::default()).unwrap();
    let peak = |c: &[f64]| c.iter().take(record.acceleration.len()).fold(0.0f64, |m, x| m.max(x.abs()));
    let (sd, sa) = (peak(&os[2]), peak(&os[3]));
    let (du, da) = ((r.sd - sd).abs() / sd, (r.sa - sa).abs() / sa);
    eprintln!(
        "multibody, 20 modes, right end: Sd {:.6} m vs OpenSees {sd:.6} m ({:.3} %), Sa {:.5} vs {sa:.5} m/s^2 ({:.3} %)",
        r.sd,
        du * 100.0,
        r.sa,
        da * 100.0
    );
    assert!(du < 0.01 && da < 0.01, "multibody: Sd {du:e}, Sa {da:e}");
    // every point and the base shear: the solver's modes against the exact
    // superposition of the same 20 modes
    let kept = bridge.kept(Some(20), 1.0, 0.05);
    let alone = quakejoint_model::modal::modal_superposition(record, &kept, 0);
    let shear = alone.base_shear_peak();
    for (k, p) in r.points.iter().enumerate() {
        let [sd, sa] = alone.peaks(k);
        let (ed, ea) = ((p.sd - sd).abs() / sd, (p.sa - sa).abs() / sa);
        assert!(ed < 1e-4 && ea < 1e-4, "{}: Sd {ed:e}, Sa {ea:e}", p.name);
    }
    let v = r.base_shear.unwrap();
    eprintln!("base shear, 20 modes: {:.1} kN (multibody) vs {:.1} kN (exact)", v / 1e3, shear / 1e3);
    assert!((v - shear).abs() / shear < 1e-4, "base shear {v} vs {shear}");
}

/// The check of how many modes are enough, on the three-span bridge: the
/// kept modes' share of the full model's static flexibility (from
/// OpenSees' unit loads, the file's `[static]` table) at the deck ends and
/// between them grows with the modes kept and is the whole with every
/// mode; with 3 modes the deck's stretching between its ends is missing
/// (its axial modes are above 12 Hz) and the run warns.
#[test]
fn kept_modes_share_of_the_static_flexibility() {
    let bridge = ModalBridge::read(&data().join("modes.toml")).unwrap();
    let (l, r) =
        (bridge.point("left end", Direction::X, "p").unwrap(), bridge.point("right end", Direction::X, "p").unwrap());
    let mut last = (0.0, 0.0);
    for count in [3, 10, 20, 40, bridge.modes.len()] {
        let kept = bridge.kept(Some(count), 1.0, 0.05);
        let check = bridge.mode_check(&kept, &[l, r]);
        let (end, between) = (check.flexibility[l], check.between[0].2);
        eprintln!("{count:>4} modes: {:.1} % at the left end, {:.1} % between the ends", end * 100.0, between * 100.0);
        assert!(end >= last.0 && between >= last.1, "{count} modes: {end}, {between} after {last:?}");
        last = (end, between);
        let warned =
            check.warnings(&bridge, &[l, r], false, true).iter().any(|w| w.starts_with("between \"left end\""));
        assert_eq!(warned, between < quakejoint_model::modal::ENOUGH, "{count} modes");
    }
    assert!((last.0 - 1.0).abs() < 1e-6 && (last.1 - 1.0).abs() < 1e-6, "every mode: {last:?}");
    let three = bridge.mode_check(&bridge.kept(Some(3), 1.0, 0.05), &[l, r]);
    assert!(three.between[0].2 < 0.01 && !three.warnings(&bridge, &[l, r], false, true).is_empty());
}
