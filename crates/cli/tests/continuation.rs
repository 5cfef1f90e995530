//! What a sweep or a merge says to do next when it has not finished
//! everything, and that doing it works:
//!
//! - an interrupted `--retry-failed` continues with `--retry-failed` (the
//!   journal still holds the failures it had not retried yet); jobs it had
//!   retried that failed again run once more;
//! - a complete sweep with failed jobs never says just "complete": it says
//!   how many failed and prints the command that runs them again;
//! - in a job of `scripts/slurm_array.sh` (`QUAKEJOINT_RESUBMIT` and the
//!   SLURM variables set), the task's and the merge's advice is the
//!   resubmission `scripts/slurm_array.sh <config> <N> --tasks K`, never a
//!   `quakejoint sweep` to run on the login node.
//!
//! The interruptions are made certain, not timed: `QUAKEJOINT_TEST_HOLD`
//! keeps the last job of a sweep from starting until the sweep is stopped,
//! so a signal always lands in a running sweep, however fast the machine.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::{assert_identical, bin, config, dir, ok, root, stderr, stdout};
use quakejoint_sweep::sweep_h5::read_sweep;

const GRID: &str = "[sweep]\nperiods = [0.3, 0.6, 1.0, 2.0, 3.0]\ndamping = [0.05]\n";

