//! Overnight and cluster batch runs: each test reproduces a way a batch run
//! used to stall, lose work or report a partial or wrong result as whole.
//!
//! - Merging: an incomplete set of shards is refused (naming the missing
//!   shards and jobs) unless a partial result is accepted explicitly; a shard
//!   file that does not exist or does not read is named, with exit code 2; the
//!   same file twice is read once; two files claiming one shard are refused;
//!   jobs in two overlapping inputs are kept once when identical.
//! - Failed jobs can be retried (`--retry-failed`) after raising a per-job
//!   limit, keeping the finished jobs, to the numbers of an unlimited run.
//! - Two sweeps started together into one output: the second is refused
//!   before it creates or changes anything (the lock comes first).
//! - An output that disagrees with its journal (missing, cut short, another
//!   sweep's) is rebuilt from the journal with a warning, never reported as
//!   fine; a damaged journal entry in the middle is named by its byte offset
//!   and only its job runs again.
//! - SIGTERM and SIGINT end a sweep within seconds with a final checkpoint,
//!   the command to continue, and exit codes 143 and 130.
//! - Progress is written as plain lines when stderr is not a terminal, and
//!   `simulate` draws a bar on a terminal.
//! - No output overwrites an input (the config, a record, another output's
//!   journal) or a file that is not its own.
//! - The README's main job can be run twice: the second run says it is
//!   complete.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::{assert_identical, bin, config, dir, ok, root, run, stderr, stdout, wait_for_jobs};
use quakejoint_sweep::results::status;
use quakejoint_sweep::sweep_h5::read_sweep;

const GRID: &str = "[sweep]\nperiods = [0.3, 0.6, 1.0, 2.0, 3.0]\ndamping = [0.05]\n";

fn sweep(cfg: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    run(&args)
}

fn merge(files: &[&Path], out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args: Vec<&str> = vec!["merge"];
    args.extend(files.iter().map(|f| f.to_str().unwrap()));
    args.extend(["--output", out.to_str().unwrap()]);
    args.extend_from_slice(extra);
    run(&args)
}

#[test]
fn merge_refuses_incomplete_duplicate_and_unreadable_shards() {
    let d = dir("merge-rules");
    let cfg = config(&d, "c.toml", GRID, 2.0);
    let reference = d.join("reference.h5");
    ok(&sweep(&cfg, &reference, &[]));
    let shard = |k: usize, n: usize| {
        let p = d.join(format!("s{k}of{n}.h5"));
        ok(&sweep(&cfg, &p, &["--shard", &format!("{k}/{n}")]));
        p
    };
    let (s1, s2, s3) = (shard(1, 3), shard(2, 3), shard(3, 3));
    let all = d.join("all.h5");

    // an incomplete set: refused, nothing written, the missing shard named
    let res = merge(&[&s1, &s2], &all, &[]);
    assert_eq!(res.status.code(), Some(2), "{}", stderr(&res));
    for fragment in ["incomplete", "missing shards: 3/3", "have no result", "--allow-partial"] {
        assert!(stderr(&res).contains(fragment), "{fragment}: {}", stderr(&res));
    }
    assert!(!all.exists());
    // accepted explicitly: written, and the file says it is partial
    let res = merge(&[&s1, &s2], &all, &["--allow-partial", "--json"]);
    ok(&res);
    let v: serde_json::Value = serde_json::from_slice(&res.stdout).unwrap();
    assert_eq!((v["complete"].as_bool(), v["missing"].as_u64()), (Some(false), Some(plan_jobs(&s3))));
    let f = hdf5::File::open(&all).unwrap();
    assert_eq!(f.attr("complete").unwrap().read_scalar::<u8>().unwrap(), 0);
    drop(f);

    // a shard file that does not exist, and one that is not a sweep file:
    // exit 2, each named
    let absent = d.join("s4of3.h5");
    let garbage = d.join("garbage.h5");
    std::fs::write(&garbage, b"not hdf5").unwrap();
    let res = merge(&[&s1, &absent, &garbage], &all, &[]);
    assert_eq!(res.status.code(), Some(2), "{}", stderr(&res));
    assert!(stderr(&res).contains(&format!("{}: no such file", absent.display())), "{}", stderr(&res));
    assert!(stderr(&res).contains(&format!("{}: not a readable sweep file", garbage.display())), "{}", stderr(&res));

    // the same file twice: read once, with a warning; the result is whole
    let res = merge(&[&s1, &s2, &s3, &s2], &all, &[]);
    ok(&res);
    assert!(stderr(&res).contains("was given twice"), "{}", stderr(&res));
    assert_identical(&read_sweep(&all).unwrap(), &read_sweep(&reference).unwrap(), "merge with a duplicate path");

    // a copy of a shard under another name: two files claim one shard
    let copy = d.join("copy.h5");
    std::fs::copy(&s2, &copy).unwrap();
    let res = merge(&[&s1, &s2, &s3, &copy], &all, &[]);
    assert_eq!(res.status.code(), Some(2), "{}", stderr(&res));
    assert!(stderr(&res).contains("both hold shard 2/3"), "{}", stderr(&res));

    // overlapping splits (1/2 and the three thirds): identical jobs kept once
    let h1 = shard(1, 2);
    let res = merge(&[&h1, &s1, &s2, &s3], &all, &[]);
    ok(&res);
    assert!(stderr(&res).contains("in more than one input with identical results: kept once"), "{}", stderr(&res));
    assert_identical(&read_sweep(&all).unwrap(), &read_sweep(&reference).unwrap(), "overlapping shards");
    assert_eq!(hdf5::File::open(&all).unwrap().attr("complete").unwrap().read_scalar::<u8>().unwrap(), 1);
}

