//! A fuse box in an earthquake run.
//!
//! The small joint (3 center beams, 4 cells of 40 mm) under Loma Prieta
//! Corralitos 090 on the reference deck at 1 s (`configs/small.toml`):
//!
//! - At full scale its beams strike each other but center beam 1 never
//!   presses the abutment's edge beam: a fuse of any break force holds,
//!   and every result of the run is the run's without a fuse, bit for bit
//!   (no extra body exists until a fuse breaks).
//! - At twice the scale the deck's 0.4 m crush the closed joint against
//!   the abutment (a closed-joint force of the order of 1e8 N). A fuse of
//!   200 kN with 0.3 m of stroke breaks, its edge beam slides, the force
//!   on the deck stays below a few MN, and the energy balance closes with
//!   the fuse's friction in it.

mod common;

use quakejoint_model::run::{load_records, simulate_records, RunOptions, RunResult};

/// `configs/small.toml` with its record scaled by `scale` and `fuse` (a
/// `[joint.fuse]` body, or none).
fn run(scale: f64, fuse: Option<&str>) -> RunResult {
    let fuse = fuse.map_or(String::new(), |f| format!("[joint.fuse]\n{f}\n"));
    let text = std::fs::read_to_string(common::configs_dir().join("small.toml")).unwrap();
    let record = text.find("\n[record]").unwrap() + 1;
    let text = format!("{}{fuse}{}\nscale = {scale}\n", &text[..record], &text[record..]);
    let config =
        quakejoint_model::Config::from_toml(&text, &common::configs_dir().join("small.toml").display().to_string())
            .unwrap();
    let (x, _) = load_records(&config, &common::configs_dir()).unwrap();
    simulate_records(&config, &x.record, None, &RunOptions::default()).unwrap()
}

/// The run's fields but its fuse's and the machine's.
fn fields(r: &RunResult) -> Vec<(&'static str, u64)> {
    quakejoint_model::fields::FIELDS
        .iter()
        .filter(|f| !f.machine_dependent && !f.name.starts_with("fuse_"))
        .map(|f| (f.name, (f.value)(r).to_bits()))
        .collect()
}

#[test]
fn a_fuse_that_holds_leaves_every_result_unchanged() {
    let with = run(1.0, Some("kind = \"box\"\nbreak_force = 1e4\nstroke = 0.3"));
    let without = run(1.0, None);
    let fuse = with.joints[0].fuse.unwrap();
    assert!(!fuse.broke && fuse.break_time.is_nan() && fuse.stroke_used == 0.0);
    assert!(without.joints[0].fuse.is_none());
    assert_eq!(fields(&with), fields(&without));
    assert!(with.pounding.impacts > 0, "the beams strike each other");
}

#[test]
fn a_fuse_that_breaks_frees_the_edge_beam_and_the_energy_balance_closes() {
    let fuse = "kind = \"box\"\nbreak_force = 2e5\nstroke = 0.3";
    let with = run(2.0, Some(fuse));
    let without = run(2.0, None);
    let f = with.joints[0].fuse.unwrap();
    eprintln!(
        "{f:?}\nwith: deck force {:.3e} N, abutment {:.3e} N, energy error {:.1e}; without: deck force {:.3e} N",
        with.peak_joint_force, with.peak_abutment_force, with.energy_error, without.peak_joint_force
    );
    assert!(f.broke && (f.break_force / 2e5 - 1.0).abs() < 1e-3, "{f:?}");
    assert!(f.stroke_used > 0.0 && f.residual_offset > 0.0 && f.residual_offset <= f.stroke_used + 1e-9);
    assert!(f.energy > 0.0);
    // the break force reaches the abutment at the break (the joist pivots'
    // and the guide's reactions add their share)
    assert!(with.peak_abutment_force > f.break_force, "{} N", with.peak_abutment_force);
    assert!(with.energy_error < 1e-6, "energy balance error {:.1e}", with.energy_error);
    assert!(without.peak_joint_force > 1e7 && with.peak_joint_force < 1e-2 * without.peak_joint_force);
}

