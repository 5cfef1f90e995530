//! Validity flags: a run says when it leaves what the model can stand
//! behind, and only then.
//!
//! - collision (contact disabled): the small joint under the full
//!   Corralitos record closes its sub-gaps (the deck moves 0.14 m at T = 1
//!   s; four sub-gaps of 40 mm); the flag must be set exactly when the
//!   smallest clear sub-gap, reported independently, is below zero, and
//!   name that sub-gap's size; scaled as in `quick.toml` (0.15) the same run
//!   stays open and is `ok`.
//! - with contact (the default) the same run pounds instead: its beams touch
//!   through their contacts, which is not a flag; `penetration` is set
//!   exactly when the deepest penetration, reported independently, exceeds
//!   `joint.contact.max_penetration`; `capacity_exceeded` exactly when the
//!   largest clear sub-gap exceeds `joint.capacity.max_subgap` (80 mm: the
//!   small joint's uneven sub-gaps open to 117 mm here).
//! - a coarse record does not hide a collision: the record sampled at 0.1 s
//!   and the same piecewise-linear ground motion written out at 5 ms are
//!   one excitation; checked at least every 5 ms, both runs find the same
//!   smallest sub-gap (a check at the samples only found +2.2 mm against
//!   -3.8 mm).
//! - joist_pulled_out: a joist 0.55 m long whose pivot-to-box distance is
//!   sqrt((G0 + u)^2 + (G0 tan 13 deg)^2) = 0.534 m at rest is pulled out as
//!   soon as the joint opens by about 16 mm, which this run does.
//!
//! (The energy_balance flag is a safeguard: even at rtol = 0.1 the energy
//! balance of these runs closes to 4e-6, far below its threshold of 1e-3;
//! its logic is tested in `validity.rs`.)

mod common;

use quakejoint_model::run::{simulate, RunOptions};
use quakejoint_model::validity::Flags;

fn run(extra: &str) -> quakejoint_model::run::RunResult {
    let config = common::shipped_with("small.toml", extra);
    simulate(&config, &common::configs_dir(), &RunOptions::default()).unwrap()
}

#[test]
fn a_collision_is_flagged_exactly_when_a_sub_gap_closes() {
    let full =
        run("[simulation]\nduration = 8.0\n[joint.contact]\nenabled = false\n[joint.capacity]\nmax_subgap = 0.5\n");
    let min = full.min_subgap.unwrap();
    assert!(min < 0.0, "the small joint closes under the full record: {min}");
    assert!(full.validity.flags.contains(Flags::COLLISION), "{:?}", full.validity);
    let finding = &full.validity.findings[0];
    assert!(finding.contains(&format!("{:.1} mm", min * 1e3)), "{finding}");
    let scaled = common::shipped("quick.toml");
    let r = simulate(&common::at_omega(scaled, 6.3), &common::configs_dir(), &RunOptions::default()).unwrap();
    assert!(r.min_subgap.unwrap() > 0.0 && r.validity.flags.is_ok(), "{:?} {:?}", r.min_subgap, r.validity);
}

#[test]
fn pounding_is_physics_but_crushing_and_overopening_are_flagged() {
    let full = run("[simulation]\nduration = 8.0\n");
    let p = full.pounding;
    assert!(p.impacts > 0 && p.peak_contact_force > 0.0 && p.contact_energy > 0.0, "{p:?}");
    assert!(!full.validity.flags.contains(Flags::COLLISION) && !full.validity.flags.contains(Flags::PENETRATION));
    assert!(p.max_penetration < 0.005, "{p:?}");
    // the largest sub-gap against the capacity
    let max = full.max_subgap.unwrap();
    assert!(max > 0.08 && full.validity.flags.contains(Flags::CAPACITY_EXCEEDED), "{max} {:?}", full.validity);
    assert!(full.validity.message().contains(&format!("{:.1} mm", max * 1e3)), "{}", full.validity.message());
    let roomy = run("[simulation]\nduration = 8.0\n[joint.capacity]\nmax_subgap = 0.2\n");
    assert!(roomy.validity.flags.is_ok(), "{:?}", roomy.validity);
    // the deepest penetration against a limit just below it
    let limit = 0.9 * p.max_penetration;
    let strict = run(&format!(
        "[simulation]\nduration = 8.0\n[joint.capacity]\nmax_subgap = 0.2\n[joint.contact]\nmax_penetration = {limit}\n"
    ));
    assert_eq!(strict.validity.flags, Flags::PENETRATION, "{:?}", strict.validity);
    assert!(
        strict.validity.message().contains(&format!("{:.1} mm", p.max_penetration * 1e3)),
        "{}",
        strict.validity.message()
    );
}

