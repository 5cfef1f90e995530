//! Fault-injection points for the crash-safety tests.
//!
//! With `QUAKEJOINT_TEST_PAUSE=<point>:<n>` in the environment (`point` one
//! of `journal`, `checkpoint` or `locked`), the process stops in the middle
//! of its `n`-th journal append (half of the frame written and synced), of
//! its `n`-th HDF5 checkpoint (the temporary file half written, not yet
//! renamed), or right after taking the output's lock (before anything else
//! of the output exists), creates the file `<file>.paused` beside the file
//! it is writing (the journal, or the HDF5 output for the other two) and
//! sleeps until it is killed. The
//! tests (`crates/cli/tests/crash_safety.rs`) then send SIGKILL at exactly
//! that moment. Without the variable the points cost one relaxed atomic load.
//!
//! With `QUAKEJOINT_TEST_HOLD=all` (any sweep) or `=K/N[,K/N..]` (only the
//! sweeps of those shards), the last job of a sweep's to-do list does not
//! start until the sweep is stopped (SIGINT, SIGTERM) or the file
//! `<output>.release` appears: a sweep that is still running when a test
//! signals, kills or watches it, however fast the machine
//! (`crates/cli/tests/batch.rs`, `tests/slurm/test_array.sh`).
//!
//! With `QUAKEJOINT_TEST_HOLD_START=<file>`, a sweep holds after installing
//! its signal handlers and before reading its config ([`hold_start`]).
//!
//! The hooks are compiled only with the feature `fault-injection`, which
//! the command's tests turn on (a dev-dependency of `crates/cli`): a
//! program built for use (`cargo build`, `cargo install`, the Python
//! package) has none, and the variables do nothing there. The file names
//! ([`marker`], [`release`]) are always there, for the tests.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
#[cfg(feature = "fault-injection")]
use std::sync::atomic::{AtomicUsize, Ordering};
#[cfg(feature = "fault-injection")]
use std::sync::OnceLock;
#[cfg(feature = "fault-injection")]
use std::time::Duration;

/// Where a pause can be requested.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Point {
    /// Half-way through a journal append.
    Journal,
    /// Half-way through an HDF5 checkpoint.
    Checkpoint,
    /// Just after the output's lock is taken.
    Locked,
}

/// The requested pause, parsed once.
#[cfg(feature = "fault-injection")]
fn requested() -> Option<(Point, usize)> {
    static REQUEST: OnceLock<Option<(Point, usize)>> = OnceLock::new();
    *REQUEST.get_or_init(|| {
        let text = std::env::var("QUAKEJOINT_TEST_PAUSE").ok()?;
        let (point, n) = text.split_once(':')?;
        let point = match point {
            "journal" => Point::Journal,
            "checkpoint" => Point::Checkpoint,
            "locked" => Point::Locked,
            _ => return None,
        };
        Some((point, n.parse().ok()?))
    })
}

/// `<file>.paused`: created when the process has stopped while writing `file`.
pub fn marker(file: &Path) -> PathBuf {
    let mut s = file.as_os_str().to_owned();
    s.push(".paused");
    PathBuf::from(s)
}

/// Counts the passes through `point`; at the requested one, creates the
/// marker beside `file` and sleeps for ever.
#[cfg(feature = "fault-injection")]
pub(crate) fn point(point: Point, file: &Path) {
    static COUNTS: [AtomicUsize; 3] = [AtomicUsize::new(0), AtomicUsize::new(0), AtomicUsize::new(0)];
    let Some((wanted, n)) = requested() else { return };
    let count = COUNTS[point as usize].fetch_add(1, Ordering::Relaxed) + 1;
    if wanted == point && count == n {
        let _ = std::fs::write(marker(file), b"paused");
        loop {
            std::thread::sleep(Duration::from_secs(3600));
        }
    }
}

/// Whether job `index` is to fail (`QUAKEJOINT_TEST_FAIL_JOBS=3,7`): the
/// tests' way to make a job fail as the solver can (a typed error, status
/// failed) without hunting for physics that breaks it.
#[cfg(feature = "fault-injection")]
pub(crate) fn job_fails(index: usize) -> bool {
    static JOBS: OnceLock<Vec<usize>> = OnceLock::new();
    JOBS.get_or_init(|| {
        std::env::var("QUAKEJOINT_TEST_FAIL_JOBS")
            .map(|v| v.split(',').filter_map(|j| j.trim().parse().ok()).collect())
            .unwrap_or_default()
    })
    .contains(&index)
}

/// `<output>.release`: lets a held job start (`QUAKEJOINT_TEST_HOLD`).
pub fn release(output: &Path) -> PathBuf {
    let mut s = output.as_os_str().to_owned();
    s.push(".release");
    PathBuf::from(s)
}

/// Holds the last job of a sweep of `shard` into `output` if
/// `QUAKEJOINT_TEST_HOLD` asks for it: waits until `stop` is set (then
/// returns true: the job is abandoned, as a running one would be) or the
/// release file appears (false: the job runs). Without the variable it
/// returns false at once.
#[cfg(feature = "fault-injection")]
pub(crate) fn hold(shard: Option<(usize, usize)>, output: &Path, stop: &AtomicBool) -> bool {
    let Ok(text) = std::env::var("QUAKEJOINT_TEST_HOLD") else { return false };
    let held =
        text.split(',').map(str::trim).any(|s| s == "all" || shard.is_some_and(|(k, n)| s == format!("{k}/{n}")));
    if !held {
        return false;
    }
    let release = release(output);
    while !stop.load(Ordering::Relaxed) {
        if release.exists() {
            return false;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    true
}

/// With `QUAKEJOINT_TEST_HOLD_START=<file>`: creates `<file>` and waits
/// until `stop` is set (at most a minute), where a sweep would read its
/// config: a signal that lands there however fast the machine
/// (`crates/cli/tests/edges.rs`). Without the variable it returns at once.
#[cfg(feature = "fault-injection")]
pub fn hold_start(stop: &AtomicBool) {
    let Some(file) = std::env::var_os("QUAKEJOINT_TEST_HOLD_START") else { return };
    let _ = std::fs::write(&file, b"");
    let start = std::time::Instant::now();
    while !stop.load(Ordering::Relaxed) && start.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Without the feature: nothing held at the start.
#[cfg(not(feature = "fault-injection"))]
#[inline(always)]
pub fn hold_start(_stop: &AtomicBool) {}

/// Without the feature: no pause.
#[cfg(not(feature = "fault-injection"))]
#[inline(always)]
pub(crate) fn point(_point: Point, _file: &Path) {}

/// Without the feature: no job fails on purpose.
#[cfg(not(feature = "fault-injection"))]
#[inline(always)]
pub(crate) fn job_fails(_index: usize) -> bool {
    false
}

/// Without the feature: no job is held.
#[cfg(not(feature = "fault-injection"))]
#[inline(always)]
pub(crate) fn hold(_shard: Option<(usize, usize)>, _output: &Path, _stop: &AtomicBool) -> bool {
    false
}
