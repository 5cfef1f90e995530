//! The edges a user steps onto off the shipped path: records from CESMD,
//! paths that are not UTF-8, FIFOs and devices given as files, absurd
//! thread counts and intervals, long messages. Each must give a clear
//! answer with the right exit code: no panic (exit 101), no hang, no
//! unbounded read, and an error that names the value.

mod common;

use std::ffi::OsStr;
use std::os::unix::ffi::OsStrExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::{bin, config, dir, root, run};

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Runs the command with a deadline: a hang fails the test instead of
/// stalling the suite.
fn run_within(args: &[&OsStr], seconds: u64) -> Output {
    let mut child = bin().args(args).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(seconds) {
            let _ = child.kill();
            panic!("quakejoint {args:?} still runs after {seconds} s: it hangs");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn os(s: &str) -> &OsStr {
    OsStr::new(s)
}

fn cesmd(file: &str) -> String {
    root().join("ground_motions/cesmd").join(file).display().to_string()
}

#[test]
fn a_cesmd_volume_1_file_is_read_by_every_command() {
    // quakejoint record: the channel and its direction, the duration said as
    // what it is (n - 1) dt, the header's n dt told apart
    let out = run(&["record", &cesmd("CICLC.v1"), "--channel", "2"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.contains("read as           csmip file, numbers in g"), "{text}");
    assert!(text.contains("channel           channel 2 of 3 (360°)"), "{text}");
    assert!(text.contains("319.310 s") || text.contains("320.790 s"), "{text}");
    assert!(text.contains("(first to last sample: (samples - 1) dt)"), "{text}");
    let json: serde_json::Value =
        serde_json::from_slice(&run(&["record", &cesmd("CICLC.v1"), "--azimuth", "90", "--json"]).stdout).unwrap();
    assert_eq!(json["channel"]["number"], 1);
    assert_eq!(json["channel"]["orientation"]["degrees"], 90.0);
    assert_eq!(json["duration"].as_f64().unwrap(), 31931.0 * 0.01);
    // spectrum and simulate --record take the channel too
    let out = run(&["spectrum", &cesmd("CICLC.v1"), "--azimuth", "360", "--periods", "1.0"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let out = run(&[
        "simulate",
        "configs/small.toml",
        "--record",
        &cesmd("CE54730_CHAN001.V2"),
        "--no-joint",
        "--period",
        "1.0",
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // the vertical channel is refused unless asked for, and says how
    let out = run(&["record", &cesmd("CICLC.v1"), "--channel", "3"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--allow-vertical"), "{}", stderr(&out));
    assert_eq!(run(&["record", &cesmd("CICLC.v1"), "--channel", "3", "--allow-vertical"]).status.code(), Some(0));
    // --column on a file of channels says what to use
    let out = run(&["record", &cesmd("CICLC.v1"), "--column", "2"]);
    assert!(stderr(&out).contains("`--channel N`"), "{}", stderr(&out));
    // a config's record table takes the channel
    let d = dir("edges-cesmd");
    let cfg = config(&d, "c.toml", "", 2.0);
    let text = std::fs::read_to_string(&cfg).unwrap();
    let start = text.find("[record]").unwrap();
    let end = start + text[start..].find("[simulation]").unwrap();
    let record = format!("[record]\nfile = {:?}\nazimuth = 360\nscale = 0.15\n", cesmd("CICLC.v1"));
    std::fs::write(&cfg, format!("{}{record}{}", &text[..start], &text[end..])).unwrap();
    let out = run(&["simulate", cfg.to_str().unwrap(), "--no-joint", "--period", "1.0"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

/// A file name that is not UTF-8 (Latin-1 `ÿ`).
fn latin1(dir: &Path, stem: &[u8], ext: &str) -> PathBuf {
    let mut name = stem.to_vec();
    name.extend_from_slice(ext.as_bytes());
    dir.join(OsStr::from_bytes(&name))
}

#[test]
fn paths_that_are_not_utf8_never_panic() {
    let d = dir("edges-latin1");
    let good = config(&d, "good.toml", "[sweep]\nperiods = [1.0]\ndamping = [0.05]\n", 1.0);
    let cfg = latin1(&d, b"q\xff", ".toml");
    std::fs::copy(&good, &cfg).unwrap();
    // a config whose name is not UTF-8 is read; the output name derived
    // from it, and the command line kept for the output's provenance
    let out = run_within(&[os("sweep"), cfg.as_os_str(), os("--check")], 60);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let output = d.join("out.h5");
    let out = run_within(
        &[os("sweep"), cfg.as_os_str(), os("--output"), output.as_os_str(), os("--progress"), os("none")],
        120,
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let file = hdf5::File::open(&output).unwrap();
    let command = quakejoint_io::h5::read_attr_str(&file, "command").unwrap();
    assert!(command.as_str().contains("q\\xff.toml'") && command.as_str().contains(" $'"), "{}", command.as_str());
    // an output name HDF5 cannot take is refused before anything runs
    let bad_out = latin1(&d, b"o\xff", ".h5");
    for args in [
        vec![os("simulate"), good.as_os_str(), os("--period"), os("1.0"), os("--output"), bad_out.as_os_str()],
        vec![os("sweep"), good.as_os_str(), os("--output"), bad_out.as_os_str()],
    ] {
        let start = Instant::now();
        let out = run_within(&args, 60);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains("only UTF-8 file names"), "{}", stderr(&out));
        assert!(start.elapsed() < Duration::from_secs(30), "refused before running");
    }
    assert!(!bad_out.exists());
}

#[test]
fn fifos_and_devices_are_refused_as_records_and_configs() {
    let d = dir("edges-fifo");
    let fifo = d.join("record.fifo");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let cfg = config(&d, "c.toml", "[sweep]\nperiods = [1.0]\ndamping = [0.05]\n", 1.0);
    let text = std::fs::read_to_string(&cfg).unwrap();
    let via_fifo = d.join("fifo.toml");
    let record = root().join("ground_motions/RSN753_LOMAP_CLS090-hor2.AT2");
    std::fs::write(
        &via_fifo,
        text.replace(&format!("{:?}", record.display().to_string()), &format!("{:?}", fifo.display().to_string())),
    )
    .unwrap();
    for (args, what) in [
        (vec![os("record"), fifo.as_os_str(), os("--units"), os("g"), os("--dt"), os("0.01")], "a FIFO"),
        (vec![os("record"), os("/dev/zero"), os("--units"), os("g"), os("--dt"), os("0.01")], "a device"),
        (vec![os("simulate"), via_fifo.as_os_str(), os("--no-joint")], "a FIFO"),
        (vec![os("sweep"), via_fifo.as_os_str(), os("--check")], "a FIFO"),
        (vec![os("sweep"), fifo.as_os_str(), os("--check")], "a FIFO"),
        (vec![os("model"), os("/dev/zero")], "a device"),
    ] {
        let out = run_within(&args, 30);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains(what), "{args:?}: {}", stderr(&out));
    }
}

#[test]
fn absurd_counts_and_intervals_are_refused_naming_the_value() {
    let d = dir("edges-absurd");
    let cfg = config(&d, "c.toml", "[sweep]\nperiods = [1.0]\ndamping = [0.05]\n", 1.0);
    let cfg = cfg.to_str().unwrap();
    for (args, says) in [
        (vec!["sweep", cfg, "--threads", "100000"], "100000: expected a whole number of threads from 1 to 1024"),
        (vec!["plan", cfg, "--threads", "100000"], "from 1 to 1024"),
        (vec!["sweep", cfg, "--progress-interval", "1e20", "--check"], "--progress-interval 100000000000000000000"),
    ] {
        let out = run_within(&args.iter().map(|a| os(a)).collect::<Vec<_>>(), 30);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains(says), "{args:?}: {}", stderr(&out));
    }
    let slow = config(&d, "slow.toml", "[sweep]\nperiods = [1.0]\ndamping = [0.05]\ncheckpoint_seconds = 1e20\n", 1.0);
    let out = run_within(&[os("sweep"), slow.as_os_str(), os("--check")], 30);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("sweep.checkpoint_seconds"), "{}", stderr(&out));
    // 1024 threads for one job: one worker, done at once
    let out = run_within(
        &[os("sweep"), os(cfg), os("--threads"), os("1024"), os("--output"), d.join("one.h5").as_os_str()],
        120,
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

#[test]
fn an_empty_journal_is_one_that_check_and_sweep_both_start_afresh() {
    let d = dir("edges-journal");
    let cfg = config(&d, "c.toml", "[sweep]\nperiods = [1.0]\ndamping = [0.05]\n", 1.0);
    let out = d.join("out.h5");
    std::fs::write(d.join("out.h5.journal"), b"").unwrap();
    let check = run(&["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap(), "--check"]);
    assert_eq!(check.status.code(), Some(0), "{}", stderr(&check));
    assert!(stdout(&check).contains("0 failed"), "{}", stdout(&check));
    let sweep = run(&["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap()]);
    assert_eq!(sweep.status.code(), Some(0), "{}", stderr(&sweep));
}

#[test]
fn a_long_path_keeps_the_cause_in_a_bounded_line() {
    let d = dir("edges-long");
    let deep = d.join("x".repeat(200)).join("y".repeat(200)).join("z".repeat(200));
    std::fs::create_dir_all(&deep).unwrap();
    let missing = deep.join("missing.AT2");
    let out = run(&["record", missing.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(err.lines().all(|l| l.chars().count() <= 500), "{err}");
    assert!(err.contains("missing.AT2") && err.contains("No such file or directory"), "{err}");
}

#[test]
fn a_sweep_of_ten_records_is_complete_when_run_again() {
    // more than 8 members put an HDF5 1.10 group in dense storage, whose
    // members are listed in hashed order, not the config's: the check of a
    // finished output against its config must not depend on that order
    let d = dir("edges-ten");
    let gm = root().join("ground_motions");
    let mut records: Vec<String> = std::fs::read_dir(&gm)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "AT2"))
        .map(|p| format!("{{ file = {:?} }}", p.display().to_string()))
        .collect();
    records.sort();
    records.push(format!("{{ file = {:?} }}", cesmd("CE54730_CHAN001.V2")));
    records.push(format!("{{ file = {:?}, channel = 1 }}", cesmd("CICLC.v1")));
    assert_eq!(records.len(), 10);
    let sweep = format!("[sweep]\nperiods = [1.0]\ndamping = [0.05]\nrecords = [\n  {}\n]\n", records.join(",\n  "));
    let cfg = config(&d, "ten.toml", &sweep, 1.0);
    let out = d.join("ten.h5");
    let args = ["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap(), "--progress", "none"];
    let first = run(&args);
    assert_eq!(first.status.code(), Some(0), "{}", stderr(&first));
    let again = run(&args);
    assert_eq!(again.status.code(), Some(0), "{}", stderr(&again));
    assert!(!stderr(&again).contains("rebuilt"), "a good output taken for a damaged one: {}", stderr(&again));
    let check = run(&["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap(), "--check"]);
    assert!(stdout(&check).contains("output are fine"), "{}{}", stdout(&check), stderr(&check));
}

#[test]
fn a_damaged_earlier_merge_is_replaced_by_the_next_merge() {
    let d = dir("edges-remerge");
    let cfg = config(&d, "c.toml", "[sweep]\nperiods = [0.5, 1.0]\ndamping = [0.05]\n", 1.0);
    let shards: Vec<String> = (1..=2).map(|k| d.join(format!("s{k}.h5")).display().to_string()).collect();
    for (k, shard) in shards.iter().enumerate() {
        let spec = format!("{}/2", k + 1);
        let out = run(&["sweep", cfg.to_str().unwrap(), "--shard", &spec, "--output", shard]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    }
    let merged = d.join("all.h5").display().to_string();
    let merge = || run(&["merge", &shards[0], &shards[1], "--output", &merged]);
    assert_eq!(merge().status.code(), Some(0));
    // one bit of the merged file's reduction flipped on disk
    let at = {
        let f = hdf5::File::open(&merged).unwrap();
        let info = f.dataset("spectrum/reduction").unwrap().chunk_info(0).unwrap();
        (info.addr + info.size / 2) as usize
    };
    let mut bytes = std::fs::read(&merged).unwrap();
    bytes[at] ^= 0x10;
    std::fs::write(&merged, bytes).unwrap();
    let out = run(&["compare", &merged, &merged]);
    assert_ne!(out.status.code(), Some(0));
    assert!(stderr(&out).contains("/spectrum/reduction is damaged"), "{}", stderr(&out));
    let again = merge();
    assert_eq!(again.status.code(), Some(0), "{}", stderr(&again));
    assert!(stderr(&again).contains("the earlier merge there cannot be read") && stderr(&again).contains("replaced"));
    assert_eq!(run(&["compare", &merged, &merged]).status.code(), Some(0));
}

/// Every file the tool opens goes through one reader that refuses what is
/// not a regular file: a FIFO (which would block until something writes
/// to it) or /dev/zero (which never ends: the process held 7 GB after 6 s)
/// as the modes file, the hazard curve, or an HDF5 input of `compare` and
/// `merge`, refused at once, named.
#[test]
fn fifos_and_devices_are_refused_as_modes_files_hazard_curves_and_hdf5_inputs() {
    let d = dir("edges-fifo-inputs");
    let fifo = d.join("input.fifo");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let modal = |modes: &Path| {
        format!(
            "[bridge]\ndamping = 0.05\n[bridge.modal]\nmodes = {:?}\njoint_point = \"left end\"\n[simulation]\nduration = 1.0\n",
            modes.display().to_string()
        )
    };
    let record = root().join("ground_motions/RSN753_LOMAP_CLS090-hor2.AT2").display().to_string();
    let stripes = |hazard: &Path| {
        format!(
            "[sweep]\nperiods = [1.0]\nrecords = [{{ file = {record:?} }}]\n[sweep.stripes]\nmeasure = \"pga\"\n\
             levels = [0.1, 0.2]\n[sweep.fragility]\nhazard = {{ file = {:?} }}\n",
            hazard.display().to_string()
        )
    };
    let good = config(&d, "good.toml", "[sweep]\nperiods = [1.0]\ndamping = [0.05]\n", 1.0);
    let good_out = d.join("good.h5");
    assert_eq!(run(&["sweep", good.to_str().unwrap(), "--output", good_out.to_str().unwrap()]).status.code(), Some(0));
    for (what, input) in [("a FIFO", fifo.as_path()), ("a device", Path::new("/dev/zero"))] {
        let modes_cfg = d.join("modes.toml");
        std::fs::write(&modes_cfg, modal(input)).unwrap();
        let hazard_cfg = config(&d, "hazard.toml", &stripes(input), 1.0);
        for args in [
            vec![os("model"), modes_cfg.as_os_str()],
            vec![os("simulate"), modes_cfg.as_os_str()],
            vec![os("sweep"), hazard_cfg.as_os_str(), os("--check")],
            vec![os("compare"), good_out.as_os_str(), input.as_os_str()],
            vec![os("merge"), input.as_os_str(), os("--output"), d.join("m.h5").as_os_str()],
        ] {
            let out = run_within(&args, 30);
            assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
            assert!(stderr(&out).contains(what), "{args:?}: {}", stderr(&out));
        }
    }
}

/// An output never overwrites an input: `calibrate --output-dir` holding
/// the config as `link.toml` is refused before the calibration runs, and
/// so is an output folder that is a file.
#[test]
fn calibrate_refuses_to_write_over_its_own_config_or_into_a_file() {
    let d = dir("edges-calibrate");
    let cfg = config(&d, "link.toml", "", 1.0);
    let before = std::fs::read(&cfg).unwrap();
    let start = Instant::now();
    let out = run_within(&[os("calibrate"), cfg.as_os_str(), os("--output-dir"), d.as_os_str()], 30);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("would overwrite its input"), "{}", stderr(&out));
    assert!(start.elapsed() < Duration::from_secs(10), "refused before calibrating");
    assert_eq!(std::fs::read(&cfg).unwrap(), before, "the config is untouched");
    let file = d.join("a-file");
    std::fs::write(&file, b"x").unwrap();
    let out = run_within(&[os("calibrate"), cfg.as_os_str(), os("--output-dir"), file.as_os_str()], 30);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("it is a file, not a folder"), "{}", stderr(&out));
}

/// A SIGTERM while the sweep still reads its config and records (the
/// first tenths of a second) stops it as one during its jobs does: exit
/// 143 and the command that continues it (a SLURM log then has the
/// resubmission). `QUAKEJOINT_TEST_HOLD_START` holds the sweep after its
/// handlers are installed and before it reads the config, so the signal
/// lands there however fast the machine.
#[test]
fn a_sigterm_while_the_config_is_read_leaves_the_continuation() {
    let d = dir("edges-early-signal");
    let cfg = config(&d, "c.toml", "[sweep]\nperiods = [1.0, 2.0]\ndamping = [0.05]\n", 1.0);
    let out = d.join("out.h5");
    let ready = d.join("held");
    let child = bin()
        .args(["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap()])
        .env("QUAKEJOINT_TEST_HOLD_START", &ready)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while !ready.exists() {
        assert!(start.elapsed() < Duration::from_secs(60), "the sweep never got to reading its config");
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(Command::new("kill").args(["-TERM", &child.id().to_string()]).status().unwrap().success());
    let done = child.wait_with_output().unwrap();
    assert_eq!(done.status.code(), Some(143), "{}", stderr(&done));
    assert!(stderr(&done).contains("continue with"), "{}", stderr(&done));
}

/// A config is refused by every command or by none: a broken `[sweep]`
/// table (here `[sweep.fragility]` and `[sweep.stripes]`) is named by
/// `model` and `simulate` as by `sweep`, not only when a sweep runs.
#[test]
fn a_broken_sweep_table_is_refused_by_model_and_simulate_too() {
    let d = dir("edges-sweep-table");
    let record = root().join("ground_motions/RSN753_LOMAP_CLS090-hor2.AT2").display().to_string();
    for (sweep, says) in [
        (
            "[sweep.stripes]\nmeasure = \"pga\"\nlevels = [0.1, 0.2]\n[sweep.fragility]\nbootstrap = -3\n",
            "sweep.fragility.bootstrap",
        ),
        ("[sweep.stripes]\nmeasure = \"pgv\"\nlevels = [0.1, 0.2]\n", "sweep.stripes.measure"),
    ] {
        let cfg = config(
            &d,
            "c.toml",
            &format!("[sweep]\nperiods = [1.0]\nrecords = [{{ file = {record:?} }}]\n{sweep}"),
            1.0,
        );
        for cmd in ["model", "simulate", "sweep"] {
            let out = run_within(&[os(cmd), cfg.as_os_str()], 60);
            assert_eq!(out.status.code(), Some(2), "{cmd}: {}", stderr(&out));
            assert!(stderr(&out).contains(says), "{cmd}: {}", stderr(&out));
        }
    }
}

/// `calibrate --record` reads its record as `quakejoint record` does and
/// says what it read: the first of CICLC.v1's three channels unless
/// `--channel` or `--azimuth` chooses, with the warning `simulate` gives;
/// and 2 mm loops of the small joint, which stay elastic, are refused
/// (their fitted slider would be noise).
#[test]
fn calibrate_says_which_channel_it_read_and_refuses_loops_that_do_not_slide() {
    let d = dir("edges-calibrate-channel");
    let cfg = root().join("configs/small.toml");
    let record = cesmd("CICLC.v1");
    let args = [os("calibrate"), cfg.as_os_str(), os("--record"), os(&record), os("--amplitudes"), os("0.002")];
    let out = run_within(&[&args[..], &[os("--output-dir"), d.as_os_str()]].concat(), 120);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("holds 3 channels") && stderr(&out).contains("channel 1 of 3"), "{}", stderr(&out));
    assert!(stderr(&out).contains("the loops do not slide"), "{}", stderr(&out));
    let chosen = [&args[..], &[os("--channel"), os("2"), os("--output-dir"), d.as_os_str()]].concat();
    let out = run_within(&chosen, 120);
    assert!(!stderr(&out).contains("holds 3 channels"), "{}", stderr(&out));
}
