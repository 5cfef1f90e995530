//! Spectrum sweeps through the command line.
//!
//! - The HDF5 output holds every dataset of the documented layout with its
//!   shape, and a job's numbers equal those of the same run through
//!   `quakejoint simulate`.
//! - A sweep killed with SIGKILL part way resumes from its journal to the
//!   same numbers; a finished sweep run again says it is complete; a sweep
//!   into an output that another sweep is writing, or continuing after a
//!   config change, is refused. (Thread counts and shards:
//!   `determinism.rs`; kills at many moments: `crash_safety.rs`.)
//! - A case that cannot work (a geometry, a step limit, an absurd
//!   stiffness, a per-job wall-clock limit) fails its jobs with a status and
//!   a message, the others finish, and the exit code is 3.
//! - The plotting scripts turn the outputs into PNG files.

mod common;

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use common::{assert_identical, bin, config, dir, ok, root, run, stderr, stdout};
use quakejoint_sweep::results::{status, FIELDS};
use quakejoint_sweep::sweep_h5::read_sweep;

const GRID: &str = "[sweep]\nperiods = [0.3, 0.6, 1.0, 2.0]\ndamping = [0.02, 0.05]\nhistories = [1.0]\n";

#[test]
fn sweep_layout_and_a_spot_value_against_simulate() {
    let d = dir("layout");
    let cfg = config(&d, "c.toml", GRID, 3.0);
    let out = d.join("out.h5");
    let res = run(&["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap(), "--json"]);
    ok(&res);
    let summary: serde_json::Value = serde_json::from_slice(&res.stdout).unwrap();
    assert_eq!(summary["jobs"], 8);
    assert_eq!(summary["failed"], 0);

    let file = hdf5::File::open(&out).unwrap();
    for attr in ["quakejoint_version", "schema_version", "config", "created"] {
        assert!(file.attr(attr).is_ok(), "root attribute {attr}");
    }
    let shape = |name: &str| file.dataset(name).unwrap().shape();
    assert_eq!(shape("spectrum/period"), vec![4]);
    assert_eq!(shape("spectrum/damping"), vec![2]);
    assert_eq!(shape("spectrum/record"), vec![1]);
    assert_eq!(shape("spectrum/case"), vec![1]);
    for name in ["sa", "psa", "sd", "sv"] {
        assert_eq!(shape(&format!("spectrum/without_joint/{name}")), vec![1, 2, 4]);
    }
    for name in [
        "sa",
        "psa",
        "sd",
        "sv",
        "t_sa",
        "peak_joint_force",
        "friction_energy",
        "min_subgap",
        "max_subgap",
        "energy_error",
        "max_position_residual",
        "max_angle_residual",
        "max_velocity_residual",
        "max_angular_velocity_residual",
        "validity",
        "findings",
        "steps",
        "wall_time_s",
        "status",
        "message",
    ] {
        assert_eq!(shape(&format!("spectrum/with_joint/{name}")), vec![1, 1, 2, 4], "{name}");
    }
    assert_eq!(shape("spectrum/reduction"), vec![1, 1, 2, 4]);
    let rec = file.group("records/RSN753_LOMAP_CLS090-hor2").unwrap();
    assert_eq!(rec.dataset("acceleration").unwrap().shape(), vec![7999]);
    for (name, units) in [("dt", "s"), ("scale", "m/s^2 per file unit"), ("pga", "m/s^2")] {
        let ds = rec.dataset(name).unwrap();
        assert_eq!(quakejoint_io::h5::read_attr_str(&ds, "units").unwrap(), units);
    }
    for attr in ["source", "sha256", "file_units"] {
        assert!(rec.attr(attr).is_ok(), "record attribute {attr}");
    }
    assert_eq!(file.member_names().unwrap().iter().filter(|n| *n == "histories").count(), 1);

    // the job (damping 0.05, T = 1.0 s) through `quakejoint simulate`
    let sweep = read_sweep(&out).unwrap();
    let j = sweep.results.status.len() - 2; // damping index 1, period index 2
    assert_eq!(sweep.periods[2], 1.0);
    let sim = run(&["simulate", cfg.to_str().unwrap(), "--period", "1.0", "--json"]);
    ok(&sim);
    let v: serde_json::Value = serde_json::from_slice(&sim.stdout).unwrap();
    let field = |name: &str| sweep.results.values[FIELDS.iter().position(|f| *f == name).unwrap()][j];
    for name in ["sa", "psa", "sd", "sv", "t_sa", "peak_joint_force", "friction_energy", "min_subgap", "energy_error"] {
        assert_eq!(field(name), v[name].as_f64().unwrap(), "{name}");
    }
    assert_eq!(field("steps"), v["steps"].as_f64().unwrap());
    // reduction = 1 - with / without
    let r = &sweep.results;
    assert_eq!(r.reduction()[j], 1.0 - field("sa") / r.without[0][j % 8]);
}

#[test]
fn a_finished_sweep_run_again_says_so_and_a_changed_config_is_refused() {
    let d = dir("refusals");
    let cfg = config(&d, "c.toml", GRID, 2.0);
    let cfgs = cfg.to_str().unwrap();
    let out = d.join("out.h5");
    let outs = out.to_str().unwrap();
    ok(&run(&["sweep", cfgs, "--output", outs, "--json"]));
    let before = std::fs::read(&out).unwrap();
    // the same command again: nothing to do, nothing rewritten
    let again = run(&["sweep", cfgs, "--output", outs]);
    ok(&again);
    assert!(stdout(&again).contains("sweep already complete: 8 of 8 jobs done"), "{}", stdout(&again));
    assert_eq!(std::fs::read(&out).unwrap(), before, "a complete output is left as it is");

    // continuing after a change of the config is refused, saying what changed
    let changed = config(&d, "c.toml", &format!("{GRID}\n[joint.friction]\nmu = 0.1\n"), 2.0);
    for extra in [&[][..], &["--resume"][..]] {
        let mut args = vec!["sweep", changed.to_str().unwrap(), "--output", outs];
        args.extend_from_slice(extra);
        let refused = run(&args);
        assert_eq!(refused.status.code(), Some(2), "{}", stderr(&refused));
        assert!(stderr(&refused).contains("config differs"), "{}", stderr(&refused));
    }
    // --resume insists on a journal
    let fresh = run(&["sweep", cfgs, "--output", d.join("new.h5").to_str().unwrap(), "--resume"]);
    assert_eq!(fresh.status.code(), Some(2), "{}", stderr(&fresh));
    assert!(stderr(&fresh).contains("there is no journal to continue"), "{}", stderr(&fresh));
    assert!(!d.join("new.h5.journal").exists());
}

#[test]
fn a_second_sweep_into_a_running_output_is_refused() {
    let d = dir("concurrent");
    let cfg = config(&d, "c.toml", GRID, 2.0);
    let cfgs = cfg.to_str().unwrap();
    let out = d.join("out.h5");
    // the first sweep stops in its first checkpoint, holding the journal
    let mut first = bin()
        .args(["sweep", cfgs, "--output", out.to_str().unwrap(), "--json"])
        .env("QUAKEJOINT_TEST_PAUSE", "checkpoint:1")
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let marker = quakejoint_sweep::fault::marker(&out);
    let start = Instant::now();
    while !marker.exists() {
        assert!(start.elapsed() < Duration::from_secs(60), "the first sweep never paused");
        std::thread::sleep(Duration::from_millis(5));
    }
    let second = run(&["sweep", cfgs, "--output", out.to_str().unwrap(), "--resume"]);
    first.kill().unwrap();
    first.wait().unwrap();
    assert_eq!(second.status.code(), Some(2), "{}", String::from_utf8_lossy(&second.stderr));
    assert!(stderr(&second).contains("another quakejoint process is writing this output"), "{}", stderr(&second));
    // once the first is gone, the journal is free
    ok(&run(&["sweep", cfgs, "--output", out.to_str().unwrap(), "--resume", "--json"]));
}

#[test]
fn a_killed_sweep_resumes_to_the_same_numbers() {
    let d = dir("resume");
    let cfg = config(&d, "c.toml", GRID, 3.0);
    let cfgs = cfg.to_str().unwrap();
    let reference = d.join("reference.h5");
    ok(&run(&["sweep", cfgs, "--output", reference.to_str().unwrap(), "--threads", "2", "--json"]));
    let out = d.join("killed.h5");
    let journal = d.join("killed.h5.journal");
    // the last job is held (QUAKEJOINT_TEST_HOLD): the sweep cannot finish
    // before the kill, however fast the machine
    let mut child = bin()
        .args(["sweep", cfgs, "--output", out.to_str().unwrap(), "--threads", "1", "--json"])
        .env("QUAKEJOINT_TEST_HOLD", "all")
        .spawn()
        .unwrap();
    // wait until some but not all jobs are journalled, then SIGKILL
    let start = Instant::now();
    loop {
        let done = quakejoint_sweep::journal::read(&journal).map(|(_, r)| r.len()).unwrap_or(0);
        if done >= 2 {
            break;
        }
        assert!(child.try_wait().unwrap().is_none(), "the sweep finished before it could be killed");
        assert!(start.elapsed() < Duration::from_secs(300), "no progress");
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let (_, partial) = quakejoint_sweep::journal::read(&journal).unwrap();
    assert!(partial.len() < 8, "killed part way ({} jobs journalled)", partial.len());
    let res = run(&["sweep", cfgs, "--output", out.to_str().unwrap(), "--resume", "--json"]);
    ok(&res);
    let v: serde_json::Value = serde_json::from_slice(&res.stdout).unwrap();
    assert_eq!(v["resumed"].as_u64().unwrap() as usize, partial.len());
    assert_identical(
        &read_sweep(&out).unwrap(),
        &read_sweep(&reference).unwrap(),
        "killed and resumed vs uninterrupted",
    );
    // every job is in the journal exactly once
    let (_, all) = quakejoint_sweep::journal::read(&journal).unwrap();
    let mut jobs: Vec<u32> = all.iter().map(|r| r.job).collect();
    jobs.sort_unstable();
    assert_eq!(jobs, (0..8).collect::<Vec<u32>>());
}

#[test]
fn failing_jobs_are_recorded_and_the_sweep_goes_on() {
    let d = dir("failing");
    let sweep = "[sweep]\nperiods = [0.5, 1.0]\ndamping = [0.05]\n\
                 [[sweep.cases]]\nname = \"reference\"\n\
                 [[sweep.cases]]\nname = \"step limit\"\nsimulation.max_steps = 5\n\
                 [[sweep.cases]]\nname = \"time limit\"\nsimulation.h_max = 1e-7\nsimulation.max_wall_time = 0.5\n\
                 [[sweep.cases]]\nname = \"solver failure\"\n";
    let cfg = config(&d, "c.toml", sweep, 2.0);
    let out = d.join("out.h5");
    let start = Instant::now();
    // job 6 (case 3, period 0) fails as a solver failure does (an injected
    // fault: no valid config makes this solver give up reliably)
    let res = bin()
        .args(["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap(), "--threads", "2", "--json"])
        .env("QUAKEJOINT_TEST_FAIL_JOBS", "6")
        .output()
        .unwrap();
    let wall = start.elapsed();
    assert_eq!(res.status.code(), Some(3), "{}", stderr(&res));
    let v: serde_json::Value = serde_json::from_slice(&res.stdout).unwrap();
    assert_eq!(v["failed"], 5);
    let f = read_sweep(&out).unwrap();
    assert_eq!(f.cases, vec!["reference", "step limit", "time limit", "solver failure"]);
    let r = &f.results;
    assert_eq!(&r.status[0..2], &[status::OK, status::OK]);
    assert_eq!(&r.status[2..4], &[status::LIMIT, status::LIMIT]);
    assert!(r.messages[2].contains("step limit"), "{}", r.messages[2]);
    // ten million steps would be needed: the per-job limit ends each job
    assert_eq!(&r.status[4..6], &[status::LIMIT, status::LIMIT]);
    assert!(r.messages[4].contains("time limit of 0.5 s wall clock"), "{}", r.messages[4]);
    assert_eq!(&r.status[6..8], &[status::FAILED, status::OK]);
    assert!(r.messages[6].contains("integration failed at t ="), "{}", r.messages[6]);
    // a failed job was not checked, which is not the same as valid (0)
    let not_checked = quakejoint_model::validity::Flags::NOT_CHECKED.0;
    assert_eq!((r.validity[6], r.validity[0]), (not_checked, 0), "{:?}", r.validity);
    assert!(r.findings[6].starts_with("not_checked"), "{}", r.findings[6]);
    assert!(r.values[0][2].is_nan() && r.values[0][0] > 0.0);
    // the time-limited jobs (2 x 0.5 s on 2 threads) bound the sweep
    assert!(wall.as_secs_f64() < 30.0, "the sweep took {wall:?}");
}

#[test]
fn a_case_that_cannot_work_is_bad_input_and_nothing_is_written() {
    let d = dir("impossible");
    for (case, expect) in [
        ("joint.center_beam.length = 2.0", "outside the center beam"),
        ("joint.bushing.kx = 1e25", "joint.bushing.kx = 1e25"),
        ("simulation.extra_time = 86400.0", "share its run window"),
    ] {
        let sweep = format!(
            "[sweep]\nperiods = [0.5]\n[[sweep.cases]]\nname = \"fine\"\n[[sweep.cases]]\nname = \"bad\"\n{case}\n"
        );
        let cfg = config(&d, "c.toml", &sweep, 1.0).to_str().unwrap().to_string();
        // the run length of the record itself, so that a case's extra time counts
        let text = std::fs::read_to_string(&cfg).unwrap().replace("[simulation]\nduration = 1\n", "");
        std::fs::write(&cfg, text).unwrap();
        let out = d.join("out.h5");
        let res = run(&["sweep", &cfg, "--output", out.to_str().unwrap()]);
        assert_eq!(res.status.code(), Some(2), "{case}: {}", stderr(&res));
        assert!(stderr(&res).contains("case \"bad\"") && stderr(&res).contains(expect), "{case}: {}", stderr(&res));
        assert!(!out.exists() && !d.join("out.h5.journal").exists(), "{case}: nothing written");
    }
}

#[test]
fn bad_sweep_tables_name_the_key() {
    let d = dir("bad");
    for (sweep, expect) in [
        ("[sweep]\nperiods = [0.0]\n", "sweep.periods[0]"),
        ("[sweep]\nperiods = [1.0]\ndamping = [1.0]\n", "sweep.damping[0]"),
        ("[sweep]\nperiods = { from = 0.1, to = 5.0, count = 10, spacing = \"cubic\" }\n", "sweep.periods.spacing"),
        ("[sweep]\nperiods = [1.0]\nthreads = 4\n", "sweep.threads"),
        ("[sweep]\nperiods = [1.0]\n[[sweep.cases]]\nname = \"a\"\nbridge.period = 2.0\n", "bridge.period"),
        ("[sweep]\nperiods = [1.0]\n[[sweep.cases]]\nname = \"a\"\njoint.frictoin.mu = 0.1\n", "frictoin"),
        (
            "[sweep]\nperiods = [1.0]\n[[sweep.cases]]\nname = \"a\"\njoint.friction.mu = -0.1\n",
            "joint.friction.mu = -0.1",
        ),
        ("[sweep]\nperiods = [1.0]\nrecords = []\n", "sweep.records"),
    ] {
        let cfg = config(&d, "bad.toml", sweep, 2.0);
        let res = run(&["sweep", cfg.to_str().unwrap(), "--output", d.join("x.h5").to_str().unwrap()]);
        assert_eq!(res.status.code(), Some(2), "{sweep}: {}", String::from_utf8_lossy(&res.stderr));
        assert!(
            String::from_utf8_lossy(&res.stderr).contains(expect),
            "{sweep}: {}",
            String::from_utf8_lossy(&res.stderr)
        );
    }
    // a folder that does not exist is bad input, refused before anything
    let res = run(&["sweep", "configs/quick.toml", "--output", "/nonexistent-dir/x.h5"]);
    assert_eq!(res.status.code(), Some(2));
    assert!(stderr(&res).contains("the folder /nonexistent-dir does not exist"), "{}", stderr(&res));
    // an unwritable one is the machine's
    let locked = d.join("read-only");
    std::fs::create_dir_all(&locked).unwrap();
    let mut perms = std::fs::metadata(&locked).unwrap().permissions();
    std::os::unix::fs::PermissionsExt::set_mode(&mut perms, 0o555);
    std::fs::set_permissions(&locked, perms).unwrap();
    let probe = locked.join("probe");
    if std::fs::write(&probe, b"x").is_err() {
        // (root may write anyway; then there is nothing to test)
        let res = run(&["sweep", "configs/quick.toml", "--output", locked.join("x.h5").to_str().unwrap()]);
        assert_eq!(res.status.code(), Some(1), "{}", stderr(&res));
        assert!(stderr(&res).contains("not writable"), "{}", stderr(&res));
    }
}

#[test]
fn plotting_scripts_write_png_files() {
    if !common::python_with(&["h5py", "matplotlib"]) {
        return;
    }
    let d = dir("plots");
    let cfg = config(&d, "c.toml", "[sweep]\nperiods = [0.5, 1.0]\ndamping = [0.05]\nhistories = [1.0]\n", 2.0);
    let out = d.join("out.h5");
    ok(&run(&["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap(), "--json"]));
    let run_h5 = d.join("run.h5");
    ok(&run(&["simulate", cfg.to_str().unwrap(), "--output", run_h5.to_str().unwrap(), "--json"]));
    let sparsity = d.join("sparsity.h5");
    ok(&run(&["model", "configs/small.toml", "--sparsity", sparsity.to_str().unwrap(), "--json"]));
    let model_json = run(&["model", "configs/small.toml", "--json"]);
    ok(&model_json);
    std::fs::write(d.join("model.json"), &model_json.stdout).unwrap();
    let script = |name: &str, args: &[&Path]| {
        let png = d.join(format!("{name}.png"));
        let mut cmd = Command::new("python3");
        cmd.arg(root().join("scripts").join(format!("{name}.py")));
        for a in args {
            cmd.arg(a);
        }
        let res = cmd.arg(&png).output().expect("python3 runs");
        assert!(res.status.success(), "{name}: {}", String::from_utf8_lossy(&res.stderr));
        assert!(std::fs::metadata(&png).map(|m| m.len() > 1000).unwrap_or(false), "{name}: no PNG");
    };
    script("plot_spectrum", &[&out]);
    script("plot_history", &[&out]);
    script("plot_history", &[&run_h5]);
    // a time window (impacts last milliseconds), and a window the wrong way round
    let windowed = |t0: &str, t1: &str| {
        Command::new("python3")
            .arg(root().join("scripts/plot_history.py"))
            .args([run_h5.as_os_str(), d.join("window.png").as_os_str()])
            .args(["--window", t0, t1])
            .output()
            .expect("python3 runs")
    };
    let res = windowed("1", "3");
    assert!(res.status.success(), "--window 1 3: {}", String::from_utf8_lossy(&res.stderr));
    let res = windowed("3", "1");
    assert!(!res.status.success(), "--window 3 1 must be refused");
    assert!(String::from_utf8_lossy(&res.stderr).contains("T0 must be below T1"));
    script("plot_sparsity", &[&sparsity]);
    script("plot_geometry", &[&d.join("model.json")]);
    // the runs bench's table (format of crates/model/benches/runs.rs)
    let scaling = d.join("scaling.json");
    std::fs::write(
        &scaling,
        r#"[{"nc": 3, "bodies": 45, "coordinates": 130, "equations": 90, "steps": 100, "newton_iterations": 150, "factorizations": 10, "wall_time_s": 0.01},
            {"nc": 27, "bodies": 309, "coordinates": 922, "equations": 570, "steps": 100, "newton_iterations": 150, "factorizations": 10, "wall_time_s": 0.07}]"#,
    )
    .unwrap();
    script("plot_scaling", &[&scaling]);
}

#[test]
fn slurm_script_runs_shards_locally_and_merges_them() {
    let d = dir("slurm");
    let cfg = config(&d, "job.toml", "[sweep]\nperiods = [0.4, 0.8, 1.6]\ndamping = [0.05]\n", 2.0);
    let reference = d.join("reference.h5");
    ok(&run(&["sweep", cfg.to_str().unwrap(), "--output", reference.to_str().unwrap(), "--json"]));
    let res = Command::new("bash")
        .arg(root().join("scripts/slurm_array.sh"))
        .args([cfg.to_str().unwrap(), "3", "--local"])
        .env("QUAKEJOINT", env!("CARGO_BIN_EXE_quakejoint"))
        .current_dir(&d)
        .output()
        .unwrap();
    ok(&res);
    assert!(d.join("shards/job-2-of-3.h5").exists());
    assert_identical(
        &read_sweep(&d.join("job.h5")).unwrap(),
        &read_sweep(&reference).unwrap(),
        "script shards vs one run",
    );
}

/// The bridge without the joint is solved over the runs' window, not over
/// the whole record. Closed form: an undamped oscillator of period T at
/// rest under a ground acceleration a0 switched on at t = 0 has
/// `a_abs(t) = a0 (1 - cos(2 pi t / T))`, so over a window of T/4 its peak
/// is a0, and over the whole (longer) record 2 a0. A run with the joint
/// disabled is the same oscillator integrated by the multibody solver.
#[test]
fn the_spectrum_without_the_joint_covers_the_runs_window() {
    let d = dir("window");
    let record = d.join("step.txt");
    std::fs::write(&record, "1.0\n".repeat(4001)).unwrap(); // 4 s of 1 m/s^2 at 1 ms
    let cfg = d.join("c.toml");
    std::fs::write(
        &cfg,
        "[joint]\nenabled = false\n[bridge]\ndamping = 0.0\n\
         [record]\nfile = \"step.txt\"\ndt = 0.001\nunits = \"m/s2\"\n\
         [simulation]\nduration = 0.25\n[sweep]\nperiods = [1.0]\ndamping = [0.0]\n",
    )
    .unwrap();
    let out = d.join("out.h5");
    let res = run(&["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap()]);
    ok(&res);
    let f = read_sweep(&out).unwrap();
    let without = f.results.without[0][0];
    assert!((without - 1.0).abs() < 1e-9, "Sa without the joint over T/4: {without}, expected a0 = 1");
    let with = f.results.values[0][0];
    assert!((with - 1.0).abs() < 1e-4, "Sa of the bridge alone in the multibody solver: {with}");
    let warning = f.provenance.warnings.join("\n");
    assert!(warning.contains("first 0.25 s of 4 s") && warning.contains("100.0 % more"), "{warning}");
    assert!(stderr(&res).contains("100.0 % more"), "{}", stderr(&res));
}

/// A stored history carries its job's validity, as the spectrum arrays do.
#[test]
fn stored_histories_say_whether_their_job_was_valid() {
    let d = dir("history-validity");
    let cfg = config(&d, "c.toml", "[sweep]\nperiods = [0.5, 1.0]\ndamping = [0.05]\nhistories = [1.0]\n", 2.0);
    let out = d.join("out.h5");
    ok(&run(&["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap()]));
    let file = hdf5::File::open(&out).unwrap();
    let g = file.group("histories/job_1").unwrap();
    assert_eq!(g.attr("validity").unwrap().read_scalar::<u32>().unwrap(), 0);
    let label = quakejoint_io::h5::read_attr_str(&g, "validity_label").unwrap();
    assert_eq!(label.as_str(), "ok");
    let gaps = g.dataset("subgaps").unwrap();
    assert_eq!(gaps.shape()[0], 4, "Nc + 1 sub-gaps");
}
