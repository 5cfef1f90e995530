//! What a sweep over a bridge given by its modes (`[bridge.modal]`)
//! accepts and refuses, and what recognises it.
//!
//! A modal bridge's periods are its modes file's, all scaled by one factor
//! (`bridge.modal.period_scale`: the stiffness over `f^2`, the masses
//! kept), and its damping ratios are the file's (or `bridge.damping`). So
//! a sweep of it sweeps that factor (`sweep.period_scales`); a list of
//! periods (`sweep.periods`) would have to say which mode it sets, and a
//! swept damping would silently override the file's, so both are refused,
//! as a factor on the periods of a single-DOF bridge is. The bridge alone,
//! the reference of every reduction, is the modes' exact superposition at
//! the first joint's point: a case that keeps other modes has a bridge
//! alone of its own (stored per case), while the modes file, the swept
//! factor and the damping ratios belong to the whole sweep. The modes
//! file's bytes are part of the config's hash, so that a journal started
//! with other modes is not continued, and shards of a modal sweep merge to
//! the whole sweep bit for bit.
//!
//! The bridge is the three-span bridge of `tests/data/three_span` with the
//! small joint of `configs/small.toml` at its right end, under the first
//! 2 s of Corralitos 090 at 0.15 (each job takes a few hundredths of a
//! second).

use std::path::{Path, PathBuf};

use quakejoint_sweep::runner::{run_sweep, SweepOptions};
use quakejoint_sweep::sweep_h5::read_sweep;
use quakejoint_sweep::{merge, MergeOptions, Plan, Progress};

/// The config's record.
const RECORD: &str = "ground_motions/RSN753_LOMAP_CLS090-hor2.AT2";

