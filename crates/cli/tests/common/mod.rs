//! Helpers shared by the command-line tests: the binary, scratch
//! directories, the small-model config and bit-for-bit comparison of sweep
//! outputs.
#![allow(dead_code)] // each test file uses a different subset

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use quakejoint_sweep::sweep_h5::SweepFile;

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The `quakejoint` binary, run from the repository root.
pub fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_quakejoint"));
    c.current_dir(root());
    c
}

/// Runs `quakejoint` with `args` to completion.
pub fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("runs")
}

/// A fresh, empty scratch directory for the test `name`.
pub fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("quakejoint-sweep-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes `dir/name`: the small model under the first `duration` s of
/// Corralitos 090 scaled to 0.15, followed by `sweep` (a `[sweep]` table).
/// At full scale the small joint's four sub-gaps of 40 mm close at periods
/// from about 0.6 s (runs flagged `collision`, exit code 4); at 0.15 they
/// stay open, at both ends of the beams, at every period and damping the
/// tests use, so that a run that works exits with 0. A sweep that lists its
/// own records (a `records = ` line) gets no `[record]` (a config may not
/// have both).
pub fn config(dir: &Path, name: &str, sweep: &str, duration: f64) -> PathBuf {
    let record = root().join("ground_motions/RSN753_LOMAP_CLS090-hor2.AT2");
    let record = if sweep.lines().any(|l| l.starts_with("records = ")) {
        String::new()
    } else {
        format!("[record]\nfile = {record:?}\nscale = 0.15\n")
    };
    let text = format!(
        "[joint]\ncenter_beams = 3\n\
         [[joint.support_beams]]\nkind = \"guide\"\ny = -7.2\n\
         [[joint.support_beams]]\nkind = \"joist\"\ny = -1.0\nangle_deg = 13.0\n\
         [[joint.support_beams]]\nkind = \"joist\"\ny = 5.0\nangle_deg = 17.0\n\
         {record}\
         [simulation]\nduration = {duration}\n\
         {sweep}\n"
    );
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Asserts a zero exit code, showing stderr otherwise.
pub fn ok(out: &Output) {
    assert!(out.status.success(), "exit {:?}: {}", out.status.code(), String::from_utf8_lossy(&out.stderr));
}

/// All numeric datasets equal bit for bit (machine-dependent wall times aside).
pub fn assert_identical(a: &SweepFile, b: &SweepFile, what: &str) {
    let diffs = quakejoint_sweep::compare::differences(a, b);
    assert!(diffs.is_empty(), "{what}: {diffs:?}");
}

/// stderr of a finished command, as text.
pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// stdout of a finished command, as text.
pub fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Whether `python3` can import `modules` (h5py, matplotlib: the plotting
/// scripts' and the HDF5 checks' needs). Without them a test skips what
/// needs them, saying what to install; `scripts/test.sh` (the README's test
/// command, which installs them) sets `QJ_REQUIRE_PYTHON=1`, and then a
/// missing module fails the test instead.
pub fn python_with(modules: &[&str]) -> bool {
    let found = Command::new("python3")
        .arg("-c")
        .arg(format!("import {}", modules.join(", ")))
        .output()
        .is_ok_and(|o| o.status.success());
    if !found {
        let what = format!(
            "python3 with {} (python3 -m pip install -r scripts/requirements.txt, or run scripts/test.sh, which \
             installs them)",
            modules.join(" and ")
        );
        assert!(std::env::var_os("QJ_REQUIRE_PYTHON").is_none(), "this test needs {what}");
        eprintln!("SKIPPED: the part of this test that needs {what}");
    }
    found
}

/// Waits until the journal `journal` of the running sweep `child` holds
/// `jobs` finished jobs; fails (naming `what`) if the sweep ends first or
/// nothing comes within two minutes.
pub fn wait_for_jobs(child: &mut std::process::Child, journal: &Path, jobs: usize, what: &str) {
    let start = std::time::Instant::now();
    while quakejoint_sweep::journal::read(journal).map(|(_, r)| r.len()).unwrap_or(0) < jobs {
        assert!(child.try_wait().unwrap().is_none(), "{what}: the sweep ended before the signal");
        assert!(start.elapsed() < std::time::Duration::from_secs(120), "{what}: no progress");
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
}
