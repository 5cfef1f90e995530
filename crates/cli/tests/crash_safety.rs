//! Crash safety: a sweep killed with SIGKILL at 20 moments, resumed after
//! each kill, ends with exactly the numbers of an uninterrupted run.
//!
//! The sweep: the small model under 20 s of Corralitos 090, 3 cases x
//! 2 dampings x 10 periods = 60 jobs, time histories at one period, and an
//! HDF5 checkpoint after every job (`checkpoint_seconds` tiny), so that
//! kills often land in a checkpoint. The kills:
//! - 6 in the middle of an HDF5 checkpoint (the temporary file half
//!   written, not yet renamed), and 6 in the middle of a journal append
//!   (half a frame written and synced): the sweep stops there by itself
//!   (`QUAKEJOINT_TEST_PAUSE`, `quakejoint_sweep::fault`) and is killed at
//!   that exact moment;
//! - 8 at pseudo-random times (fixed seed) after the start, between 1 % and
//!   8 % of the uninterrupted run's wall time.
//!
//! After every kill:
//! - (a) the journal reads (a torn last frame is ignored), holds each job at
//!   most once, and holds every job it held before with the same numbers:
//!   no finished job is lost or run twice;
//! - (c) the output name holds either nothing or a complete file: h5py
//!   opens every snapshot taken after a kill, and no job in it is missing
//!   from the journal (a checkpoint never runs ahead of the journal).
//!
//! At the end, (b): the resumed sweep's numeric datasets equal the
//! uninterrupted run's bit for bit, and the journal holds all 60 jobs once.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::time::{Duration, Instant};

use common::{assert_identical, bin, config, dir, ok, run};
use quakejoint_sweep::fault::marker;
use quakejoint_sweep::journal;
use quakejoint_sweep::results::{status, JobResult};
use quakejoint_sweep::runner::journal_path;
use quakejoint_sweep::sweep_h5::read_sweep;

const SWEEP: &str = "[sweep]\n\
    periods = { from = 0.2, to = 3.0, count = 10, spacing = \"log\" }\n\
    damping = [0.02, 0.05]\n\
    histories = [0.94]\n\
    checkpoint_seconds = 0.001\n\
    [[sweep.cases]]\nname = \"reference\"\n\
    [[sweep.cases]]\nname = \"mu 0.1\"\njoint.friction.mu = 0.1\n\
    [[sweep.cases]]\nname = \"v_eps 0.01\"\njoint.friction.v_eps = 0.01\n";
const JOBS: usize = 60;

/// How a run is interrupted.
#[derive(Debug, Clone, Copy)]
enum Kill {
    /// Paused in its n-th HDF5 checkpoint.
    Checkpoint(usize),
    /// Paused in its n-th journal append.
    Journal(usize),
    /// After this many milliseconds.
    After(u64),
}

/// A small deterministic generator (xorshift64).
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: u64) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0 % n
    }
}

/// The journal's results by job (empty if the journal does not exist yet or
/// was cut while its header was being written).
fn journalled(path: &Path) -> BTreeMap<u32, JobResult> {
    if !path.exists() {
        return BTreeMap::new();
    }
    let results = match journal::read(path) {
        Ok((_, results)) => results,
        // cut while the header was written: no job had finished
        Err(e) if e.to_string().contains("no header") => Vec::new(),
        Err(e) => panic!("the journal must read after a kill: {e}"),
    };
    let mut by_job = BTreeMap::new();
    for r in results {
        let job = r.job;
        assert!(by_job.insert(job, r).is_none(), "job {job} is in the journal twice");
    }
    by_job
}

/// Waits until `file` exists or the child exits; true if the file appeared.
fn wait_for(file: &Path, child: &mut Child) -> bool {
    let start = Instant::now();
    loop {
        if file.exists() {
            return true;
        }
        if child.try_wait().unwrap().is_some() {
            return false;
        }
        assert!(start.elapsed() < Duration::from_secs(120), "{} never appeared", file.display());
        std::thread::sleep(Duration::from_millis(2));
    }
}

