//! The link against the detailed joint where the cells decide: its racked
//! cells, and its fuse (the last test's doc).
//!
//! The link opens its cells alike, `g0 + u / (Nc + 1)` (the intercept
//! theorem). The detailed joint's cells do not: its center beams lag on
//! their bushings behind their intercept places while their bearings
//! slide, and under an earthquake their own inertia carries them further,
//! so its narrowest cell is narrower and its widest wider than the average
//! by several millimetres. That is what decides when its beams first
//! strike and when a cell reaches the movement capacity. The calibration
//! takes the racking from the detailed joint's own runs (the largest of its
//! service loops and of its calibration suite) and the link reports its
//! narrowest and widest cells with it.
//!
//! Checked against the detailed joint itself (a second model, not the
//! link's earlier output), under records the link was not calibrated on:
//! the medium joint of configs/medium.toml calibrated under El Centro 270,
//! then run with its link and detailed on a 2e7 kg deck at 3 s under
//! Corralitos 090 and on a 1e7 kg deck at 1 s under the Pacoima Dam pulse
//! (254). The link's narrowest cell is at most the detailed joint's (0.5 mm
//! allowed: the racking is a suite's largest, not a bound), its widest at
//! least the detailed joint's (1 mm allowed), where the cells opening alike
//! miss by more than 4 mm on either side.

use std::path::{Path, PathBuf};

use quakejoint_model::calibrate::{calibrate, racking, CalibrationOptions};
use quakejoint_model::config::JointKind;
use quakejoint_model::link::{LinkParts, LinkWatch};
use quakejoint_model::run::{simulate_records, RunOptions, RunResult};
use quakejoint_model::scenario::Scenario;
use quakejoint_model::Config;
use quakejoint_motion::Record;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn record(file: &str) -> Record {
    scaled(file, 1.0)
}

fn scaled(file: &str, scale: f64) -> Record {
    let text =
        format!("[record]\nfile = \"{}\"\nscale = {scale}\n", root().join("ground_motions").join(file).display());
    let config = Config::from_toml(&text, "record.toml").unwrap();
    quakejoint_model::run::load_records(&config, Path::new(".")).unwrap().0.record
}

/// The medium joint on a deck of `mass` [kg] and `period` [s].
fn medium(mass: f64, period: f64) -> Config {
    let mut config = Config::from_file(&root().join("configs/medium.toml")).unwrap();
    config.bridge.mass = mass;
    config.bridge.w0 = None;
    config.bridge.period = Some(period);
    config
}

#[test]
fn the_links_racked_cells_bound_the_detailed_joints_under_records_it_was_not_calibrated_on() {
    let options =
        CalibrationOptions { records: vec![record("RSN6_IMPVALL.I_I-ELC270-hor2.AT2")], ..Default::default() };
    let c = calibrate(&Scenario::new(medium(1e8, 1.0)).unwrap(), &options).unwrap();
    let [rc, ro] = c.link.racking();
    eprintln!("racking {:.1} / {:.1} mm: {}", rc * 1e3, ro * 1e3, c.racking_from);
    let (cells, clear) = (c.cells as f64, 0.04);
    assert!((c.first_closure() - (c.gap - cells * rc)).abs() < 1e-12);
    for (mass, period, file) in [(2e7, 3.0, "RSN753_LOMAP_CLS090-hor2.AT2"), (1e7, 1.0, "RSN77_SFERN_PUL254-hor2.AT2")]
    {
        let detailed_config = medium(mass, period);
        let mut link_config = detailed_config.clone();
        link_config.joint.model = Some(JointKind::Link);
        link_config.joint.link = Some(c.link.clone());
        let r = record(file);
        let options = RunOptions { histories: true, ..Default::default() };
        let detailed = simulate_records(&detailed_config, &r, None, &options).unwrap();
        let link = simulate_records(&link_config, &r, None, &options).unwrap();
        let [dn, dw] = [detailed.min_subgap.unwrap(), detailed.max_subgap.unwrap()];
        let [ln, lw] = [link.min_subgap.unwrap(), link.max_subgap.unwrap()];
        // the link's cells opening alike, from its own deck's extremes
        let u = &link.histories.as_ref().unwrap().u;
        let lo = u.iter().copied().fold(0.0f64, f64::min);
        let hi = u.iter().copied().fold(0.0f64, f64::max);
        let [an, aw] = [clear + lo / cells, clear + hi / cells];
        eprintln!(
            "{mass:e} kg, {period} s, {file}: narrowest {:.1} (alike {:.1}) against {:.1} mm detailed, widest {:.1} \
             (alike {:.1}) against {:.1} mm",
            ln * 1e3,
            an * 1e3,
            dn * 1e3,
            lw * 1e3,
            aw * 1e3,
            dw * 1e3
        );
        assert!(ln <= dn + 5e-4 && lw >= dw - 1e-3, "the link's cells do not bound the detailed joint's");
        assert!(an > dn + 4e-3 && aw < dw - 4e-3, "the cells alike already bound them: the test shows nothing");
        assert!(detailed.validity.flags.is_ok() && link.validity.flags.is_ok());
    }
}

