//! The command line: exit codes, JSON keys, output files and error messages.
//!
//! Exit code 0 on success, 2 on bad input with a message naming the file,
//! field or value; `--json` prints one object with the documented keys.

mod common;

use std::process::Output;

use common::{dir, run as quakejoint};

fn json(out: &Output) -> serde_json::Value {
    assert!(out.status.success(), "failed: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).to_string()
}

#[test]
fn model_json_reports_the_reference_counts() {
    let v = json(&quakejoint(&["model", "configs/paper.toml", "--json"]));
    assert_eq!(v["bodies"], 307);
    assert_eq!(v["coordinates"], 922);
    assert_eq!(v["constraints"], 570);
    assert_eq!(v["dof"], 352);
    assert!(v["jacobian_nnz"].as_u64().unwrap() > 922);
}

#[test]
fn simulate_json_has_every_documented_key_and_writes_histories() {
    let out = dir("cli-histories").join("small.h5");
    let v = json(&quakejoint(&["simulate", "configs/small.toml", "--json", "--output", out.to_str().unwrap()]));
    for key in [
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
        "max_constraint_residual",
        "steps",
        "rejected_steps",
        "newton_iterations",
        "factorizations",
        "wall_time_s",
    ] {
        assert!(v.get(key).is_some_and(|x| !x.is_null()), "missing {key} in {v}");
    }
    assert!(v["energy_error"].as_f64().unwrap() < 1e-6);
    assert!(v["max_constraint_residual"].as_f64().unwrap() < 1e-8);
    // the HDF5 file holds the histories, one value per record sample
    let file = hdf5::File::open(&out).unwrap();
    let t: Vec<f64> = file.dataset("history/t").unwrap().read_raw().unwrap();
    let a: Vec<f64> = file.dataset("history/a_abs").unwrap().read_raw().unwrap();
    assert_eq!(t.len(), 7999);
    assert_eq!(a.len(), t.len());
    let sa = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert_eq!(sa, v["sa"].as_f64().unwrap());
    let dx = file.dataset("history/center_beam_dx").unwrap();
    assert_eq!(dx.shape(), vec![3, 7999]);
    for name in ["u", "v", "ag", "joint_force", "friction_power"] {
        assert_eq!(file.dataset(&format!("history/{name}")).unwrap().size(), 7999, "{name}");
    }
    assert!(!out.with_extension("h5.tmp").exists(), "no temporary file left behind");
}

#[test]
fn no_joint_is_the_exact_linear_solution_of_the_spectrum_command() {
    let v = json(&quakejoint(&["simulate", "configs/paper.toml", "--no-joint", "--period", "1.25", "--json"]));
    let s = quakejoint(&[
        "spectrum",
        "ground_motions/RSN753_LOMAP_CLS090-hor2.AT2",
        "--periods",
        "1.25",
        "--damping",
        "0.05",
        "--json",
    ]);
    let rows = json(&s);
    assert_eq!(rows[0]["sa"], v["sa"]);
    assert_eq!(rows[0]["sd"], v["sd"]);
    for key in ["sa", "psa", "sd", "sv", "t_sa"] {
        assert!(v[key].is_number(), "{key}");
    }
}

#[test]
fn service_reports_friction_work_and_the_hand_calculation() {
    let v = json(&quakejoint(&["service", "configs/small.toml", "--cycles", "1", "--json"]));
    assert!(v["friction_work_per_cycle"].as_f64().unwrap() > 0.0);
    assert!(v["hand_calculation"].as_f64().unwrap() > 0.0);
    assert_eq!(v["cycles"], 1);
}

#[test]
fn record_and_spectrum_commands() {
    let v = json(&quakejoint(&["record", "ground_motions/RSN753_LOMAP_CLS090-hor2.AT2", "--json"]));
    assert_eq!(v["samples"], 7999);
    assert!((v["pga"].as_f64().unwrap() / 9.80665 - 0.4828).abs() < 5e-5);
    for key in ["dt", "duration", "pgv", "pgd", "arias", "d5_95"] {
        assert!(v[key].is_number(), "{key}");
    }
    let out = quakejoint(&[
        "spectrum",
        "ground_motions/RSN753_LOMAP_CLS090-hor2.AT2",
        "--from",
        "0.1",
        "--to",
        "5",
        "--count",
        "5",
        "--log",
        "--damping",
        "0.02,0.05",
        "--csv",
    ]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "damping,period,sa,psa,sd,sv");
    assert_eq!(lines.len(), 11);
}

#[test]
fn bad_input_exits_with_code_2_and_names_the_problem() {
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["model", "configs/missing.toml"], "configs/missing.toml"),
        (vec!["simulate", "configs/small.toml", "--period", "-1"], "--period -1"),
        (vec!["simulate", "configs/small.toml", "--record", "ground_motions/none.AT2"], "none.AT2"),
        (vec!["record", "configs/paper.toml"], "paper.toml"),
        (vec!["spectrum", "ground_motions/RSN753_LOMAP_CLS090-hor2.AT2", "--damping", "1.5"], "1.5"),
        (vec!["service", "configs/small.toml", "--speed", "0"], "service.speed"),
    ];
    for (args, expect) in cases {
        let out = quakejoint(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains(expect), "{args:?}: {}", stderr(&out));
    }
    let bad = dir("cli-bad").join("bad.toml");
    std::fs::write(&bad, "[joint]\npitch = -0.13\n").unwrap();
    let out = quakejoint(&["model", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("joint.pitch = -0.13"), "{}", stderr(&out));
    std::fs::write(&bad, "[joint]\ncenter_beams = 27\npich = 1\n").unwrap();
    let out = quakejoint(&["model", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("pich") && stderr(&out).contains("bad.toml"), "{}", stderr(&out));
}

#[test]
fn every_command_has_help() {
    for cmd in ["model", "simulate", "service", "record", "spectrum"] {
        let out = quakejoint(&[cmd, "--help"]);
        assert!(out.status.success(), "{cmd}");
        assert!(String::from_utf8_lossy(&out.stdout).contains("Usage"), "{cmd}");
    }
}