/// Jobs in a shard file's scope.
fn plan_jobs(shard: &Path) -> u64 {
    read_sweep(shard).unwrap().scope.len() as u64
}

#[test]
fn retry_failed_reruns_the_failed_jobs_after_a_limit_is_raised() {
    let d = dir("retry");
    let cases = "[[sweep.cases]]\nname = \"a\"\n[[sweep.cases]]\nname = \"b\"\njoint.friction.mu = 0.1\n";
    // the reference: no step limit
    let unlimited = config(&d, "unlimited.toml", &format!("{GRID}{cases}"), 2.0);
    let reference = d.join("reference.h5");
    ok(&sweep(&unlimited, &reference, &[]));
    // the same sweep with a step limit too low for the jobs of case b
    let limited = d.join("c.toml");
    let text = std::fs::read_to_string(&unlimited).unwrap() + "simulation.max_steps = 100\n";
    std::fs::write(&limited, &text).unwrap();
    let out = d.join("out.h5");
    let first = sweep(&limited, &out, &["--json"]);
    assert_eq!(first.status.code(), Some(3), "{}", stderr(&first));
    let st = read_sweep(&out).unwrap().results.status;
    assert_eq!(st, [vec![status::OK; 5], vec![status::LIMIT; 5]].concat());
    let failed = 5;
    // raise the limit: continuing keeps the failures, --retry-failed runs them
    std::fs::write(&limited, text.replace("max_steps = 100", "max_steps = 1000000")).unwrap();
    let again = sweep(&limited, &out, &["--json"]);
    assert_eq!(again.status.code(), Some(3), "{}", stderr(&again));
    let retried = sweep(&limited, &out, &["--retry-failed", "--json"]);
    ok(&retried);
    let v: serde_json::Value = serde_json::from_slice(&retried.stdout).unwrap();
    assert_eq!(v["retried"].as_u64(), Some(failed as u64));
    assert_eq!(v["ran"].as_u64(), Some(failed as u64), "only the failed jobs ran again");
    assert_identical(&read_sweep(&out).unwrap(), &read_sweep(&reference).unwrap(), "retried vs unlimited");
}