/// The link's watch by hand: 4 cells of 40 mm, racked 10 mm closing and 5
/// mm opening, a capacity of 70 mm.
#[test]
fn a_racked_cell_closes_first_and_the_widest_reaches_the_capacity_first() {
    let parts = LinkParts {
        deck: quakejoint_solver::BodyId::GROUND,
        slider: quakejoint_solver::BodyId::GROUND,
        stiffness: 1e6,
        damping: 0.0,
        abutment: quakejoint_solver::BodyId::GROUND,
        gap: 0.16,
        cells: 4,
        clear: 0.04,
        max_subgap: 0.07,
        racking: [0.01, 0.005],
        contact: None,
        gap_force: None,
    };
    let mut w = LinkWatch::default();
    // the average cell at 40 - 110/4 = 12.5 mm: the narrowest at 2.5 mm
    w.update(&parts, 0.0, -0.11, 0.0);
    assert!((w.cells(&parts)[0] - 0.0025).abs() < 1e-12 && w.cell_closures == 0);
    // at 40 - 130/4 = 7.5 mm the racked cell is closed, the joint not yet
    w.update(&parts, 1.0, -0.13, 0.0);
    assert_eq!((w.cell_closures, w.closures), (1, 0));
    assert_eq!(w.cells(&parts)[0], 0.0);
    // the whole joint closed 2 mm beyond its gap: the average's overlap
    w.update(&parts, 2.0, -0.162, 5e5);
    assert_eq!((w.cell_closures, w.closures), (1, 1));
    assert!((w.cells(&parts)[0] + 0.0005).abs() < 1e-12);
    // open again, then the widest cell: 40 + 100/4 + 5 = 70 mm, at the
    // capacity; beyond it at 101 mm
    w.update(&parts, 3.0, 0.1, 0.0);
    assert!(w.beyond_capacity_at.is_none());
    w.update(&parts, 4.0, 0.101, 0.0);
    assert_eq!(w.beyond_capacity_at, Some(4.0));
    assert!((w.cells(&parts)[1] - 0.07025).abs() < 1e-12);
    // closing again counts the racked cell's second closure
    w.update(&parts, 5.0, -0.13, 0.0);
    assert_eq!((w.cell_closures, w.closures), (2, 1));

    // a run's racking: narrowest 5 mm and widest 60 mm about an average
    // of 40 - 100/4 = 15 and 40 + 60/4 = 55 mm
    let r = racking(4, 0.04, &[0.0, -0.1, 0.06], [0.005, 0.06]);
    assert!((r[0] - 0.010).abs() < 1e-12 && (r[1] - 0.005).abs() < 1e-12);
    // a closed cell hides its racking
    assert!(racking(4, 0.04, &[-0.1], [0.0, 0.05])[0].is_nan());
}

#[test]
fn a_racking_that_closes_a_cell_at_rest_is_refused() {
    let text = "[joint]\nmodel = \"link\"\ncenter_beams = 3\n[joint.link]\nstiffness = 5e6\nfriction = 9e3\n\
                mass = 800.0\ngap_stiffness = 1e8\nracking_closing = 0.05\n";
    let e = Config::from_toml(text, "link.toml").unwrap_err().to_string();
    assert!(e.contains("joint.link.racking_closing") && e.contains("closed at rest"), "{e}");
    let ok = text.replace("racking_closing = 0.05", "racking_closing = 0.039");
    assert!(Config::from_toml(&ok, "link.toml").is_ok());
}