#[test]
fn a_joist_longer_than_its_reach_is_flagged() {
    let text =
        "[joint.support_beam]\nlength = 0.55\n[record]\nfile = \"../ground_motions/RSN753_LOMAP_CLS090-hor2.AT2\"\n\
                scale = 0.2\n[simulation]\nduration = 6.0\n";
    let small = std::fs::read_to_string(common::configs_dir().join("small.toml")).unwrap();
    let small = small.split("[record]").next().unwrap().to_string();
    let config = quakejoint_model::Config::from_toml(&format!("{small}\n{text}"), "t.toml").unwrap();
    let r = simulate(&config, &common::configs_dir(), &RunOptions::default()).unwrap();
    assert!(r.validity.flags.contains(Flags::JOIST_PULLED_OUT), "{:?}", r.validity);
    assert!(r.validity.message().contains("beyond its length 0.55 m"), "{}", r.validity.message());
}

#[test]
fn a_coarse_record_does_not_hide_a_collision_between_its_samples() {
    use quakejoint_model::run::simulate_records;
    use quakejoint_motion::Record;
    let config = common::shipped_with("small.toml", "[simulation]\nduration = 6.0\n");
    let full = quakejoint_model::run::load_records(&config, &common::configs_dir()).unwrap().0.record;
    // every 20th sample (0.1 s), scaled to 0.7, and the same line joined
    // every 5 ms
    let coarse: Vec<f64> = full.acceleration.iter().step_by(20).map(|a| 0.7 * a).collect();
    let mut fine = Vec::new();
    for pair in coarse.windows(2) {
        for k in 0..20 {
            fine.push(pair[0] + (pair[1] - pair[0]) * k as f64 / 20.0);
        }
    }
    fine.push(*coarse.last().unwrap());
    let coarse = Record::new("coarse", 0.1, coarse).unwrap();
    let fine = Record::new("fine", 0.005, fine).unwrap();
    let options = RunOptions::default();
    let a = simulate_records(&config, &coarse, None, &options).unwrap();
    let b = simulate_records(&config, &fine, None, &options).unwrap();
    let (ga, gb) = (a.min_subgap.unwrap(), b.min_subgap.unwrap());
    assert!((ga - gb).abs() < 0.5e-3, "smallest sub-gap {ga} m (0.1 s record) against {gb} m (5 ms)");
    assert_eq!(a.validity.flags, b.validity.flags, "{:?} {:?}", a.validity, b.validity);
}

/// The first crossing of a limit is located on the dense output, not at the
/// sample that first sees it: the collision of the small joint without
/// contacts under the full record begins where the smallest sub-gap's
/// history, sampled every 5 ms independently of the root finding, crosses
/// zero (linear interpolation between the last sample above zero and the
/// first below, good to the curvature over 5 ms: 1 ms).
#[test]
fn a_limit_is_first_crossed_where_the_sub_gaps_history_crosses_it() {
    let config = common::shipped_with(
        "small.toml",
        "[simulation]\nduration = 8.0\n[joint.contact]\nenabled = false\n[joint.capacity]\nmax_subgap = 0.5\n",
    );
    let options = RunOptions { histories: true, ..RunOptions::default() };
    let r = simulate(&config, &common::configs_dir(), &options).unwrap();
    let h = r.histories.as_ref().unwrap();
    let smallest = |j: usize| h.subgaps.iter().map(|s| s[j]).fold(f64::INFINITY, f64::min);
    let k = (0..h.t.len()).find(|&j| smallest(j) < 0.0).expect("the sub-gaps close");
    let (g0, g1) = (smallest(k - 1), smallest(k));
    let interpolated = h.t[k - 1] + (h.t[k] - h.t[k - 1]) * g0 / (g0 - g1);
    let finding = &r.validity.findings[0];
    let first: f64 = finding
        .split("first below zero at t = ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("{finding}"));
    assert!(first > h.t[k - 1] - 1e-3 && first <= h.t[k] + 1e-3, "{first} outside ({}, {}]", h.t[k - 1], h.t[k]);
    assert!((first - interpolated).abs() < 1e-3, "located {first} s, interpolated {interpolated} s: {finding}");
    eprintln!("located {first} s, interpolated {interpolated:.5} s, samples {} and {} s", h.t[k - 1], h.t[k]);
}
