//! A fuse element driven through a prescribed closing, against the hand
//! calculation (the joint and its closing: `common/closing.rs`).
//!
//! Center beam 2 of the small joint is a fuse element of release force
//! `F_r`. The deck closes the joint by `A = 0.30 m`. With nothing holding
//! the beams, every cell carries the same force once the joint has
//! closed, the four cells in series with the two ends of each in
//! parallel, `K = 2 k / 4`: the closing force on beam 2 reaches `F_r` when
//! the deck has closed the joint by `4 c + F_r / K`, the release time.
//!
//! Beam 2 then leaves the plane and its two cells are one: beams 1 and 3
//! meet across `2 c + w` (its width `w` is room too). The joint, three
//! cells now (`K' = 2 k / 3`), closes again once the deck has moved `4 c
//! + w` and pushes the deck with `K' (A - 4 c - w)` at the turning point,
//! where without the fuse it pushed with `K (A - 4 c)`.
//!
//! As beam 2 leaves, its four contacts (two cells, two ends each, `F_r /
//! 2` on each) still hold `4 (F_r / 2)^2 / (2 k) = F_r^2 / (2 k)`: lost with
//! them, the fuse's energy, and the run's energy balance closes with it.
//! A stronger element releases later, one that never reaches its release
//! force changes nothing, bit for bit.

mod common;

use common::closing::{assert_breaks_later, assert_same_run, config, run, time_of_closing, CELLS, CLEAR, K_END, WIDTH};

/// How far the deck closes the joint \[m\].
const A: f64 = 0.30;

/// A fuse element at beam 2 of release force `f_r` \[N\].
fn element(f_r: f64) -> String {
    format!("kind = \"element\"\nbreak_force = {f_r}\nbeam = 2")
}

/// The release time of an element of `f_r` \[N\] by hand \[s\].
fn release_time(f_r: f64) -> f64 {
    time_of_closing(CELLS * CLEAR + f_r / (2.0 * K_END / CELLS), A)
}

#[test]
fn a_fuse_element_leaves_and_its_cells_close_as_one_as_the_hand_calculation_says() {
    let f_r = 2.0e4;
    let closed = run(&config(Some(&element(f_r))), A);
    let fuse = closed.fuse.unwrap();
    assert!(fuse.broke);
    // (to within the step's local error, atol 1e-6 m on a cell of 2 k)
    assert!((fuse.break_force - f_r).abs() < 2.0 * K_END * 1e-6, "released at {} N", fuse.break_force);
    let t = release_time(f_r);
    assert!((fuse.break_time - t).abs() < 5e-3, "released at {} s, by hand {t} s", fuse.break_time);
    // the contacts' elastic energy as it left (their damping carries a
    // little of the release force, c d' with the cells closing at 5 mm/s,
    // about 1 %: the energy is up to 2 % short)
    let held = f_r * f_r / (2.0 * K_END);
    let ratio = fuse.energy / held;
    assert!(ratio < 1.0 && ratio > 0.97, "its contacts held {} J, by hand {held} J", fuse.energy);
    // the three cells closed again: the deck's push at the turning point
    let by_hand = 2.0 * K_END / (CELLS - 1.0) * (A - CELLS * CLEAR - WIDTH);
    let peak = closed.peak_deck_force;
    assert!((peak / by_hand - 1.0).abs() < 0.01, "peak force on the deck {peak} N, by hand {by_hand} N");
    let without = run(&config(None), A).peak_deck_force;
    let whole = 2.0 * K_END / CELLS * (A - CELLS * CLEAR);
    assert!((without / whole - 1.0).abs() < 0.01, "without the fuse {without} N, by hand {whole} N");
    // a fuse element has no stroke
    let values = quakejoint_model::run::fuse::FuseResult::values(Some(&fuse));
    assert!(values[3].is_nan() && values[4].is_nan() && values[5].is_nan(), "{values:?}");
    let e = closed.sim.energy();
    assert!(e.error().abs() < 1e-4 * e.constraints, "energy balance error {} J of {} J", e.error(), e.constraints);
}

#[test]
fn a_stronger_fuse_element_leaves_later_in_the_same_closing() {
    let weak = run(&config(Some(&element(2.0e4))), A).fuse.unwrap();
    let strong = run(&config(Some(&element(4.0e4))), A).fuse.unwrap();
    assert_breaks_later(&weak, &strong, release_time(4.0e4));
}