/// The medium joint with `fuse` on the paper's deck at 2.5 s under
/// Corralitos 090 x 3, detailed and as its link (from the service loops):
/// the two runs.
fn with_fuse(fuse: quakejoint_model::config::FuseConfig) -> (RunResult, RunResult) {
    let link = calibrate(&Scenario::new(medium(1e8, 2.5)).unwrap(), &CalibrationOptions::default()).unwrap().link;
    let mut detailed = medium(1e8, 2.5);
    detailed.joint.fuse = Some(fuse);
    let mut linked = detailed.clone();
    linked.joint.model = Some(JointKind::Link);
    linked.joint.link = Some(link);
    let r = scaled("RSN753_LOMAP_CLS090-hor2.AT2", 3.0);
    let d = simulate_records(&detailed, &r, None, &RunOptions::default()).unwrap();
    let l = simulate_records(&linked, &r, None, &RunOptions::default()).unwrap();
    (d, l)
}

/// The link with a fuse box against the detailed joint with the same fuse
/// (the fuse of docs/model.md, "Seismic fuse", on the link's closed
/// joint: the closed joint's force breaks it, as beam 1's on the edge
/// beam breaks the detailed joint's): the medium joint on the paper's deck
/// at 2.5 s under Corralitos 090 x 3, a 300 kN fuse with 0.3 m of stroke.
/// The deck is heavy (1e8 kg), so it moves alike with either joint and
/// closes both at the same time: the fuse breaks at the same instant
/// (4.42 s, 1 ms apart), at its break force, the freed beam runs into its
/// stop in both and its friction dissipates the same energy (within 1 %).
#[test]
fn the_links_fuse_breaks_as_the_detailed_joints() {
    let (d, l) = with_fuse(quakejoint_model::config::FuseConfig {
        kind: quakejoint_model::config::FuseKind::Box,
        break_force: 3e5,
        stroke: Some(0.3),
        beam: None,
        ramp_deg: 0.0,
        mu: 0.15,
        mass: None,
    });
    let (fd, fl) = (d.joints[0].fuse.unwrap(), l.joints[0].fuse.unwrap());
    eprintln!("detailed {fd:?}\nlink     {fl:?}");
    assert!(fd.broke && fl.broke);
    assert!((fd.break_time - fl.break_time).abs() < 5e-3, "{} {}", fd.break_time, fl.break_time);
    assert!((fl.break_force / 3e5 - 1.0).abs() < 1e-3);
    assert!(fd.stroke_exhausted && fl.stroke_exhausted);
    assert!((fl.energy / fd.energy - 1.0).abs() < 0.01, "{} {}", fl.energy, fd.energy);
    assert!(l.energy_error < 1e-6, "{}", l.energy_error);
}

/// The link with a fuse element against the detailed joint with the same
/// element (its middle beam, 300 kN), on the same heavy deck and record as
/// the fuse box above: the closed joint's force releases both at the same
/// instant, at the release force; both joints then close again a beam's
/// width later and push the deck again, and the energy balance closes
/// with the contacts' energy as the beam left.
#[test]
fn the_links_fuse_element_leaves_as_the_detailed_joints() {
    let (d, l) = with_fuse(quakejoint_model::config::FuseConfig {
        kind: quakejoint_model::config::FuseKind::Element,
        break_force: 3e5,
        stroke: None,
        beam: Some(5),
        ramp_deg: 0.0,
        mu: quakejoint_model::config::DEFAULT_FUSE_MU,
        mass: None,
    });
    let (fd, fl) = (d.joints[0].fuse.unwrap(), l.joints[0].fuse.unwrap());
    eprintln!(
        "detailed {fd:?} force {:.4e} N sa {:.5} min cell {:?}\nlink     {fl:?} force {:.4e} N sa {:.5} min cell {:?}",
        d.peak_joint_force, d.sa, d.min_subgap, l.peak_joint_force, l.sa, l.min_subgap
    );
    assert!(fd.broke && fl.broke);
    assert!((fd.break_time - fl.break_time).abs() < 5e-3, "{} {}", fd.break_time, fl.break_time);
    assert!((fl.break_force / 3e5 - 1.0).abs() < 1e-3 && (fd.break_force / 3e5 - 1.0).abs() < 1e-3);
    assert!(l.energy_error < 1e-6 && d.energy_error < 1e-6, "{} {}", l.energy_error, d.energy_error);
}