#[test]
fn twenty_kills_lose_nothing_and_change_nothing() {
    let d = dir("crash");
    let cfg = config(&d, "c.toml", SWEEP, 20.0);
    let cfgs = cfg.to_str().unwrap().to_string();
    let reference = d.join("reference.h5");
    let start = Instant::now();
    ok(&run(&["sweep", &cfgs, "--output", reference.to_str().unwrap(), "--threads", "2", "--json"]));
    // random kills fall 1 % to 8 % of an uninterrupted run into each run, so
    // that 20 kills end before the sweep does on a faster machine too
    let whole_ms = start.elapsed().as_millis() as u64;

    let out = d.join("killed.h5");
    let jpath = journal_path(&out);
    let snapshots = d.join("snapshots");
    std::fs::create_dir_all(&snapshots).unwrap();
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut plan: Vec<Kill> = Vec::new();
    for k in 0..20 {
        plan.push(match k % 10 {
            0 | 3 | 6 => Kill::Checkpoint(1 + rng.below(3) as usize),
            1 | 4 | 7 => Kill::Journal(1 + rng.below(3) as usize),
            _ => Kill::After(whole_ms * (10 + rng.below(70)) / 1000),
        });
    }
    let mut before = BTreeMap::new();
    let mut report = Vec::new();
    for (k, kill) in plan.iter().enumerate() {
        let mut cmd: Command = bin();
        // the same command every time: a sweep continues its journal
        cmd.args(["sweep", &cfgs, "--output", out.to_str().unwrap(), "--threads", "2", "--json"]);
        let paused = match *kill {
            Kill::Checkpoint(n) => {
                cmd.env("QUAKEJOINT_TEST_PAUSE", format!("checkpoint:{n}"));
                Some(marker(&out))
            }
            Kill::Journal(n) => {
                cmd.env("QUAKEJOINT_TEST_PAUSE", format!("journal:{n}"));
                Some(marker(&jpath))
            }
            Kill::After(_) => None,
        };
        let mut child = cmd.stdout(std::process::Stdio::null()).spawn().unwrap();
        match (*kill, &paused) {
            (_, Some(m)) => assert!(wait_for(m, &mut child), "kill {k} ({kill:?}): the sweep ended before the pause"),
            (Kill::After(ms), None) => std::thread::sleep(Duration::from_millis(ms)),
            _ => unreachable!(),
        }
        assert!(child.try_wait().unwrap().is_none(), "kill {k} ({kill:?}): the sweep ended before the kill");
        child.kill().unwrap();
        child.wait().unwrap();
        if let Some(m) = &paused {
            std::fs::remove_file(m).unwrap();
        }

        // (a) nothing lost, nothing twice, nothing changed
        let now = journalled(&jpath);
        for (job, r) in &before {
            // (as text: a value not known, such as a CPU time, is NaN)
            assert_eq!(format!("{:?}", now.get(job)), format!("{:?}", Some(r)), "kill {k}: job {job} lost or changed");
        }
        assert!(now.len() < JOBS, "kill {k}: the sweep had finished");
        // (c) the output name holds a complete file, never ahead of the journal
        let mut in_file = 0;
        if out.exists() {
            let snap = snapshots.join(format!("{k:02}.h5"));
            std::fs::copy(&out, &snap).unwrap();
            let file = read_sweep(&snap).unwrap_or_else(|e| panic!("kill {k}: the output does not read: {e}"));
            for (j, &s) in file.results.status.iter().enumerate() {
                if s != status::NOT_RUN {
                    in_file += 1;
                    assert!(now.contains_key(&(j as u32)), "kill {k}: job {j} in the file but not in the journal");
                }
            }
        }
        report.push(format!("{kill:?}: {} journalled, {in_file} in the file", now.len()));
        before = now;
    }
    let snaps: Vec<PathBuf> = std::fs::read_dir(&snapshots).unwrap().map(|e| e.unwrap().path()).collect();
    assert!(snaps.len() >= 10, "only {} kills left an output to check", snaps.len());
    if !common::python_with(&["h5py"]) {
        return;
    }
    let opened = Command::new("python3")
        .arg("-c")
        .arg(
            "import sys, h5py\n\
             for p in sys.argv[1:]:\n\
             \x20   with h5py.File(p, 'r') as f:\n\
             \x20       f['spectrum/with_joint/sa'][()]; f['spectrum/with_joint/status'][()]\n\
             print(len(sys.argv) - 1)",
        )
        .args(&snaps)
        .output()
        .unwrap();
    assert!(opened.status.success(), "h5py: {}", String::from_utf8_lossy(&opened.stderr));

    // (b) the resumed sweep equals the uninterrupted one
    let last = run(&["sweep", &cfgs, "--output", out.to_str().unwrap(), "--threads", "2", "--resume", "--json"]);
    ok(&last);
    let v: serde_json::Value = serde_json::from_slice(&last.stdout).unwrap();
    assert_eq!(v["resumed"].as_u64().unwrap() as usize, before.len());
    assert_identical(&read_sweep(&out).unwrap(), &read_sweep(&reference).unwrap(), "killed 20 times vs uninterrupted");
    let all = journalled(&jpath);
    assert_eq!(all.len(), JOBS);
    assert!(all.keys().copied().eq(0..JOBS as u32));
    eprintln!(
        "crash safety: 20 kills, {} outputs opened by h5py, {} of {JOBS} jobs journalled before the last resume\n  {}",
        snaps.len(),
        before.len(),
        report.join("\n  ")
    );
}