/// The `[record]` table of [`config`].
fn record_table() -> String {
    format!("[record]\nfile = {:?}\nscale = 0.15\n", root().join(RECORD))
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A fresh scratch directory for the test `name`.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("qj-modal-plan-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The small joint at the right end of the three-span bridge (the modes
/// file `modes`), 2 s of Corralitos 090 at 0.15, then `rest` (the
/// `[sweep]` table, and anything after it).
fn config(modes: &Path, modal_extra: &str, rest: &str) -> String {
    let joint = quakejoint_model::verification::modal::joint_tables(&root(), "small.toml").unwrap();
    format!(
        "{joint}\n{}[bridge]\ndamping = 0.05\n\
         [bridge.modal]\nmodes = {modes:?}\njoint_point = \"right end\"\n{modal_extra}\n\
         [simulation]\nduration = 2.0\n{rest}",
        record_table()
    )
}

fn modes() -> PathBuf {
    root().join("tests/data/three_span/modes.toml")
}

fn plan(text: &str) -> Result<Plan, String> {
    Plan::new(text, "modal.toml", &root()).map_err(|e| e.to_string())
}

fn options(output: &Path, shard: Option<(usize, usize)>) -> SweepOptions {
    SweepOptions {
        output: output.to_path_buf(),
        threads: Some(1),
        resume: false,
        retry_failed: false,
        shard,
        progress: Progress::Quiet,
        config_path: PathBuf::from("modal.toml"),
        command: "test".into(),
        stop: None,
    }
}

#[test]
fn sweep_periods_with_a_modal_bridge_is_refused_naming_period_scales() {
    let err = plan(&config(&modes(), "", "[sweep]\nperiods = [0.5, 1.0]\n")).unwrap_err();
    assert!(err.contains("sweep.periods") && err.contains("sweep.period_scales"), "{err}");
    let err = plan(&config(&modes(), "", "[sweep]\nperiod_scales = [1.0]\ndamping = [0.02]\n")).unwrap_err();
    assert!(err.contains("sweep.damping") && err.contains("modes file's, or bridge.damping"), "{err}");
}

#[test]
fn period_scales_without_a_modal_bridge_is_refused() {
    let text = "[sweep]\nperiods = [1.0]\nperiod_scales = [0.8, 1.0]\n";
    let err = Plan::new(text, "sdof.toml", &root()).unwrap_err().to_string();
    assert!(err.contains("sweep.period_scales") && err.contains("single-DOF"), "{err}");
}

#[test]
fn period_scales_are_checked_as_the_period_scale_is() {
    let with = |scales: &str| plan(&config(&modes(), "", &format!("[sweep]\nperiod_scales = {scales}\n")));
    let err = with("[0.8, 20.0]").unwrap_err();
    assert!(err.contains("sweep.period_scales[1] = 20: must be within 0.1 <= x <= 10"), "{err}");
    assert!(with("[0.8, 0.8]").unwrap_err().contains("is already sweep.period_scales[0]"));
    // a range, as for periods
    let p = with("{ from = 0.5, to = 2.0, count = 3 }").unwrap();
    let scales = &p.modal.as_ref().unwrap().period_scales;
    assert_eq!(scales.len(), 3);
    assert!((scales[1] - 1.0).abs() < 1e-15, "{scales:?}");
    // absent: the config's own scale (1 by default), one job per record and case
    let p = plan(&config(&modes(), "", "[sweep]\n")).unwrap();
    assert_eq!((p.modal.as_ref().unwrap().period_scales.clone(), p.job_count()), (vec![1.0], 1));
    let p = plan(&config(&modes(), "period_scale = 1.1", "[sweep]\n")).unwrap();
    assert_eq!(p.modal.as_ref().unwrap().period_scales, vec![1.1]);
    // both: the sweep's would silently replace the config's
    let err = plan(&config(&modes(), "period_scale = 1.1", "[sweep]\nperiod_scales = [1.0]\n")).unwrap_err();
    assert!(err.contains("bridge.modal.period_scale"), "{err}");
    // the axis: the scales; the periods: the longest kept period at each
    let p = with("[0.8, 1.25]").unwrap();
    assert_eq!(p.axis(), &[0.8, 1.25]);
    assert!((p.periods[1] / (1.25 * 0.7368132859282219) - 1.0).abs() < 1e-14, "{:?}", p.periods);
    assert_eq!(p.damping, vec![0.05]);
}

#[test]
fn a_case_may_keep_other_modes_but_not_change_the_modes_file_scale_or_damping() {
    let case = |keys: &str| {
        plan(&config(&modes(), "", &format!("[sweep]\nperiod_scales = [1.0]\n[[sweep.cases]]\nname = \"c\"\n{keys}\n")))
    };
    let p = case("bridge.modal.modes_used = 3").unwrap();
    assert_eq!(p.cases[0].config.bridge.modal.as_ref().unwrap().modes_used, Some(3));
    assert!(p.cases[0].config.bridge.modal.as_ref().unwrap().loaded.is_some(), "the base config's modes file");
    for (keys, field) in [
        ("bridge.modal.modes = \"other.toml\"", "sweep.cases[0].bridge.modal.modes"),
        ("bridge.modal.period_scale = 1.1", "sweep.cases[0].bridge.modal.period_scale"),
        ("bridge.damping = 0.02", "sweep.cases[0].bridge.damping"),
        ("bridge.period = 1.0", "sweep.cases[0].bridge.period"),
    ] {
        let err = case(keys).unwrap_err();
        assert!(err.contains(field), "{keys}: {err}");
    }
    // a case's joint point is checked against the modes file
    let err = case("bridge.modal.joint_point = \"nowhere\"").unwrap_err();
    assert!(err.contains("no such point"), "{err}");
}

#[test]
fn a_changed_modes_file_is_another_sweep() {
    let d = scratch("changed");
    let modes = d.join("modes.toml");
    std::fs::copy(self::modes(), &modes).unwrap();
    let text = config(&modes, "", "[sweep]\nperiod_scales = [1.0]\n");
    let before = plan(&text).unwrap();
    let out = d.join("out.h5");
    run_sweep(&before, &options(&out, None)).unwrap();
    // a comment changes no number, but the journal cannot know: the file's
    // bytes are what it recognises the modes by
    let mut changed = std::fs::read_to_string(&modes).unwrap();
    changed.push_str("# edited\n");
    std::fs::write(&modes, changed).unwrap();
    let after = plan(&text).unwrap();
    assert_ne!(after.config_sha256, before.config_sha256);
    let err = run_sweep(&after, &options(&out, None)).unwrap_err().to_string();
    assert!(err.contains("different sweep") && err.contains("modes file"), "{err}");
    // and the output never overwrites the modes file
    let err = run_sweep(&after, &options(&modes, None)).unwrap_err().to_string();
    assert!(err.contains("would overwrite the input"), "{err}");
}

#[test]
fn shards_of_a_modal_sweep_merge_to_the_whole_sweep() {
    let d = scratch("shards");
    let sweep = "[sweep]\nperiod_scales = [0.8, 1.25]\n[[sweep.cases]]\nname = \"all modes\"\n\
                 [[sweep.cases]]\nname = \"3 modes\"\nbridge.modal.modes_used = 3\n";
    let p = plan(&config(&modes(), "", sweep)).unwrap();
    let whole = d.join("whole.h5");
    run_sweep(&p, &options(&whole, None)).unwrap();
    let shards: Vec<PathBuf> = (1..=2).map(|k| d.join(format!("shard{k}.h5"))).collect();
    for (k, path) in shards.iter().enumerate() {
        run_sweep(&p, &options(path, Some((k + 1, 2)))).unwrap();
    }
    let merged = d.join("merged.h5");
    merge(&shards, &merged, MergeOptions { expected: Some(p.config_sha256.clone()), ..MergeOptions::default() })
        .unwrap();
    let (a, b) = (read_sweep(&whole).unwrap(), read_sweep(&merged).unwrap());
    let diffs = quakejoint_sweep::compare::differences(&a, &b);
    assert!(diffs.is_empty(), "{diffs:?}");
    // each case's bridge alone: fewer modes, another reference
    let r = &a.results;
    assert!(r.without_per_case);
    assert_ne!(r.without[0][0], r.without[0][2], "3 modes against all 124 at period scale 0.8");
}

#[test]
fn a_suite_over_a_modal_bridge_is_fitted_around_its_fundamental_period() {
    let records: Vec<String> = ["RSN753_LOMAP_CLS090-hor2.AT2", "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"]
        .iter()
        .map(|r| format!("{{ file = {:?} }}", root().join("ground_motions").join(r)))
        .collect();
    let sweep = format!(
        "[sweep]\nperiod_scales = [0.8, 1.25]\nrecords = [{}]\n\
         [sweep.suite]\ntarget = {{ code = \"ec8\", type = 1, ground = \"C\", ag_g = 0.02 }}\n",
        records.join(", ")
    );
    // (the suite's records, not the config's [record])
    let text = config(&modes(), "", &sweep).replace(&record_table(), "");
    let p = plan(&text).unwrap();
    // Eurocode 8's 0.2 T1 to 2 T1 about the longest kept period at scale 1
    let t1 = 0.7368132859282219;
    assert_eq!(p.suite.as_ref().unwrap().range, (0.2 * t1, 2.0 * t1));
}
