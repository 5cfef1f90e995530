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

/// The JSON of a run that finished flagged (exit code 4).
fn flagged_json(out: &Output) -> serde_json::Value {
    assert_eq!(out.status.code(), Some(4), "{}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).to_string()
}

#[test]
fn model_json_reports_the_reference_counts() {
    let v = json(&quakejoint(&["model", "configs/paper.toml", "--json"]));
    assert_eq!(v["bodies"], 307);
    assert_eq!(v["coordinates"], 652);
    assert_eq!(v["constraints"], 300);
    assert_eq!(v["dof"], 352);
    assert!(v["jacobian_nnz"].as_u64().unwrap() > 652);
}

#[test]
fn simulate_json_has_every_documented_key_and_writes_histories() {
    let out = dir("cli-histories").join("small.h5");
    // the small joint under the full record pounds, and one of its uneven
    // sub-gaps opens beyond the 80 mm a cell takes: the run says so
    let v = flagged_json(&quakejoint(&["simulate", "configs/small.toml", "--json", "--output", out.to_str().unwrap()]));
    assert_eq!(v["flags"], serde_json::json!(["capacity_exceeded"]));
    assert!(v["impacts"].as_u64().unwrap() > 0 && v["peak_contact_force"].as_f64().unwrap() > 0.0, "{v}");
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
        "max_position_residual",
        "max_angle_residual",
        "max_velocity_residual",
        "max_angular_velocity_residual",
        "validity",
        "steps",
        "rejected_steps",
        "newton_iterations",
        "factorizations",
        "wall_time_s",
    ] {
        assert!(v.get(key).is_some_and(|x| !x.is_null()), "missing {key} in {v}");
    }
    assert!(v["energy_error"].as_f64().unwrap() < 1e-6);
    for key in ["max_position_residual", "max_angle_residual", "max_velocity_residual"] {
        assert!(v[key].as_f64().unwrap() < 1e-8, "{key}");
    }
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

/// The service case of the small model closes its 0.52 m gap by 0.2 m,
/// more than its four sub-gaps of 40 mm take: the kinematic deck presses
/// the closed stack of beams into the abutment, deeper than the contacts
/// stand for, and its weakly held beams open one sub-gap beyond the cell's
/// 80 mm; the run says so like an earthquake run (exit code 4, the flags and
/// the findings). Its loop obeys its own energy balance: over a closed cycle
/// the deck's work on the joint (through the joist boxes and the deck's
/// edge beam) equals what friction, the bushings' dampers and the impacts
/// dissipate, once the cycle is steady.
#[test]
fn service_reports_friction_work_the_hand_calculation_and_its_validity() {
    let v = flagged_json(&quakejoint(&["service", "configs/small.toml", "--json"]));
    assert!(v["friction_work_per_cycle"].as_f64().unwrap() > 0.0);
    assert!(v["hand_calculation"].as_f64().unwrap() > 0.0);
    assert_eq!(v["cycles"], 2);
    assert_eq!(v["validity_label"], "penetration+capacity_exceeded");
    assert!(v["min_subgap"].as_f64().unwrap() < -0.005);
    let dissipated = ["friction_work_per_cycle", "damping_work_per_cycle", "contact_work_per_cycle"]
        .iter()
        .map(|k| v[*k].as_f64().unwrap())
        .sum::<f64>();
    let area = v["loop_work_per_cycle"].as_f64().unwrap();
    assert!((area / dissipated - 1.0).abs() < 0.01, "loop area {area} J against {dissipated} J dissipated");
    // the medium model's beams follow their intercept positions closely
    // enough to stay clear of each other
    let v = json(&quakejoint(&["service", "configs/medium.toml", "--json"]));
    assert_eq!(v["validity_label"], "ok");
    assert!(v["min_subgap"].as_f64().unwrap() > 0.0);
}

/// `simulate --record` replaces the whole [record] table: the config's
/// scale (0.2 in the test config), units and columns describe another file.
#[test]
fn simulate_record_replaces_the_record_table() {
    let d = dir("record-override");
    let cfg = d.join("c.toml");
    std::fs::write(
        &cfg,
        "[joint]\nenabled = false\n[record]\nfile = \"elsewhere.csv\"\nunits = \"m/s2\"\nscale = 0.2\n\
         [simulation]\nduration = 1.0\n",
    )
    .unwrap();
    let at2 = common::root().join("ground_motions/RSN753_LOMAP_CLS090-hor2.AT2");
    let out = quakejoint(&["simulate", cfg.to_str().unwrap(), "--record", at2.to_str().unwrap(), "--json"]);
    let v = json(&out);
    assert!((v["record_pga_g"].as_f64().unwrap() - 0.4828).abs() < 1e-3, "{v}");
    assert_eq!(v["record_file_units"], "g");
    assert!(stderr(&out).contains("replaces the config's [record]"), "{}", stderr(&out));
    let out = quakejoint(&["simulate", cfg.to_str().unwrap(), "--record", at2.to_str().unwrap(), "--scale", "0.5"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(String::from_utf8_lossy(&out.stdout).contains("PGA 0.2414 g"), "{}", String::from_utf8_lossy(&out.stdout));
    // reading options describe the file of --record
    let out = quakejoint(&["simulate", cfg.to_str().unwrap(), "--units", "g"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--record"), "{}", stderr(&out));
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
    assert_eq!(lines[0], "damping [1],period [s],sa [m/s^2],psa [m/s^2],sd [m],sv [m/s]");
    assert_eq!(lines.len(), 11);
    // every digit: the CSV's numbers are the JSON's, bit for bit
    let rows = json(&quakejoint(&[
        "spectrum",
        "ground_motions/RSN753_LOMAP_CLS090-hor2.AT2",
        "--periods",
        "0.3,1.0",
        "--damping",
        "0.05",
        "--json",
    ]));
    let csv = quakejoint(&[
        "spectrum",
        "ground_motions/RSN753_LOMAP_CLS090-hor2.AT2",
        "--periods",
        "0.3,1.0",
        "--damping",
        "0.05",
        "--csv",
    ]);
    for (line, row) in String::from_utf8(csv.stdout).unwrap().lines().skip(1).zip(rows.as_array().unwrap()) {
        let cols: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
        for (k, key) in ["sa", "psa", "sd", "sv"].iter().enumerate() {
            assert_eq!(cols[2 + k].to_bits(), row[key].as_f64().unwrap().to_bits(), "{key}");
        }
    }
}

#[test]
fn bad_input_exits_with_code_2_and_names_the_problem() {
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["model", "configs/missing.toml"], "configs/missing.toml"),
        (vec!["simulate", "configs/small.toml", "--period", "-1"], "--period -1"),
        (vec!["simulate", "configs/small.toml", "--record", "ground_motions/none.AT2"], "none.AT2"),
        (vec!["record", "configs/paper.toml"], "paper.toml"),
        (vec!["spectrum", "ground_motions/RSN753_LOMAP_CLS090-hor2.AT2", "--damping", "1.5"], "1.5"),
        (vec!["service", "configs/small.toml", "--speed", "0"], "--speed 0: must be within"),
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

/// The model description's default record exists: a config without
/// `[record]` runs under the built-in Corralitos 090, byte for byte the file
/// in `ground_motions/` (its SHA-256 is the one in PROVENANCE.md).
#[test]
fn a_config_without_a_record_uses_the_built_in_default() {
    let d = dir("cli-default-record");
    let empty = d.join("empty.toml");
    std::fs::write(&empty, "").unwrap();
    let out = d.join("run.h5");
    let v = json(&quakejoint(&[
        "simulate",
        empty.to_str().unwrap(),
        "--no-joint",
        "--json",
        "--output",
        out.to_str().unwrap(),
    ]));
    assert_eq!(v["record"], "RSN753_LOMAP_CLS090-hor2");
    let file_sa = json(&quakejoint(&["simulate", "configs/paper.toml", "--no-joint", "--json"]))["sa"].clone();
    assert_eq!(v["sa"], file_sa, "the same record as the shipped file");
    let f = hdf5::File::open(&out).unwrap();
    let x = f.group("inputs/records/x").unwrap();
    let sha = quakejoint_io::h5::read_attr_str(&x, "sha256").unwrap();
    let provenance = std::fs::read_to_string(common::root().join("ground_motions/PROVENANCE.md")).unwrap();
    assert!(provenance.contains(sha.as_str()), "{} is not in PROVENANCE.md", sha.as_str());
}

/// Error messages quote the offending input, but never megabytes of it
/// (a 1 MB token used to give 1.2 MB of stderr; the OS caps one argument
/// near 128 kB).
#[test]
fn error_messages_quote_at_most_a_short_excerpt() {
    let long = "1".repeat(100_000);
    let out = quakejoint(&["simulate", "configs/small.toml", "--period", &format!("x{long}")]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stderr.len() < 4000, "{} bytes of stderr", out.stderr.len());
    let d = dir("cli-long");
    let bad = d.join("bad.toml");
    std::fs::write(&bad, format!("[joint]\npitch = {long}x\n")).unwrap();
    let out = quakejoint(&["model", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stderr.len() < 4000, "{} bytes of stderr", out.stderr.len());
    assert!(stderr(&out).contains("bad.toml"), "{}", stderr(&out));
}

/// Every config shipped in `configs/` builds its model, and every one with
/// a `[sweep]` table plans (both read and check the whole config, the
/// records and modes files it names included): a shipped study that rots
/// is found here, not by a user.
#[test]
fn every_shipped_config_builds_and_every_sweep_plans() {
    let mut configs: Vec<_> = std::fs::read_dir(common::root().join("configs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    configs.sort();
    assert!(configs.len() >= 14, "{configs:?}");
    for c in &configs {
        let path = c.to_str().unwrap();
        let out = quakejoint(&["model", path]);
        assert_eq!(out.status.code(), Some(0), "{path}: {}", common::stderr(&out));
        if std::fs::read_to_string(c).unwrap().lines().any(|l| l.trim() == "[sweep]") {
            let out = quakejoint(&["plan", path]);
            assert_eq!(out.status.code(), Some(0), "{path}: {}", common::stderr(&out));
        }
    }
}
