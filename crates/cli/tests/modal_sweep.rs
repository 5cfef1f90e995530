//! Sweeps over a bridge given by its modes (`[bridge.modal]`, issue 28)
//! through the command line.
//!
//! The bridge is the three-span girder bridge of `tests/data/three_span`
//! (all 124 of its OpenSees modes) with the small joint of
//! `configs/small.toml` at each deck end (`[[joints]]`: "left" at the left
//! end, "right" turned half a turn at the right end), under the first 5 s
//! of Corralitos 090 scaled to 0.15 (the joints' cells stay open). A modal
//! bridge is swept by a factor on every period of its modes: a factor `f`
//! scales the stiffness by `1 / f^2` and keeps the masses, so every mode's
//! period is `f` times the file's and the shapes and participations stay.
//! Two factors, 0.8 and 1.25, put the fundamental mode (0.737 s, 96 % of
//! the mass along x) at 0.59 and 0.92 s.
//!
//! - A sweep's job is `quakejoint simulate` of the same config with
//!   `bridge.modal.period_scale` set to the job's factor, bit for bit: the
//!   first joint's deck point's Sa, Sd, Sv, its demands, the whole
//!   system's energies and counters, and the second joint's peaks.
//! - The bridge alone of each job is the exact modal superposition at the
//!   first joint's deck point (each kept mode's exact piecewise-linear
//!   response to the ground motion over the runs' window, times
//!   `Gamma_x phi`, summed; `quakejoint_model::linear::modal_response`),
//!   not the single-DOF spectrum at the fundamental period.
//! - A sweep interrupted (SIGINT) after its first job continues from its
//!   journal to the numbers of a sweep that ran through.

mod common;

use std::path::{Path, PathBuf};
use std::process::Stdio;

use common::{assert_identical, bin, dir, ok, root, run, stderr, stdout, wait_for_jobs};
use quakejoint_model::runspec::{Named, Overrides, RunSpec};
use quakejoint_sweep::results::{status, Results, FIELDS, JOINT_FIELDS, MACHINE_DEPENDENT};
use quakejoint_sweep::sweep_h5::read_sweep;

/// The swept factors on the modes' periods.
const SCALES: [f64; 2] = [0.8, 1.25];

/// The config without its `[sweep]` table: the small joint at both deck
/// ends of the three-span bridge, 5 s of Corralitos 090 at 0.15;
/// `modal_extra` is appended to `[bridge.modal]`.
fn bridge(modal_extra: &str) -> String {
    let record = root().join("ground_motions/RSN753_LOMAP_CLS090-hor2.AT2");
    let modes = root().join("tests/data/three_span/modes.toml");
    let joint = quakejoint_model::verification::modal::joint_tables(&root(), "small.toml").unwrap();
    format!(
        "{joint}\n[record]\nfile = {record:?}\nscale = 0.15\n\
         [bridge]\ndamping = 0.05\n\
         [bridge.modal]\nmodes = {modes:?}\n{modal_extra}\n\
         [[joints]]\nname = \"left\"\ndeck_point = \"left end\"\ndeck_side = \"+x\"\n\
         [[joints]]\nname = \"right\"\ndeck_point = \"right end\"\ndeck_side = \"-x\"\n\
         [simulation]\nduration = 5.0\n"
    )
}

/// Writes the sweep's config into `dir` and returns its path.
fn sweep_config(dir: &Path) -> PathBuf {
    let path = dir.join("modal.toml");
    std::fs::write(&path, format!("{}\n[sweep]\nperiod_scales = {SCALES:?}\n", bridge(""))).unwrap();
    path
}

/// `quakejoint sweep <config> --output <out>` with `args`.
fn sweep(config: &Path, out: &Path, args: &[&str]) -> std::process::Output {
    let mut all = vec!["sweep", config.to_str().unwrap(), "--output", out.to_str().unwrap(), "--progress", "none"];
    all.extend_from_slice(args);
    run(&all)
}