#[test]
fn a_fuse_element_that_never_leaves_changes_nothing() {
    // (the closed joint's force peaks at K (A - 4 c) = 700 kN)
    assert_same_run(run(&config(Some(&element(1.0e6))), A), run(&config(None), A));
}

/// What a fuse element cannot be is refused, naming the key: no beam, a
/// beam the joint does not have, a joint of one beam, a box's values.
#[test]
fn a_fuse_element_that_cannot_work_is_refused_naming_its_key() {
    let refused = |joint: &str, fuse: &str| {
        let text = format!("[joint]\n{joint}\n[joint.fuse]\nkind = \"element\"\nbreak_force = 1e6\n{fuse}\n");
        quakejoint_model::Config::from_toml(&text, "element.toml").unwrap_err().to_string()
    };
    for (joint, fuse, key, says) in [
        ("center_beams = 3", "", "joint.fuse.beam", "needs its beam"),
        ("center_beams = 3", "beam = 4", "joint.fuse.beam", "has 3 center beams"),
        ("center_beams = 3", "beam = 0", "joint.fuse.beam", "must be within"),
        ("center_beams = 1", "beam = 1", "joint.fuse.beam", "2 center beams or more"),
        ("center_beams = 3", "beam = 2\nstroke = 0.3", "joint.fuse.stroke", "a fuse box's"),
        ("center_beams = 3", "beam = 2\nramp_deg = 10.0", "joint.fuse.ramp_deg", "a fuse box's"),
        ("center_beams = 3", "beam = 2\nmu = 0.3", "joint.fuse.mu", "a fuse box's"),
        ("center_beams = 3\n[joint.contact]\nenabled = false", "beam = 2", "joint.fuse", "contact"),
    ] {
        let e = refused(joint, fuse);
        assert!(e.contains(key) && e.contains(says), "{joint} / {fuse}: {e}");
    }
    let link =
        "[joint]\ncenter_beams = 3\nmodel = \"link\"\n[joint.link]\nstiffness = 1e7\nfriction = 1e5\nmass = 1e4\n\
                gap_stiffness = 1e8\n[joint.fuse]\nkind = \"element\"\nbreak_force = 1e6\nbeam = 2\n";
    // (the link element takes one: its gap lets go)
    assert!(quakejoint_model::Config::from_toml(link, "link.toml").is_ok());
    // and a box's beam
    let text = "[joint.fuse]\nkind = \"box\"\nbreak_force = 1e6\nstroke = 0.3\nbeam = 2\n";
    let e = quakejoint_model::Config::from_toml(text, "box.toml").unwrap_err().to_string();
    assert!(e.contains("joint.fuse.beam") && e.contains("fuse element's"), "{e}");
}

/// A service loop that closes the whole joint would break its fuse, which
/// the service case does not model: refused, naming the amplitude; one
/// that stays open runs.
#[test]
fn a_service_loop_that_would_break_the_fuse_is_refused() {
    let with = |amplitude: f64| {
        let text = format!(
            "[joint]\ncenter_beams = 3\n[joint.fuse]\nkind = \"element\"\nbreak_force = 1e6\nbeam = 2\n\
             [service]\namplitude = {amplitude}\ncycles = 1\n"
        );
        let config = quakejoint_model::Config::from_toml(&text, "service.toml").unwrap();
        quakejoint_model::service::service(&quakejoint_model::scenario::Scenario::new(config).unwrap())
    };
    // (4 cells of 40 mm: the joint closes at 0.16 m)
    let e = with(0.2).unwrap_err().to_string();
    assert!(e.contains("service.amplitude") && e.contains("0.16"), "{e}");
    assert!(with(0.05).is_ok());
}

/// A contact of a fuse element's merged cell is named by the cell's sides
/// after the beam left, by its own before.
#[test]
fn a_merged_cells_contact_is_named_by_its_sides() {
    let place = quakejoint_model::generator::ContactPlace { gap: 0, end: 0, center_beams: 3 };
    let released = Some((1, 3.5));
    assert_eq!(place.describe_after(released, 3.4), "the abutment's edge beam and center beam 1 (end y = -L/2)");
    let after = place.describe_after(released, 3.6);
    assert!(after.starts_with("the abutment's edge beam and center beam 2 (one cell since center beam 1"), "{after}");
    let deck = quakejoint_model::generator::ContactPlace { gap: 3, end: 1, center_beams: 3 };
    assert!(deck.describe_after(Some((3, 1.0)), 2.0).starts_with("center beam 2 and the deck's edge beam"));
    assert_eq!(deck.describe(), "center beam 3 and the deck's edge beam (end y = +L/2)");
}
