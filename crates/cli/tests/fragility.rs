//! Multiple-stripe sweeps (`[sweep.stripes]`, `[sweep.fragility]`).
//!
//! Four records (Corralitos 090 and 000, El Centro 180 and 270) are scaled to five levels of
//! Sa(1 s, 5 %) on the small three-beam joint, whose cell at the deck
//! takes most of the opening and reaches its 80 mm capacity when the deck
//! has moved about 45 mm: at the lowest stripe (Sd 5 mm) no cell does, at
//! the highest (Sd 75 mm) one does in every run. Runs flagged beyond
//! capacity end the command with exit code 4, as every flagged sweep.
//!
//! - Scaling: the bridge alone's pseudo-spectral acceleration at the
//!   measure's period (computed by the sweep for the spectrum without the
//!   joint, independently of the scaling) equals each stripe's level.
//! - The outcome of each limit state is the run's own flag or field.
//! - Determinism (the records scaled to PGA, whose stripes overlap, so
//!   that curves are fitted): 1 and 2 threads and 2 shards merged give the same
//!   `/fragility`, bit for bit (read back, every stored curve is computed
//!   again from the results and must agree).
//! - A changed `[sweep.fragility]` refits a finished sweep without
//!   running a job again.
//! - What stripes cannot be is refused, naming the field.

mod common;

use std::path::Path;

use common::{assert_identical, config, dir, root, run, stderr, stdout};
use quakejoint_model::validity::Flags;
use quakejoint_sweep::fragility::{outcome, rows};
use quakejoint_sweep::results::{status, Results};
use quakejoint_sweep::sweep_h5::read_sweep;

/// Levels of PGA [g]: scaled to PGA the records move the deck unlike
/// each other, so that stripes overlap and the curves are determined
/// (scaled to Sa(1 s) every record moves the heavy deck alike, and the
/// joint's limit states are all or nothing at each stripe).
const PGA: &str = "[0.05, 0.1, 0.15, 0.2, 0.3, 0.4]";

/// A sweep that finished: exit 0, or 4 when runs are flagged.
fn ok(out: &std::process::Output) {
    assert!(matches!(out.status.code(), Some(0 | 4)), "exit {:?}: {}", out.status.code(), stderr(out));
}

const LEVELS: [f64; 5] = [0.02, 0.1, 0.15, 0.2, 0.3];

fn records() -> String {
    let record = |name: &str| root().join("ground_motions").join(name);
    format!(
        "records = [{{ file = {:?} }}, {{ file = {:?} }}, {{ file = {:?} }}, {{ file = {:?} }}]\n",
        record("RSN753_LOMAP_CLS090-hor2.AT2"),
        record("RSN753_LOMAP_CLS000-hor1.AT2"),
        record("RSN6_IMPVALL.I_I-ELC180-hor1.AT2"),
        record("RSN6_IMPVALL.I_I-ELC270-hor2.AT2")
    )
}

/// The sweep: `measure` at `levels` [g], `fragility`: more keys of
/// `[sweep.fragility]`.
fn stripes(measure: &str, levels: &str, fragility: &str) -> String {
    format!(
        "[sweep]\nperiods = [1.0]\n{}\
         [sweep.stripes]\nmeasure = \"{measure}\"\nlevels = {levels}\n\
         [sweep.fragility]\n{fragility}\
         hazard = {{ intensity = [0.1, 1.0, 10.0], frequency = [1e-2, 1e-4, 1e-6] }}\n\
         [[sweep.fragility.limit_states]]\nkind = \"capacity\"\n\
         [[sweep.fragility.limit_states]]\nkind = \"pounding\"\n\
         [[sweep.fragility.limit_states]]\nkind = \"field\"\nfield = \"sd\"\nabove = 0.1\n\
         [[sweep.fragility.limit_states]]\nkind = \"deck\"\nmeasure = \"sd\"\nabove = 0.1\n",
        records()
    )
}