/// `quakejoint sweep <cfg> --output <out> <extra>` with `env`, outside SLURM.
fn sweep_cmd(cfg: &Path, out: &Path, extra: &[&str], env: &[(&str, &str)]) -> Command {
    let mut c = bin();
    c.args(["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap()]).args(extra);
    for v in ["QUAKEJOINT_RESUBMIT", "SLURM_JOB_ID", "SLURM_ARRAY_TASK_ID", "QUAKEJOINT_TEST_HOLD"] {
        c.env_remove(v);
    }
    c.envs(env.iter().copied());
    c
}

/// Jobs in a journal, superseded entries included.
fn journalled(journal: &Path) -> usize {
    quakejoint_sweep::journal::read(journal).map(|(_, r)| r.len()).unwrap_or(0)
}

/// Waits until `ready()` (the child still running), or fails the test.
fn wait_until(what: &str, child: &mut Child, ready: impl Fn() -> bool) {
    let start = Instant::now();
    while !ready() {
        assert!(child.try_wait().unwrap().is_none(), "the sweep ended before {what}");
        assert!(start.elapsed() < Duration::from_secs(300), "never: {what}");
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Sends `signal` to the child and collects it.
fn signal(child: Child, signal: &str) -> Output {
    let kill = Command::new("kill").args([&format!("-{signal}"), &child.id().to_string()]).status().unwrap();
    assert!(kill.success());
    child.wait_with_output().unwrap()
}

/// The line after the one containing `marker`, trimmed.
fn line_after(text: &str, marker: &str) -> String {
    text.lines()
        .skip_while(|l| !l.contains(marker))
        .nth(1)
        .unwrap_or_else(|| panic!("no line after {marker:?} in:\n{text}"))
        .trim()
        .to_string()
}

#[test]
fn an_interrupted_retry_continues_with_retry_failed_and_failures_are_never_just_complete() {
    let d = dir("retry-interrupted");
    let cfg = config(&d, "c.toml", GRID, 1.0);
    let reference = d.join("reference.h5");
    ok(&sweep_cmd(&cfg, &reference, &[], &[]).output().unwrap());
    let out = d.join("out.h5");
    let journal = d.join("out.h5.journal");
    let fail = [("QUAKEJOINT_TEST_FAIL_JOBS", "0,1,2,3")];
    let first = sweep_cmd(&cfg, &out, &[], &fail).output().unwrap();
    assert_eq!(first.status.code(), Some(3), "{}", stderr(&first));

    // run again: complete, but the headline says how many failed, and the
    // exact command that retries them is printed
    let again = sweep_cmd(&cfg, &out, &[], &[]).output().unwrap();
    assert_eq!(again.status.code(), Some(3), "{}", stderr(&again));
    let text = stdout(&again);
    let headline = text.lines().next().unwrap();
    assert!(headline.starts_with("sweep already complete, but 4 of its jobs failed: 5 of 5 jobs done"), "{text}");
    let retry = line_after(&text, "run the 4 failed jobs again");
    assert_eq!(retry, format!("{} sweep {} --output {} --retry-failed", bin_path(), cfg.display(), out.display()));
    let check = sweep_cmd(&cfg, &out, &["--check"], &[]).output().unwrap();
    ok(&check);
    assert!(
        stdout(&check).contains("is complete, but 4 of its jobs failed, which `--retry-failed` runs again"),
        "{}",
        stdout(&check)
    );
    let check = sweep_cmd(&cfg, &out, &["--check", "--retry-failed"], &[]).output().unwrap();
    assert!(stdout(&check).contains("the sweep would run its 4 failed jobs again"), "{}", stdout(&check));

    // a retry that is interrupted after it has retried three of the four
    // (which fail again), the fourth held back
    let mut child = sweep_cmd(
        &cfg,
        &out,
        &["--retry-failed", "--threads", "1", "--json"],
        &[fail[0], ("QUAKEJOINT_TEST_HOLD", "all")],
    )
    .stdout(Stdio::piped())
    .stderr(Stdio::piped())
    .spawn()
    .unwrap();
    wait_until("three jobs were retried", &mut child, || journalled(&journal) >= 5 + 3);
    let res = signal(child, "TERM");
    assert_eq!(res.status.code(), Some(143), "{}", stderr(&res));
    let v: serde_json::Value = serde_json::from_slice(&res.stdout).unwrap();
    assert_eq!((v["interrupted"].as_bool(), v["not_run"].as_u64()), (Some(true), Some(1)), "{v}");
    let command = line_after(&stderr(&res), "continue with");
    assert_eq!(v["continue_command"].as_str(), Some(command.as_str()));
    assert!(command.contains("--retry-failed") && command.contains("--resume"), "{}", stderr(&res));
    // the printed command, run by a shell: the held job and the three that
    // failed again all run (the journal cannot tell the retried from the
    // not yet retried), and the result is the unfailing sweep's
    let resumed = Command::new("sh").arg("-c").arg(&command).current_dir(root()).output().unwrap();
    ok(&resumed);
    let v: serde_json::Value = serde_json::from_slice(&resumed.stdout).unwrap();
    assert_eq!((v["retried"].as_u64(), v["ran"].as_u64(), v["failed"].as_u64()), (Some(4), Some(4), Some(0)), "{v}");
    assert_identical(&read_sweep(&out).unwrap(), &read_sweep(&reference).unwrap(), "retried after an interruption");
}

/// The binary as the tests call it.
fn bin_path() -> String {
    env!("CARGO_BIN_EXE_quakejoint").to_string()
}

/// `quakejoint merge` of `files` into `out` with `env` (and `--config`).
fn merge(files: &[&PathBuf], cfg: &Path, out: &Path, env: &[(&str, &str)]) -> Output {
    let mut c = bin();
    c.arg("merge").args(files.iter().map(|f| f.to_str().unwrap()));
    c.args(["--config", cfg.to_str().unwrap(), "--output", out.to_str().unwrap()]);
    c.envs(env.iter().copied()).output().unwrap()
}

#[test]
fn in_a_job_of_the_slurm_script_the_advice_is_to_resubmit_shards() {
    let d = dir("slurm-advice");
    let cfg = config(&d, "job.toml", GRID, 1.0);
    let (s1, s2) = (d.join("job-1-of-2.h5"), d.join("job-2-of-2.h5"));
    let resubmit = "scripts/slurm_array.sh job.toml 2";
    let slurm = |task: &'static str| {
        [("QUAKEJOINT_RESUBMIT", resubmit), ("SLURM_JOB_ID", "4242"), ("SLURM_ARRAY_TASK_ID", task)]
    };

    // task 1: every job of its shard fails; its log says how to retry them
    let env = [slurm("1").as_slice(), &[("QUAKEJOINT_TEST_FAIL_JOBS", "0,1,2,3,4")]].concat();
    let task1 = sweep_cmd(&cfg, &s1, &["--shard", "1/2", "--progress", "lines"], &env).output().unwrap();
    assert_eq!(task1.status.code(), Some(3), "{}", stderr(&task1));
    assert!(stdout(&task1).contains("of its jobs failed"), "{}", stdout(&task1));
    let retry = line_after(&stdout(&task1), "failed jobs again");
    assert_eq!(retry, format!("{resubmit} --tasks 1 --retry-failed"), "{}", stdout(&task1));

    // task 2: stopped by SIGTERM (scancel, or the time limit) while it runs
    let log = d.join("task2.log");
    let mut child = sweep_cmd(&cfg, &s2, &["--shard", "2/2", "--progress", "lines"], &slurm("2"))
        .env("QUAKEJOINT_TEST_HOLD", "2/2")
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .unwrap();
    wait_until("the task started", &mut child, || std::fs::read_to_string(&log).unwrap().contains("started:"));
    let res = signal(child, "TERM");
    assert_eq!(res.status.code(), Some(143));
    let text = std::fs::read_to_string(&log).unwrap();
    assert_eq!(line_after(&text, "continue with"), format!("{resubmit} --tasks 2"), "{text}");
    assert!(!text.contains("quakejoint sweep") && !text.contains("--resume"), "{text}");

    // the merge job: names shard 2 and resubmits it, and nothing else
    let merged = d.join("job.h5");
    let res = merge(&[&s1, &s2], &cfg, &merged, &slurm("1")[..2]);
    assert_eq!(res.status.code(), Some(2), "{}", stderr(&res));
    let err = stderr(&res);
    assert!(err.contains("job-2-of-2.h5 (shard 2/2) has"), "{err}");
    assert_eq!(line_after(&err, "resubmit the shards that are not done"), format!("{resubmit} --tasks 2"), "{err}");
    assert!(!err.contains("quakejoint sweep"), "{err}");
    assert!(!merged.exists());
    // a shard whose file is missing (its task never started): the same
    let gone = d.join("gone");
    std::fs::create_dir_all(&gone).unwrap();
    let missing = gone.join("job-2-of-2.h5");
    let res = merge(&[&s1, &missing], &cfg, &merged, &slurm("1")[..2]);
    assert_eq!(res.status.code(), Some(2), "{}", stderr(&res));
    assert_eq!(line_after(&stderr(&res), "resubmit the shards"), format!("{resubmit} --tasks 2"), "{}", stderr(&res));

    // shard 2 finished: the merge writes the failed jobs of shard 1 and
    // says how to retry them, by resubmission
    ok(&sweep_cmd(&cfg, &s2, &["--shard", "2/2"], &[]).output().unwrap());
    let res = merge(&[&s1, &s2], &cfg, &merged, &slurm("1")[..2]);
    assert_eq!(res.status.code(), Some(3), "{}", stderr(&res));
    assert_eq!(line_after(&stdout(&res), "run them again"), format!("{resubmit} --tasks 1 --retry-failed"));
    // and a merge without failed jobs advises nothing
    let res = bin()
        .args(["merge", s2.to_str().unwrap(), "--allow-partial", "--output", d.join("part.h5").to_str().unwrap()])
        .envs(slurm("1"))
        .output()
        .unwrap();
    ok(&res);
    assert!(!stdout(&res).contains("run them again") && !stdout(&res).contains("slurm_array"), "{}", stdout(&res));

    // in a SLURM job of one's own (no resubmission command), the command
    // is the job's, to run as a job again
    let own = [("SLURM_JOB_ID", "4243")];
    let res = sweep_cmd(&cfg, &s1, &["--shard", "1/2"], &own).output().unwrap();
    assert_eq!(res.status.code(), Some(3), "{}", stderr(&res));
    assert!(stdout(&res).contains("as a SLURM job like this one, not on the login node"), "{}", stdout(&res));
}