/// A number of `simulate --json` (null: not computed, NaN).
fn number(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

#[test]
fn a_modal_sweep_job_is_simulate_with_its_period_scale() {
    let d = dir("modal-simulate");
    let cfg = sweep_config(&d);
    let out = d.join("modal.h5");
    let res = sweep(&cfg, &out, &["--json"]);
    ok(&res);
    let summary: serde_json::Value = serde_json::from_slice(&res.stdout).unwrap();
    assert_eq!((summary["jobs"].as_u64(), summary["failed"].as_u64()), (Some(2), Some(0)), "{summary}");

    // the period axis is the scales, not periods
    let h5 = hdf5::File::open(&out).unwrap();
    let spectrum = h5.group("spectrum").unwrap();
    assert!(!spectrum.link_exists("period"), "a modal sweep's axis does not pretend to be periods");
    assert_eq!(spectrum.dataset("period_scale").unwrap().read_raw::<f64>().unwrap(), SCALES.to_vec());
    assert_eq!(spectrum.dataset("without_joint/sa").unwrap().shape(), vec![1, 1, 1, 2]);
    assert_eq!(h5.group("joints/1").unwrap().dataset("peak_joint_force").unwrap().shape(), vec![1, 1, 1, 2]);

    let file = read_sweep(&out).unwrap();
    assert_eq!(file.results.joints.iter().map(|j| j.name.as_str()).collect::<Vec<_>>(), ["left", "right"]);
    let fundamental = 0.7368132859282219; // the modes file's longest period
    for (t, &f) in SCALES.iter().enumerate() {
        assert_eq!(file.results.status[t], status::OK);
        assert!((file.periods[t] / (f * fundamental) - 1.0).abs() < 1e-14, "longest period at {f}");
        // the same config with the job's period scale, through `simulate`
        let single = d.join(format!("scale_{t}.toml"));
        std::fs::write(&single, bridge(&format!("period_scale = {f:?}"))).unwrap();
        let sim = run(&["simulate", single.to_str().unwrap(), "--json"]);
        ok(&sim);
        let v: serde_json::Value = serde_json::from_slice(&sim.stdout).unwrap();
        let mut compared = 0;
        for (k, name) in FIELDS.iter().enumerate() {
            if MACHINE_DEPENDENT.contains(name) {
                continue;
            }
            let (swept, simulated) = (file.results.values[k][t], number(&v[*name]));
            assert!(
                swept.to_bits() == simulated.to_bits() || (swept.is_nan() && simulated.is_nan()),
                "{name} at period scale {f}: sweep {swept:e}, simulate {simulated:e}"
            );
            compared += 1;
        }
        assert!(compared > 30 && file.results.values[Results::field("sa")][t] > 0.0);
        let right = &v["joints"][1];
        assert_eq!(right["name"], "right");
        for (k, (name, _)) in JOINT_FIELDS.iter().enumerate() {
            let (swept, simulated) = (file.results.joints[1].values[k][t], number(&right[*name]));
            assert_eq!(swept.to_bits(), simulated.to_bits(), "joint right: {name} at period scale {f}");
        }
        assert_eq!(u64::from(file.results.joints[1].validity[t]), right["validity"].as_u64().unwrap());
        assert_eq!(u64::from(file.results.validity[t]), v["validity"].as_u64().unwrap());
    }
}

#[test]
fn the_bridge_alone_of_a_modal_sweep_is_the_exact_modal_superposition() {
    let d = dir("modal-alone");
    let cfg = sweep_config(&d);
    let out = d.join("modal.h5");
    ok(&sweep(&cfg, &out, &[]));
    let file = read_sweep(&out).unwrap();
    let config = quakejoint_model::Config::from_file(&cfg).unwrap();
    let (x, _) = quakejoint_model::run::load_records(&config, &root()).unwrap();
    let window = quakejoint_model::run::run_window(&config, &x.record);
    for (t, &f) in SCALES.iter().enumerate() {
        let overrides = Overrides { period_scale: Some(Named::new(f, "test")), ..Overrides::default() };
        let spec = RunSpec::new(config.clone(), &overrides).unwrap();
        let kept = &spec.scenario.bridge.modal().unwrap().kept;
        assert_eq!(kept.len(), 124);
        let left = quakejoint_model::placement::places(spec.config()).unwrap()[0].deck_point;
        let exact = quakejoint_model::linear::modal_response(&window, kept, left, false);
        let without: Vec<f64> = (0..4).map(|k| file.results.without[k][t]).collect();
        assert_eq!(without, vec![exact.sa, exact.psa, exact.sd, exact.sv], "period scale {f}");
        // not the single-DOF spectrum at the fundamental period
        let sdof = quakejoint_motion::peaks(&window.acceleration, window.dt, spec.period, 0.05, Default::default());
        assert_ne!(exact.sa.to_bits(), sdof.sa.to_bits());
        // the reduction is against it
        let sa = file.results.values[Results::field("sa")][t];
        assert_eq!(file.results.reduction()[t], 1.0 - sa / exact.sa);
    }
}

#[test]
fn an_interrupted_modal_sweep_resumes_to_the_same_numbers() {
    let d = dir("modal-resume");
    let cfg = sweep_config(&d);
    let reference = d.join("reference.h5");
    ok(&sweep(&cfg, &reference, &[]));
    let out = d.join("interrupted.h5");
    let journal = d.join("interrupted.h5.journal");
    // the last job is held until the signal: the sweep is still running
    // when it comes, however fast the machine
    let mut child = bin()
        .args(["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap(), "--threads", "1"])
        .args(["--progress", "none"])
        .env("QUAKEJOINT_TEST_HOLD", "all")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_for_jobs(&mut child, &journal, 1, "modal sweep");
    let kill = std::process::Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(kill.success());
    let res = child.wait_with_output().unwrap();
    assert_eq!(res.status.code(), Some(130), "{}", stderr(&res));
    assert!(stdout(&res).contains("sweep interrupted: 1 of 2 jobs done"), "{}", stdout(&res));
    assert_eq!(read_sweep(&out).unwrap().results.finished(), 1, "the checkpoint holds the finished job");

    // the same command continues: the journalled job is kept, the other runs
    let res = sweep(&cfg, &out, &["--json"]);
    ok(&res);
    let v: serde_json::Value = serde_json::from_slice(&res.stdout).unwrap();
    assert_eq!((v["resumed"].as_u64(), v["ran"].as_u64()), (Some(1), Some(1)), "{v}");
    assert_identical(&read_sweep(&out).unwrap(), &read_sweep(&reference).unwrap(), "resumed modal sweep");
    let cmp = run(&["compare", out.to_str().unwrap(), reference.to_str().unwrap()]);
    ok(&cmp);
}