#[test]
fn stripes_scale_every_record_to_every_level_and_count_the_runs() {
    let d = dir("fragility_stripes");
    let cfg = config(&d, "stripes.toml", &stripes("sa", "[0.02, 0.1, 0.15, 0.2, 0.3]", "bootstrap = 40\n"), 4.0);
    let out = d.join("s.h5");
    let o = run(&["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap()]);
    ok(&o);
    assert!(stdout(&o).contains("fragility: Sa(1 s, 5 %) at 5 stripes"), "{}", stdout(&o));
    let f = read_sweep(&out).unwrap();
    let fr = f.fragility.as_ref().expect("a multiple-stripe sweep stores /fragility");
    assert_eq!(f.records.len(), 20);
    assert_eq!(f.records[0].name, "RSN753_LOMAP_CLS090-hor2@0.02g");
    assert_eq!(f.records[17].name, "RSN753_LOMAP_CLS000-hor1@0.3g");
    let r = &f.results;
    for (i, run) in fr.stripes.runs.iter().enumerate() {
        let level = LEVELS[run.stripe];
        // the bridge alone, solved exactly by the sweep: psa is the measure
        let psa = r.without[1][r.without_index(i)] / quakejoint_motion::G;
        assert!((psa / level - 1.0).abs() < 1e-12, "record {i}: psa {psa} g at the stripe {level} g");
        assert!((run.factor * fr.stripes.ground[run.ground].1 / level - 1.0).abs() < 1e-12);
    }
    assert!(r.status.iter().all(|&s| s == status::OK));
    let evaluated = fr.evaluate(r);
    let sd = Results::field("sd");
    for j in 0..r.status.len() {
        assert_eq!(evaluated[0].outcome[j], i8::from(Flags(r.validity[j]).contains(Flags::CAPACITY_EXCEEDED)));
        assert_eq!(evaluated[2].outcome[j], i8::from(r.values[sd][j] > 0.1));
        assert_eq!(evaluated[4].outcome[j], i8::from(r.without[2][r.without_index(j)] > 0.1));
    }
    let capacity = &evaluated[0].curves[0];
    let exceeded: Vec<u32> = capacity.counts.iter().map(|k| k.exceeded).collect();
    assert_eq!(exceeded.first(), Some(&0), "no cell beyond capacity at 0.02 g");
    assert_eq!(exceeded.last(), Some(&4), "a cell beyond capacity in every run at 0.3 g");
    assert!(evaluated.iter().all(|ls| ls.outcome.iter().all(|&o| o != outcome::FAILED)));
    // the deck's displacement with the joint: flagged runs are reported in the note
    let flagged: u32 = evaluated[2].curves[0].counts.iter().map(|k| k.flagged).sum();
    assert!(flagged == 0 || evaluated[2].curves[0].note.contains("flagged"));
}

#[test]
fn stripes_are_deterministic_across_threads_and_shards_and_refit_without_running() {
    let d = dir("fragility_determinism");
    let cfg = config(&d, "stripes.toml", &stripes("pga", PGA, "bootstrap = 200\n"), 4.0);
    let cfgs = cfg.to_str().unwrap();
    let path = |n: &str| d.join(n).to_str().unwrap().to_string();
    let sweep = |out: &str, extra: &[&str]| {
        let mut args = vec!["sweep", cfgs, "--output", out, "--json"];
        args.extend_from_slice(extra);
        ok(&run(&args));
    };
    sweep(&path("t1.h5"), &["--threads", "1"]);
    let one = read_sweep(Path::new(&path("t1.h5"))).unwrap();
    let curves = |f: &quakejoint_sweep::sweep_h5::SweepFile| {
        let fr = f.fragility.as_ref().unwrap();
        rows(fr, &f.results, &|_, _, _| String::new())
            .iter()
            .flat_map(|r| [r.median, r.beta, r.median_interval[0], r.median_interval[1], r.annual_frequency])
            .map(f64::to_bits)
            .collect::<Vec<u64>>()
    };
    assert!(curves(&one).iter().any(|&b| f64::from_bits(b).is_finite()), "some curve is fitted");
    sweep(&path("t2.h5"), &["--threads", "2"]);
    let two = read_sweep(Path::new(&path("t2.h5"))).unwrap();
    assert_identical(&two, &one, "2 threads vs 1");
    assert_eq!(curves(&two), curves(&one));
    let shards: Vec<String> = (1..=2).map(|k| path(&format!("s{k}.h5"))).collect();
    for (k, s) in shards.iter().enumerate() {
        sweep(s, &["--shard", &format!("{}/2", k + 1), "--threads", "1"]);
    }
    let merged = path("merged.h5");
    let o = run(&["merge", &shards[0], &shards[1], "--output", &merged, "--json"]);
    ok(&o);
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    assert_eq!(v["fragility"]["curves"].as_array().map(Vec::len), Some(5), "the merge's curves: {v}");
    let merged = read_sweep(Path::new(&merged)).unwrap();
    assert_identical(&merged, &one, "2 shards merged vs 1 thread");
    assert_eq!(curves(&merged), curves(&one));

    // another bootstrap: the same jobs (the config's hash leaves the
    // fitting out), refitted
    let cfg = config(&d, "stripes.toml", &stripes("pga", PGA, "bootstrap = 100\n"), 4.0);
    let o = run(&["sweep", cfg.to_str().unwrap(), "--output", &path("t1.h5"), "--json"]);
    ok(&o);
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    assert_eq!(v["ran"], 0, "no job runs again: {v}");
    assert!(v["notices"][0].as_str().unwrap().contains("refitted"), "{v}");
    let refit = read_sweep(Path::new(&path("t1.h5"))).unwrap();
    assert_eq!(refit.fragility.as_ref().unwrap().spec.bootstrap, 100);
    assert_ne!(curves(&refit), curves(&one), "the intervals come from 100 resamples now");
    // the shards, fitted with 200 resamples, merged with the config's 100
    let remerged = path("remerged.h5");
    let o = run(&["merge", &shards[0], &shards[1], "--output", &remerged, "--config", cfg.to_str().unwrap()]);
    ok(&o);
    assert!(stderr(&o).contains("fitted with the config's"), "{}", stderr(&o));
    assert_eq!(curves(&read_sweep(Path::new(&remerged)).unwrap()), curves(&refit));
}

/// Runs stopped by a step limit (`simulation.max_steps`) at the two
/// highest stripes: left out and reported, or counted as exceeding, as
/// `failed` says; never silently.
#[test]
fn failed_runs_are_left_out_or_counted_as_the_config_says() {
    let d = dir("fragility_failed");
    for (policy, outcome_of_failed) in [("exclude", outcome::FAILED), ("exceed", outcome::EXCEEDED)] {
        let sweep = stripes("pga", PGA, &format!("bootstrap = 0\nfailed = \"{policy}\"\n"))
            + "[[sweep.cases]]\nname = \"limited\"\nsimulation.max_steps = 400\n";
        let cfg = config(&d, &format!("{policy}.toml"), &sweep, 4.0);
        let out = d.join(format!("{policy}.h5"));
        let o = run(&["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap(), "--json"]);
        assert!(!o.status.success(), "jobs failed: the sweep says so with its exit code");
        let f = read_sweep(&out).unwrap();
        let fr = f.fragility.as_ref().unwrap();
        let r = &f.results;
        let failed: Vec<usize> = (0..r.status.len()).filter(|&j| r.status[j] != status::OK).collect();
        assert!(!failed.is_empty(), "the step limit stops some runs");
        let evaluated = fr.evaluate(r);
        for j in &failed {
            assert_eq!(evaluated[0].outcome[*j], outcome_of_failed, "{policy}: job {j}");
        }
        let curve = &evaluated[0].curves[0];
        let counted_failed: u32 = curve.counts.iter().map(|k| k.failed).sum();
        assert_eq!(counted_failed as usize, failed.len(), "{policy}");
        assert!(curve.note.contains(&format!("{} failed runs", failed.len())), "{policy}: {}", curve.note);
        let runs: u32 = curve.counts.iter().map(|k| k.runs).sum();
        let expected = if policy == "exclude" { 24 - failed.len() } else { 24 };
        assert_eq!(runs as usize, expected, "{policy}");
        let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
        assert!(v["fragility"]["curves"][0]["note"].as_str().unwrap().contains("failed runs"), "{v}");
    }
}

#[test]
fn what_stripes_cannot_be_is_refused_naming_the_field() {
    let d = dir("fragility_refused");
    let r = records();
    let cases: [(&str, String, &str); 9] = [
        (
            "two periods",
            format!("[sweep]\nperiods = [1.0, 2.0]\n{r}[sweep.stripes]\nmeasure = \"sa\"\nlevels = [0.1, 0.2]\n"),
            "sweep.stripes.measure",
        ),
        (
            "a suite",
            format!(
                "[sweep]\nperiods = [1.0]\n{r}[sweep.stripes]\nmeasure = \"pga\"\nlevels = [0.1, 0.2]\n\
                 [sweep.suite]\ntarget = {{ code = \"ec8\", type = 1, ground = \"C\", ag_g = 0.3 }}\n"
            ),
            "sweep.stripes",
        ),
        (
            "fragility without stripes",
            format!("[sweep]\nperiods = [1.0]\n{r}[sweep.fragility]\nbootstrap = 10\n"),
            "sweep.fragility",
        ),
        (
            "levels not increasing",
            format!("[sweep]\nperiods = [1.0]\n{r}[sweep.stripes]\nmeasure = \"pga\"\nlevels = [0.3, 0.2]\n"),
            "sweep.stripes.levels[1]",
        ),
        (
            "one level",
            format!("[sweep]\nperiods = [1.0]\n{r}[sweep.stripes]\nmeasure = \"pga\"\nlevels = [0.3]\n"),
            "sweep.stripes.levels",
        ),
        (
            "a record beyond 5 g",
            format!("[sweep]\nperiods = [1.0]\n{r}[sweep.stripes]\nmeasure = \"pga\"\nlevels = [1.0, 6.0]\n"),
            "sweep.stripes.levels[1]",
        ),
        (
            "a hazard curve in other units",
            format!(
                "[sweep]\nperiods = [1.0]\n{r}[sweep.stripes]\nmeasure = \"pga\"\nlevels = [0.1, 0.2]\n\
                 [sweep.fragility]\nhazard = {{ intensity = [5.0, 10.0, 20.0], frequency = [1e-2, 1e-3, 1e-4] }}\n"
            ),
            "do not reach the stripes",
        ),
        (
            "an unknown kind",
            format!(
                "[sweep]\nperiods = [1.0]\n{r}[sweep.stripes]\nmeasure = \"pga\"\nlevels = [0.1, 0.2]\n\
                 [[sweep.fragility.limit_states]]\nkind = \"collapse\"\n"
            ),
            "sweep.fragility.limit_states[0].kind",
        ),
        (
            "a field that is not stored",
            format!(
                "[sweep]\nperiods = [1.0]\n{r}[sweep.stripes]\nmeasure = \"pga\"\nlevels = [0.1, 0.2]\n\
                 [[sweep.fragility.limit_states]]\nkind = \"field\"\nfield = \"sdd\"\nabove = 1.0\n"
            ),
            "sweep.fragility.limit_states[0].field",
        ),
    ];
    for (what, sweep, field) in cases {
        let cfg = config(&d, "bad.toml", &sweep, 4.0);
        let out = d.join("bad.h5");
        let o = run(&["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap()]);
        assert!(!o.status.success(), "{what}: accepted");
        assert!(stderr(&o).contains(field), "{what}: {}", stderr(&o));
        assert!(!out.exists(), "{what}: an output was written");
    }
}

/// The fuse's limit states (`fuse_broken`, `fuse_stroke_exhausted`): on
/// the small joint at Sa(1 s) of 0.5 g (the joint never closes against
/// the abutment) and 1.5 g (the deck moves 0.35 to 0.43 m and crushes the
/// joint against the abutment without a fuse, some 5e8 N), without a fuse
/// and with fuse boxes of 200 kN with a stroke of 0.1 m and of 1 m. Each
/// run's outcome is its own `fuse_broken`, `fuse_stroke_exhausted`; a run
/// without a fuse is undetermined (not a run that held). The short stroke
/// is exhausted at 1.5 g (the joint then crushes against the stop, some
/// 1e8 N); on the long one the freed edge beam, held by 1.3 kN of
/// friction, travels 0.7 to 0.8 m and the abutment's force stays under
/// 1 MN (the break force, and the joist pivots' and guide's share as the
/// beams follow the edge beam: 0.56 to 0.65 MN).
#[test]
fn the_fuse_limit_states_are_the_runs_fuse_and_undetermined_without_one() {
    let d = dir("fragility_fuse");
    let record = |name: &str| root().join("ground_motions").join(name);
    let fuse = |stroke: f64| format!("{{ kind = \"box\", break_force = 2e5, stroke = {stroke} }}");
    let sweep = format!(
        "[sweep]\nperiods = [1.0]\nrecords = [{{ file = {:?} }}, {{ file = {:?} }}]\n\
         [sweep.stripes]\nmeasure = \"sa\"\nlevels = [0.5, 1.5]\n\
         [sweep.fragility]\nbootstrap = 0\n\
         [[sweep.fragility.limit_states]]\nkind = \"fuse_broken\"\n\
         [[sweep.fragility.limit_states]]\nkind = \"fuse_stroke_exhausted\"\n\
         [[sweep.cases]]\nname = \"no fuse\"\n\
         [[sweep.cases]]\nname = \"short stroke\"\njoint.fuse = {}\n\
         [[sweep.cases]]\nname = \"long stroke\"\njoint.fuse = {}\n",
        record("RSN753_LOMAP_CLS090-hor2.AT2"),
        record("RSN6_IMPVALL.I_I-ELC180-hor1.AT2"),
        fuse(0.1),
        fuse(1.0),
    );
    let cfg = config(&d, "fuse.toml", &sweep, 8.0);
    let out = d.join("fuse.h5");
    let o = run(&["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap()]);
    ok(&o);
    let said = "fuses: broke in 4 of the 8 finished job(s) with a seismic fuse, their stroke exhausted in 2";
    assert!(stdout(&o).contains(said), "{}", stdout(&o));
    let f = read_sweep(&out).unwrap();
    let fr = f.fragility.as_ref().unwrap();
    let r = &f.results;
    let evaluated = fr.evaluate(r);
    let field = Results::field;
    let (broken, exhausted, force) =
        (field("fuse_broken"), field("fuse_stroke_exhausted"), field("peak_abutment_force"));
    assert_eq!(r.status.len(), 12);
    for j in 0..12 {
        for (ls, f) in [(0, broken), (1, exhausted)] {
            let expected = if j >= 4 { i8::from(r.values[f][j] > 0.5) } else { outcome::UNDETERMINED };
            assert_eq!(evaluated[ls].outcome[j], expected, "limit state {ls}, job {j}");
        }
    }
    // (a case's jobs: the two records at 0.5 g, then at 1.5 g)
    let values = |f: usize, case: usize| -> Vec<f64> { [2, 3].map(|k| r.values[f][4 * case + k]).to_vec() };
    // at 1.5 g both fuses break, the short one runs out
    assert_eq!((values(broken, 1), values(exhausted, 1)), (vec![1.0; 2], vec![1.0; 2]));
    assert_eq!((values(broken, 2), values(exhausted, 2)), (vec![1.0; 2], vec![0.0; 2]));
    // at 0.5 g none breaks
    assert!([4, 5, 8, 9].iter().all(|&j| r.values[broken][j] == 0.0));
    let crushed = values(force, 0).into_iter().fold(f64::INFINITY, f64::min);
    let fused = values(force, 2).into_iter().fold(0.0f64, f64::max);
    assert!(crushed > 1e8 && fused < 1e6, "abutment force {crushed} N without the fuse, {fused} N with it");
}

/// A bridge with two joints (the three-span bridge of configs/three_span.toml,
/// its 5 longest modes): the reference joint's 1.12 m of gap at the left
/// abutment, which the deck never closes, and the small joint's 0.16 m at
/// the right one, which it closes and pounds. A joint's limit state
/// (abutment force, pounding) is exceeded in a run where any joint exceeds
/// it; the run's own fields are the first joint's, which would say the
/// bridge is safe.
#[test]
fn a_joint_limit_state_on_a_bridge_with_several_joints_is_every_joints() {
    let d = dir("fragility_joints");
    let record = |name: &str| root().join("ground_motions").join(name);
    let text = format!(
        "[bridge]\ndamping = 0.05\n[bridge.modal]\nmodes = {:?}\nmodes_used = 5\n\
         [[joints]]\nname = \"left\"\ndeck_point = \"left end\"\ndeck_side = \"+x\"\n\
         [[joints]]\nname = \"right\"\ndeck_point = \"right end\"\ndeck_side = \"-x\"\n\
         [joints.joint]\ncenter_beams = 3\n\
         [sweep]\nperiod_scales = [1.0]\nrecords = [{{ file = {:?} }}, {{ file = {:?} }}]\n\
         [sweep.stripes]\nmeasure = \"sa\"\nlevels = [0.3, 2.0]\n\
         [sweep.fragility]\nbootstrap = 0\n\
         [[sweep.fragility.limit_states]]\nkind = \"abutment_force\"\nforce = 5e6\n\
         [[sweep.fragility.limit_states]]\nkind = \"pounding\"\n",
        root().join("tests/data/three_span/modes.toml"),
        record("RSN753_LOMAP_CLS090-hor2.AT2"),
        record("RSN6_IMPVALL.I_I-ELC180-hor1.AT2"),
    );
    let cfg = d.join("joints.toml");
    std::fs::write(&cfg, text).unwrap();
    let out = d.join("joints.h5");
    let o = run(&["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap()]);
    ok(&o);
    let f = read_sweep(&out).unwrap();
    let r = &f.results;
    let evaluated = f.fragility.as_ref().unwrap().evaluate(r);
    let joint = |name: &str| quakejoint_sweep::results::JOINT_FIELDS.iter().position(|(n, _)| *n == name).unwrap();
    // the summary counts a job whose second joint alone pounds
    let impacts = joint("impacts");
    let pounded = (0..4).filter(|&j| r.joints.iter().any(|k| k.values[impacts][j] > 0.0)).count();
    let said = format!("pounding: the beams of {pounded} job(s) struck each other");
    assert!(stdout(&o).contains(&said), "{said}: {}", stdout(&o));
    let (force, speed) = (joint("peak_abutment_force"), joint("max_impact_speed"));
    assert_eq!((r.joints.len(), r.status.len()), (2, 4));
    let mut only_the_second = 0;
    for j in 0..4 {
        let [left, right] = [0, 1].map(|k| r.joints[k].values[force][j] > 5e6);
        assert_eq!(evaluated[0].outcome[j], i8::from(left || right), "job {j}");
        let [left, right] = [0, 1].map(|k| r.joints[k].values[speed][j] > 0.05);
        assert_eq!(evaluated[1].outcome[j], i8::from(left || right), "job {j}");
        only_the_second += usize::from(right && !left);
        // (the run's own fields are the first joint's)
        assert_eq!(r.values[Results::field("max_impact_speed")][j].to_bits(), r.joints[0].values[speed][j].to_bits());
    }
    assert!(only_the_second > 0, "no run where the second joint alone pounds: the test shows nothing");
}