/// Waits until `file` exists (the child paused) or fails the test.
fn wait_for(file: &Path, child: &mut Child) {
    let start = Instant::now();
    while !file.exists() {
        assert!(child.try_wait().unwrap().is_none(), "the process ended before {}", file.display());
        assert!(start.elapsed() < Duration::from_secs(120), "{} never appeared", file.display());
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn two_sweeps_started_together_into_one_output_never_both_run() {
    let d = dir("race");
    let cfg = config(&d, "c.toml", GRID, 1.0);
    let out = d.join("out.h5");
    let journal = d.join("out.h5.journal");
    // the first holds the lock and stops before creating anything
    let mut first = bin()
        .args(["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap()])
        .env("QUAKEJOINT_TEST_PAUSE", "locked:1")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_for(&quakejoint_sweep::fault::marker(&out), &mut first);
    assert!(!journal.exists() && !out.exists(), "nothing exists before the lock is taken");
    let second = sweep(&cfg, &out, &[]);
    assert_eq!(second.status.code(), Some(2), "{}", stderr(&second));
    assert!(stderr(&second).contains("another quakejoint process is writing this output"), "{}", stderr(&second));
    assert!(!journal.exists() && !out.exists(), "the refused sweep created nothing");
    first.kill().unwrap();
    first.wait().unwrap();

    // unforced: pairs started at the same moment run the jobs once between them
    let reference = d.join("reference.h5");
    ok(&sweep(&cfg, &reference, &[]));
    for pair in 0..10 {
        let out = d.join(format!("pair{pair}.h5"));
        let spawn = || {
            bin()
                .args(["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap(), "--json", "--threads", "1"])
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        };
        let (a, b) = (spawn(), spawn());
        let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
        let ran = |o: &std::process::Output| match o.status.code() {
            Some(0) => serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()["ran"].as_u64().unwrap(),
            Some(2) if stderr(o).contains("another quakejoint process") => 0,
            other => panic!("pair {pair}: exit {other:?}: {}", stderr(o)),
        };
        assert_eq!(ran(&a) + ran(&b), 5, "pair {pair}: every job ran exactly once");
        assert_identical(&read_sweep(&out).unwrap(), &read_sweep(&reference).unwrap(), "a racing pair");
    }
}

#[test]
fn an_output_that_disagrees_with_its_journal_is_rebuilt_with_a_warning() {
    let d = dir("rebuild");
    let cfg = config(&d, "c.toml", GRID, 1.5);
    let reference = d.join("reference.h5");
    ok(&sweep(&cfg, &reference, &[]));
    let other_cfg = config(&d, "other.toml", "[sweep]\nperiods = [0.5]\n", 1.0);
    let foreign = d.join("foreign.h5");
    ok(&sweep(&other_cfg, &foreign, &[]));
    let out = d.join("out.h5");
    ok(&sweep(&cfg, &out, &[]));
    let whole = std::fs::read(&out).unwrap();
    for what in ["it is missing", "it cannot be read", "written for another config"] {
        match what {
            "it is missing" => std::fs::remove_file(&out).unwrap(),
            "it cannot be read" => std::fs::write(&out, &whole[..whole.len() / 2]).unwrap(),
            _ => drop(std::fs::copy(&foreign, &out).unwrap()),
        }
        let res = sweep(&cfg, &out, &["--json"]);
        ok(&res);
        assert!(stderr(&res).contains(what) && stderr(&res).contains("rebuilt from the journal"), "{}", stderr(&res));
        let v: serde_json::Value = serde_json::from_slice(&res.stdout).unwrap();
        assert_eq!(v["ran"].as_u64(), Some(0), "{what}: the journal's jobs are not run again");
        assert!(v["notices"][0].as_str().unwrap().contains(what));
        assert_identical(&read_sweep(&out).unwrap(), &read_sweep(&reference).unwrap(), what);
    }

    // a flipped bit in the middle of the journal: named, its job run again
    let journal = d.join("out.h5.journal");
    let mut bytes = std::fs::read(&journal).unwrap();
    let (header, entries) = quakejoint_sweep::journal::read(&journal).unwrap();
    assert_eq!((header.jobs, entries.len()), (5, 5));
    let at = bytes.len() / 2;
    bytes[at] ^= 0x04;
    std::fs::write(&journal, &bytes).unwrap();
    let res = sweep(&cfg, &out, &["--json"]);
    ok(&res);
    let v: serde_json::Value = serde_json::from_slice(&res.stdout).unwrap();
    assert!(stderr(&res).contains("damaged bytes at byte offset"), "{}", stderr(&res));
    assert_eq!(v["ran"].as_u64(), Some(1), "only the damaged entry's job runs again");
    assert_identical(&read_sweep(&out).unwrap(), &read_sweep(&reference).unwrap(), "journal with a flipped bit");
    // the journal was rewritten whole: no second warning
    let res = sweep(&cfg, &out, &[]);
    ok(&res);
    assert!(!stderr(&res).contains("damaged"), "{}", stderr(&res));
}

#[test]
fn sigterm_and_sigint_checkpoint_and_print_the_command_to_continue() {
    let d = dir("signals");
    let grid = "[sweep]\nperiods = { from = 0.3, to = 3.0, count = 12 }\ndamping = [0.05]\n";
    let cfg = config(&d, "c.toml", grid, 4.0);
    let reference = d.join("reference.h5");
    ok(&sweep(&cfg, &reference, &["--threads", "2"]));
    for (signal, code) in [("TERM", 143), ("INT", 130)] {
        let out = d.join(format!("{signal}.h5"));
        let journal = d.join(format!("{signal}.h5.journal"));
        // the last job is held until the signal: the sweep is still running
        // when it comes, however fast the machine
        let mut child = bin()
            .args(["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap(), "--threads", "1"])
            .env("QUAKEJOINT_TEST_HOLD", "all")
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        wait_for_jobs(&mut child, &journal, 3, signal);
        let sent = Instant::now();
        let kill = Command::new("kill").args([&format!("-{signal}"), &child.id().to_string()]).status().unwrap();
        assert!(kill.success());
        let res = child.wait_with_output().unwrap();
        let took = sent.elapsed();
        assert!(took < Duration::from_secs(5), "{signal}: the sweep took {took:?} to stop");
        assert_eq!(res.status.code(), Some(code), "{signal}: {}", stderr(&res));
        // the printed command is the one that was run (+ --resume), quoted
        // for a shell: run as printed, it continues
        let err = stderr(&res);
        let command =
            err.lines().skip_while(|l| !l.contains("continue with")).nth(1).unwrap_or_else(|| panic!("{err}"));
        assert!(command.contains("--resume") && command.contains(&out.display().to_string()), "{command}");
        let (interrupted, _) = quakejoint_sweep::journal::read(&journal).map(|(_, r)| (r.len(), 0)).unwrap();
        // the final checkpoint holds every journalled job
        let (_, journalled) = quakejoint_sweep::journal::read(&journal).unwrap();
        let file = read_sweep(&out).unwrap();
        assert_eq!(file.results.finished(), journalled.len(), "{signal}: checkpoint and journal agree");
        assert!(journalled.len() < 12, "{signal}: interrupted part way");
        assert!(stdout(&res).contains("sweep interrupted"), "{}", stdout(&res));
        // the printed command, run by a shell, finishes the work to the same numbers
        let resumed = Command::new("sh").arg("-c").arg(command.trim()).current_dir(root()).output().unwrap();
        ok(&resumed);
        assert!(stdout(&resumed).contains(&format!("({interrupted} from the journal")), "{}", stdout(&resumed));
        assert_identical(&read_sweep(&out).unwrap(), &read_sweep(&reference).unwrap(), signal);
    }
}

/// Neither half depends on the machine's speed: the sweep's last job is
/// held (`QUAKEJOINT_TEST_HOLD`) until the test has seen progress lines, and
/// the bar of `simulate` is asked for from the start
/// (`QUAKEJOINT_BAR_AFTER=0`) of a run that takes a few hundredths of a
/// second, far less than the second after which a bar is drawn by default.
#[test]
fn progress_goes_to_logs_as_lines_and_to_terminals_as_bars() {
    let d = dir("progress");
    let grid = "[sweep]\nperiods = { from = 0.3, to = 3.0, count = 12 }\ndamping = [0.05]\n";
    let cfg = config(&d, "c.toml", grid, 2.0);
    let out = d.join("out.h5");
    // stderr is a file here, as in a SLURM log
    let log_file = d.join("sweep.log");
    let mut child = bin()
        .args(["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap()])
        .args(["--threads", "1", "--progress-interval", "0.02"])
        .env("QUAKEJOINT_TEST_HOLD", "all")
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&log_file).unwrap())
        .spawn()
        .unwrap();
    // the held job: lines go on while nothing finishes
    let held = || std::fs::read_to_string(&log_file).unwrap().contains("running: 11 of 12 jobs done");
    let start = Instant::now();
    while !held() {
        assert!(child.try_wait().unwrap().is_none(), "the sweep ended while its last job was held");
        assert!(start.elapsed() < Duration::from_secs(120), "no progress lines");
        std::thread::sleep(Duration::from_millis(10));
    }
    std::fs::write(quakejoint_sweep::fault::release(&out), b"").unwrap();
    assert!(child.wait().unwrap().success());
    let log = std::fs::read_to_string(&log_file).unwrap();
    let lines: Vec<&str> = log.lines().filter(|l| l.contains("sweep out.h5")).collect();
    assert!(lines.len() >= 3, "a line per interval: {log}");
    assert!(lines[0].starts_with('[') && lines[0].contains("started: 0 of 12 jobs done"), "{log}");
    assert!(lines.iter().any(|l| l.contains("running: 11 of 12 jobs done") && l.contains("ETA")), "{log}");
    assert!(lines.last().unwrap().contains("finished: 12 of 12 jobs done (0 failed, 0 flagged)"), "{log}");
    assert!(!log.contains('\r') && !log.contains('\x1b'), "no terminal control characters in a log");

    // `simulate` on a terminal (a pseudo-terminal from `script`): a
    // progress bar, drawn from the start, however short the run
    let sim = config(&d, "sim.toml", "", 2.0);
    let command = format!("{} simulate {} --json", env!("CARGO_BIN_EXE_quakejoint"), sim.display());
    let on_tty = |after: &str| {
        Command::new("script").args(["-qec", &command, "/dev/null"]).env("QUAKEJOINT_BAR_AFTER", after).output()
    };
    let tty = on_tty("0").unwrap();
    assert!(tty.status.success(), "{}", stdout(&tty));
    assert!(stdout(&tty).contains("simulate [") && stdout(&tty).contains("ETA"), "{}", stdout(&tty));
    // a threshold never reached: no bar; and without a terminal, no bar
    let late = on_tty("1e9").unwrap();
    assert!(late.status.success() && !stdout(&late).contains("simulate ["), "{}", stdout(&late));
    let plain =
        bin().args(["simulate", sim.to_str().unwrap(), "--json"]).env("QUAKEJOINT_BAR_AFTER", "0").output().unwrap();
    ok(&plain);
    assert!(!stderr(&plain).contains("simulate ["), "{}", stderr(&plain));
}

#[test]
fn outputs_never_overwrite_inputs_or_files_that_are_not_theirs() {
    let d = dir("overwrite");
    let cfg = config(&d, "c.toml", GRID, 1.0);
    let record = root().join("ground_motions/RSN753_LOMAP_CLS090-hor2.AT2");
    let cfg_before = std::fs::read(&cfg).unwrap();
    let record_before = std::fs::read(&record).unwrap();
    let other = d.join("other.h5");
    ok(&sweep(&cfg, &other, &[]));
    let other_journal = d.join("other.h5.journal");
    let journal_before = std::fs::read(&other_journal).unwrap();
    let notes = d.join("notes.txt");
    std::fs::write(&notes, "my notes").unwrap();
    let cases: [(&str, &PathBuf, &str); 4] = [
        ("the config", &cfg, "would overwrite the input"),
        ("a record", &record, "would overwrite the input"),
        ("another output's journal", &other_journal, "a quakejoint journal"),
        ("an unrelated file", &notes, "(it has no journal): it is not overwritten"),
    ];
    for (what, target, expect) in cases {
        let res = sweep(&cfg, target, &[]);
        assert_eq!(res.status.code(), Some(2), "{what}: {}", stderr(&res));
        assert!(stderr(&res).contains(expect), "{what}: {}", stderr(&res));
    }
    // simulate and service outputs: the same rules
    for (cmd, target) in [("simulate", &cfg), ("simulate", &other), ("service", &cfg), ("simulate", &notes)] {
        let res = run(&[cmd, cfg.to_str().unwrap(), "--output", target.to_str().unwrap()]);
        assert_eq!(res.status.code(), Some(2), "{cmd} --output {}: {}", target.display(), stderr(&res));
    }
    assert_eq!(std::fs::read(&cfg).unwrap(), cfg_before, "the config is untouched");
    assert_eq!(std::fs::read(&record).unwrap(), record_before, "the record is untouched");
    assert_eq!(std::fs::read(&other_journal).unwrap(), journal_before, "the other journal is untouched");
    assert_eq!(std::fs::read_to_string(&notes).unwrap(), "my notes");
    // and a refused output leaves nothing behind (no lock file either)
    assert!(!d.join("notes.txt.lock").exists() && !d.join("other.h5.journal.lock").exists());
    // merging into a sweep's output (it has a journal) or over an input
    let res = merge(&[&other], &other, &[]);
    assert_eq!(res.status.code(), Some(2), "{}", stderr(&res));
    let res = merge(&[&other], &d.join("merged.h5"), &[]);
    ok(&res);
    let res = merge(&[&d.join("merged.h5")], &other, &[]);
    assert_eq!(res.status.code(), Some(2), "{}", stderr(&res));
    assert!(stderr(&res).contains("is the output of a sweep"), "{}", stderr(&res));
}

#[test]
fn the_main_job_can_be_run_twice() {
    let d = dir("twice");
    let cfg = config(&d, "c.toml", GRID, 1.0);
    let out = d.join("out.h5");
    let first = sweep(&cfg, &out, &[]);
    ok(&first);
    assert!(stdout(&first).contains("sweep complete: 5 of 5 jobs done"), "{}", stdout(&first));
    let second = sweep(&cfg, &out, &[]);
    ok(&second);
    assert!(stdout(&second).contains("sweep already complete: 5 of 5 jobs done"), "{}", stdout(&second));
}

/// A changed config and old shards: the script refuses to submit (its
/// `sweep --check` finds the shards' journals are of another sweep), and a
/// merge told the config refuses the stale shards, so no merged file with
/// old results is written and reported as fine. `--check` alone says what
/// a sweep would do and writes nothing.
#[test]
fn stale_shards_of_a_changed_config_are_refused() {
    let d = dir("stale");
    let cfg = config(&d, "job.toml", "[sweep]\nperiods = [0.4, 0.8, 1.6]\ndamping = [0.05]\n", 1.0);
    let script = |extra: &[&str]| {
        Command::new("bash")
            .arg(root().join("scripts/slurm_array.sh"))
            .args([cfg.to_str().unwrap(), "2", "--local"])
            .args(extra)
            .env("QUAKEJOINT", env!("CARGO_BIN_EXE_quakejoint"))
            .current_dir(&d)
            .output()
            .unwrap()
    };
    ok(&script(&[]));
    let merged = std::fs::read(d.join("job.h5")).unwrap();
    // the same sweep checked: complete
    let shard1 = d.join("shards/job-1-of-2.h5");
    let check =
        run(&["sweep", cfg.to_str().unwrap(), "--shard", "1/2", "--output", shard1.to_str().unwrap(), "--check"]);
    ok(&check);
    assert!(stdout(&check).contains("the sweep is complete"), "{}", stdout(&check));
    // change the grid: the script refuses before running anything
    std::fs::write(&cfg, std::fs::read_to_string(&cfg).unwrap().replace("[0.4, 0.8, 1.6]", "[0.4, 0.8, 1.6, 3.2]"))
        .unwrap();
    let res = script(&[]);
    assert_eq!(res.status.code(), Some(2), "{}", stderr(&res));
    assert!(stderr(&res).contains("holds the results of a different sweep"), "{}", stderr(&res));
    assert!(stderr(&res).contains("shard(s) 1,2 of 2 cannot run"), "{}", stderr(&res));
    assert_eq!(std::fs::read(d.join("job.h5")).unwrap(), merged, "the merged file is untouched");
    // a merge told the current config refuses the old shards
    let shards = [d.join("shards/job-1-of-2.h5"), d.join("shards/job-2-of-2.h5")];
    let res = run(&[
        "merge",
        shards[0].to_str().unwrap(),
        shards[1].to_str().unwrap(),
        "--config",
        cfg.to_str().unwrap(),
        "--output",
        d.join("new.h5").to_str().unwrap(),
    ]);
    assert_eq!(res.status.code(), Some(2), "{}", stderr(&res));
    assert!(stderr(&res).contains("computed from another version of the config"), "{}", stderr(&res));
    assert!(!d.join("new.h5").exists());

    // shard 2 computed for the changed config (its old files deleted), shard
    // 1 still of the old one: the script names only shard 1's files to
    // delete, never the finished shard 2's
    for f in ["shards/job-2-of-2.h5", "shards/job-2-of-2.h5.journal"] {
        std::fs::remove_file(d.join(f)).unwrap();
    }
    let res = script(&["--tasks", "2"]);
    assert_eq!(res.status.code(), Some(2), "the merge refuses the old shard 1: {}", stderr(&res));
    let finished = std::fs::read(d.join("shards/job-2-of-2.h5.journal")).unwrap();
    let res = script(&[]);
    assert_eq!(res.status.code(), Some(2), "{}", stderr(&res));
    let err = stderr(&res);
    assert!(err.contains("shard(s) 1 of 2 cannot run") && !err.contains('*'), "{err}");
    let rm = err.lines().map(str::trim).find(|l| l.starts_with("rm ")).unwrap_or_else(|| panic!("{err}"));
    assert_eq!(rm, "rm -f shards/job-1-of-2.h5 shards/job-1-of-2.h5.journal shards/job-1-of-2.h5.json");
    // done as told, the sweep goes on: shard 1 runs, shard 2 is kept
    ok(&Command::new("sh").args(["-c", rm]).current_dir(&d).output().unwrap());
    ok(&script(&[]));
    assert_eq!(std::fs::read(d.join("shards/job-2-of-2.h5.journal")).unwrap(), finished, "shard 2 was kept");
    let reference = d.join("reference.h5");
    ok(&sweep(&cfg, &reference, &[]));
    assert_identical(&read_sweep(&d.join("job.h5")).unwrap(), &read_sweep(&reference).unwrap(), "after the advice");
}

/// Small things a user ran into: `--threads 0`, an error in `--json` mode
/// (a JSON object on stdout as well), `compare` of a shard with the whole
/// (one line, not the same list for every field), a merge with failed
/// jobs (listed, with the way to retry them).
#[test]
fn errors_and_summaries_read_well() {
    let d = dir("read-well");
    let cfg = config(&d, "c.toml", GRID, 1.0);
    let res = run(&["sweep", cfg.to_str().unwrap(), "--threads", "0"]);
    assert_eq!(res.status.code(), Some(2));
    let res = run(&["simulate", d.join("missing.toml").to_str().unwrap(), "--json"]);
    assert_eq!(res.status.code(), Some(2));
    let v: serde_json::Value = serde_json::from_slice(&res.stdout).unwrap();
    assert_eq!(v["exit_code"], 2);
    assert!(v["error"].as_str().unwrap().contains("missing.toml"), "{v}");

    let whole = d.join("whole.h5");
    ok(&sweep(&cfg, &whole, &[]));
    let part = d.join("part.h5");
    ok(&sweep(&cfg, &part, &["--shard", "1/2"]));
    let cmp = run(&["compare", whole.to_str().unwrap(), part.to_str().unwrap()]);
    assert_eq!(cmp.status.code(), Some(1));
    let text = stdout(&cmp);
    let lines: Vec<&str> = text.lines().skip(1).collect();
    assert_eq!(lines.len(), 1, "{}", stdout(&cmp));
    assert!(lines[0].contains("results in the first file only"), "{}", stdout(&cmp));
    let missing = run(&["compare", whole.to_str().unwrap(), d.join("nope.h5").to_str().unwrap()]);
    assert_eq!(missing.status.code(), Some(2));
    assert!(stderr(&missing).contains("nope.h5: no such file"), "{}", stderr(&missing));

    // a merge whose shards hold failed jobs lists them
    let failing = d.join("failing.h5");
    let res = bin()
        .args(["sweep", cfg.to_str().unwrap(), "--output", failing.to_str().unwrap()])
        .env("QUAKEJOINT_TEST_FAIL_JOBS", "1,3")
        .output()
        .unwrap();
    assert_eq!(res.status.code(), Some(3));
    let merged = run(&["merge", failing.to_str().unwrap(), "--output", d.join("m.h5").to_str().unwrap()]);
    assert_eq!(merged.status.code(), Some(3));
    assert!(
        stdout(&merged).contains("2 jobs failed") && stdout(&merged).contains("--retry-failed"),
        "{}",
        stdout(&merged)
    );
    assert!(stdout(&merged).contains("job 1 (base /"), "{}", stdout(&merged));
}
