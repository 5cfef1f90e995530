//! Choosing a joint (docs/design.md): the cases of a multiple-stripe sweep
//! as candidate joints, target annual frequencies on the limit states.
//!
//! The small joint (3 center beams, 4 gaps), the same with 5 center beams
//! (6 gaps) and with a fuse box of 200 kN, under four records scaled to
//! PGA stripes (scaled to PGA the records move the deck unlike each other,
//! so that the curves are fitted), on a hazard that is one power law,
//! `H(a) = k0 a^-k`, so that a lognormal fragility's annual frequency has
//! the closed form `k0 theta^-k exp(k^2 beta^2 / 2)`.
//!
//! - Each fitted curve's annual frequency equals the closed form from its
//!   stored median and dispersion.
//! - The table is the curves': the value checked is the upper end of the
//!   annual frequency's bootstrap interval, pass when it is at most the
//!   target; a fuse's limit state of a joint without a fuse cannot happen
//!   (0, pass).
//! - The recommendation is the passing candidate with the fewest gaps.
//! - A changed target refits without running a job, and the
//!   recommendation follows the new table.

mod common;

use common::{config, dir, root, run, stdout};
use quakejoint_sweep::sweep_h5::read_sweep;

const K0: f64 = 1e-4;
const K: f64 = 2.5;

/// The sweep with the target `abutment` on the abutment force above 1 MN
/// \[1/year\].
fn sweep(abutment: f64) -> String {
    let record = |name: &str| root().join("ground_motions").join(name);
    format!(
        "[sweep]\nperiods = [1.0]\nrecords = [{{ file = {:?} }}, {{ file = {:?} }}, {{ file = {:?} }}, {{ file = {:?} }}]\n\
         [sweep.stripes]\nmeasure = \"pga\"\nlevels = [0.2, 0.4, 0.6, 0.8, 1.0, 1.3]\n\
         [sweep.fragility]\nbootstrap = 100\n\
         hazard = {{ intensity = [0.1, 1.0], frequency = [{}, {K0}] }}\n\
         [[sweep.fragility.limit_states]]\nkind = \"abutment_force\"\nforce = 1e6\ntarget = {abutment:e}\n\
         [[sweep.fragility.limit_states]]\nkind = \"fuse_broken\"\ntarget = 1e-2\n\
         [[sweep.cases]]\nname = \"3 beams\"\n\
         [[sweep.cases]]\nname = \"5 beams\"\njoint.center_beams = 5\n\
         [[sweep.cases]]\nname = \"3 beams, fuse\"\njoint.fuse = {{ kind = \"box\", break_force = 2e5, stroke = 0.3 }}\n",
        record("RSN753_LOMAP_CLS090-hor2.AT2"),
        record("RSN753_LOMAP_CLS000-hor1.AT2"),
        record("RSN6_IMPVALL.I_I-ELC180-hor1.AT2"),
        record("RSN6_IMPVALL.I_I-ELC270-hor2.AT2"),
        K0 * 10f64.powf(K),
    )
}

#[test]
fn the_design_table_is_the_curves_and_the_recommendation_the_fewest_gaps_that_pass() {
    let d = dir("design");
    let cfg = config(&d, "design.toml", &sweep(2e-3), 8.0);
    let out = d.join("design.h5");
    let o = run(&["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap()]);
    assert!(matches!(o.status.code(), Some(0 | 4)), "{}", common::stderr(&o));
    let f = read_sweep(&out).unwrap();
    let fr = f.fragility.as_ref().unwrap();
    let rows = quakejoint_sweep::fragility::rows(fr, &f.results, &|_, _, _| String::new());
    let candidates = quakejoint_sweep::fragility::design::candidates_of(&f.cases, &f.case_configs);
    assert_eq!(candidates.iter().map(|c| c.cells).collect::<Vec<_>>(), [4, 6, 4]);
    let designs = quakejoint_sweep::fragility::design::designs(fr, &rows, &candidates);
    assert_eq!(designs.len(), 1);
    let design = &designs[0];
    // the closed form of every fitted curve
    for r in rows.iter().filter(|r| r.annual_frequency.is_finite()) {
        let closed = K0 * r.median.powf(-K) * (0.5 * K * K * r.beta * r.beta).exp();
        assert!(
            (r.annual_frequency / closed - 1.0).abs() < 1e-6,
            "{}: {} against {closed}",
            r.name,
            r.annual_frequency
        );
    }
    // the table from the curves
    for (c, checks) in design.checks.iter().enumerate() {
        for ((key, _, target), check) in design.targets.iter().zip(checks) {
            let row = rows.iter().find(|r| &r.key == key && r.at[0] == c).unwrap();
            if key == "fuse_broken" && c < 2 {
                assert_eq!((check.upper, check.pass), (0.0, true), "no fuse: it cannot happen");
                continue;
            }
            if row.annual_frequency.is_finite() {
                assert_eq!(check.upper, row.annual_frequency_interval[1], "{key} of {c}");
            }
            assert_eq!(check.pass, check.upper <= *target, "{key} of {c}: {check:?}");
        }
    }
    let passing: Vec<usize> = (0..3).filter(|&c| design.checks[c].iter().all(|k| k.pass)).collect();
    let fewest = passing.iter().copied().min_by_key(|&c| (candidates[c].cells, c));
    assert_eq!(design.recommended, fewest);
    assert!(fewest.is_some(), "{design:?}");
    let said =
        format!("recommended: {} ({} gaps)", candidates[fewest.unwrap()].name, candidates[fewest.unwrap()].cells);
    assert!(stdout(&o).contains(&said), "{}", stdout(&o));

    // a target under what the joint without a fuse gives: refitted, no job
    // run again, the recommendation from the new table
    let upper = design.checks[0][0].upper;
    let stricter = 0.5 * upper;
    std::fs::write(
        &cfg,
        std::fs::read_to_string(&cfg).unwrap().replace("target = 2e-3", &format!("target = {stricter:e}")),
    )
    .unwrap();
    let o = run(&["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap(), "--json"]);
    assert!(matches!(o.status.code(), Some(0 | 4)), "{}", common::stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["ran"], 0, "a changed target runs no job");
    let d2 = &v["design"][0];
    assert_eq!(d2["candidates"][0]["meets_every_target"], false);
    let expected = (0..3)
        .filter(|&c| c != 0 && design.checks[c][0].upper <= stricter && design.checks[c][1].pass)
        .min_by_key(|&c| (candidates[c].cells, c))
        .map(|c| candidates[c].name.clone());
    assert_eq!(d2["recommended"].as_str().map(str::to_string), expected);
}