/// The three-span bridge with the small joint at each abutment (the right
/// one turned, `deck_side = "-x"`), each with a fuse box on a ramp, under
/// a record and under the same record reversed: the mirrored bridge swaps
/// the two joints, so the left fuse under `+a_g` does what the right one
/// does under `-a_g` (a check of the turned joint's fuse by symmetry:
/// its seat, stop, lift and friction act in its own x). At 1.5 times the
/// record both fuses break and both edge beams reach their stop: the
/// break and the travel to the stop agree to 1e-9; after the stop's
/// impacts the two runs, the same to rounding, part as pounding runs do
/// (the friction energies by 1.4 %, the residual offsets by 4 mm).
#[test]
fn the_mirrored_bridge_swaps_the_two_joints_fuses() {
    use quakejoint_model::verification::modal;
    let root = common::configs_dir().join("..");
    let fuse = "[joint.fuse]\nkind = \"box\"\nbreak_force = 1e4\nstroke = 0.2\nramp_deg = 10.0\n\
                [simulation]\nduration = 8.0\n";
    let run = |scale: f64| {
        let config = modal::two_joints_on_three_span(&root, "small.toml", scale, fuse).unwrap();
        modal::run(&root, &config).unwrap()
    };
    let (a, b) = (run(1.5), run(-1.5));
    let fuses = |r: &RunResult| [r.joints[0].fuse.unwrap(), r.joints[1].fuse.unwrap()];
    let ([left_a, right_a], [left_b, right_b]) = (fuses(&a), fuses(&b));
    eprintln!(
        "{left_a:?}\n{right_b:?}\n{right_a:?}\n{left_b:?}\nenergy balance {:.1e}, {:.1e}",
        a.energy_error, b.energy_error
    );
    for (x, y) in [(left_a, right_b), (right_a, left_b)] {
        assert_eq!(x.broke, y.broke);
        assert_eq!(x.stroke_exhausted, y.stroke_exhausted);
        assert!(x.broke && x.stroke_exhausted, "{x:?}");
        for (p, q) in [(x.break_time, y.break_time), (x.break_force, y.break_force), (x.stroke_used, y.stroke_used)] {
            assert!((p - q).abs() <= 1e-9 * p.abs(), "{p} against {q}: {x:?} {y:?}");
        }
        assert!((x.energy / y.energy - 1.0).abs() < 0.03, "{x:?} {y:?}");
    }
    assert!(a.energy_error < 1e-5 && b.energy_error < 1e-5, "{:.1e} {:.1e}", a.energy_error, b.energy_error);
}

/// A fuse element in the same crush (Corralitos 090 x 2 on the small
/// joint): center beam 2 leaves the plane at its release force, its two
/// cells act as one and close again, the joint gains the beam's width of
/// travel (90 mm) before it pushes the deck again; its contacts' elastic
/// energy as it left is the fuse's, and the energy balance closes with it.
/// A fuse element has no stroke: its stroke values are NaN.
#[test]
fn a_fuse_element_leaves_the_plane_and_the_energy_balance_closes() {
    let with = run(2.0, Some("kind = \"element\"\nbreak_force = 2e5\nbeam = 2"));
    let without = run(2.0, None);
    let f = with.joints[0].fuse.unwrap();
    eprintln!(
        "{f:?}\nwith: deck force {:.3e} N, abutment {:.3e} N, min subgap {:?} m, energy error {:.1e}, contact energy \
         {:.3e} J; without: deck force {:.3e} N, abutment {:.3e} N, min subgap {:?} m, contact energy {:.3e} J",
        with.peak_joint_force,
        with.peak_abutment_force,
        with.min_subgap,
        with.energy_error,
        with.pounding.contact_energy,
        without.peak_joint_force,
        without.peak_abutment_force,
        without.min_subgap,
        without.pounding.contact_energy
    );
    assert!(f.broke && (f.break_force / 2e5 - 1.0).abs() < 1e-3, "{f:?}");
    assert!(f.energy > 0.0, "{f:?}");
    let values = quakejoint_model::run::fuse::FuseResult::values(Some(&f));
    assert!(values[3..6].iter().all(|v| v.is_nan()), "{values:?}");
    assert!(with.energy_error < 1e-6, "energy balance error {:.1e}", with.energy_error);
    // (the deck closed the joint 90 mm less deep: 4.3e7 N against 2.4e8 N)
    assert!(with.peak_joint_force < 0.5 * without.peak_joint_force);
}
