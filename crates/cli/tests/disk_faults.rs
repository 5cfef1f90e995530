//! Disk faults: a write that fails part way through a sweep stops it
//! cleanly, and the same command again on a healthy disk finishes the work.
//!
//! The fault is real, not mocked: the sweep runs under a file-size limit
//! (`ulimit -f`, with SIGXFSZ ignored so that the write returns EFBIG, as
//! on a full disk or an exceeded quota). Two placements, each sized from an
//! uninterrupted run's files:
//! - the HDF5 checkpoint fails: a checkpoint after every job and no time
//!   histories, so the journal stays small while the output holds the
//!   record and every result array from the first checkpoint on; the limit
//!   lies between the complete journal's size and the output's;
//! - the journal append fails: no checkpoint before the end, time histories
//!   at one period (the journal grows by one per history job), the limit
//!   half the complete journal.
//!
//! Each must exit with code 1, name the file and the cause, say that the
//! same command continues, leave the output name either empty or holding a complete
//! file, and leave a journal that reads; resuming without the limit must
//! end with the numbers of an uninterrupted run. (An unwritable output
//! directory is refused before any job runs: `sweep.rs`.)

mod common;

use std::process::Command;

use common::{assert_identical, config, dir, ok, run};
use quakejoint_sweep::journal;
use quakejoint_sweep::runner::journal_path;
use quakejoint_sweep::sweep_h5::read_sweep;

/// 2 cases x 2 dampings x 6 periods, `histories` (a TOML list of periods);
/// `checkpoint` seconds between HDF5 checkpoints.
fn sweep_table(checkpoint: f64, histories: &str) -> String {
    format!(
        "[sweep]\n\
         periods = {{ from = 0.2, to = 3.0, count = 6, spacing = \"log\" }}\n\
         damping = [0.02, 0.05]\n\
         histories = {histories}\n\
         checkpoint_seconds = {checkpoint}\n\
         [[sweep.cases]]\nname = \"reference\"\n\
         [[sweep.cases]]\nname = \"mu 0.1\"\njoint.friction.mu = 0.1\n"
    )
}

#[test]
fn a_failing_write_stops_the_sweep_and_resume_finishes_it() {
    let d = dir("disk");
    let kib = |p: &std::path::Path| std::fs::metadata(p).unwrap().len() / 1024;
    for (name, checkpoint, histories, failing) in [
        ("checkpoint", 0.001, "[]", "checkpoint.h5: writing failed: File too large (os error 27)"),
        ("journal", 3600.0, "[1.02]", "cannot append to the journal"),
    ] {
        let reference = d.join(format!("{name}-reference.h5"));
        let cfg = config(&d, &format!("{name}-reference.toml"), &sweep_table(60.0, histories), 20.0);
        ok(&run(&["sweep", cfg.to_str().unwrap(), "--output", reference.to_str().unwrap(), "--json"]));
        let (output_kib, journal_kib) = (kib(&reference), kib(&journal_path(&reference)));
        let limit = if name == "checkpoint" {
            assert!(output_kib > journal_kib + 20, "output {output_kib} KiB, journal {journal_kib} KiB");
            (output_kib + journal_kib) / 2
        } else {
            journal_kib / 2
        };
        let reference = read_sweep(&reference).unwrap();
        let cfg = config(&d, &format!("{name}.toml"), &sweep_table(checkpoint, histories), 20.0);
        let out = d.join(format!("{name}.h5"));
        let args = format!("sweep {} --output {} --threads 2 --json", cfg.display(), out.display());
        let limited = Command::new("bash")
            .arg("-c")
            .arg(format!("trap '' XFSZ; ulimit -f {limit}; exec {} {args}", env!("CARGO_BIN_EXE_quakejoint")))
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&limited.stderr);
        assert_eq!(limited.status.code(), Some(1), "{name}: {stderr}");
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
        // the cause in the system's words, not the library's internals
        assert!(!stderr.contains("bytes actually written") && !stderr.contains("buf = 0x"), "{name}: {stderr}");
        eprintln!("{name} fault: {stderr}");
        for fragment in [failing, "File too large", "the sweep stopped", "run the same command again"] {
            assert!(stderr.contains(fragment), "{name}: `{fragment}` missing from: {stderr}");
        }
        if out.exists() {
            read_sweep(&out).unwrap_or_else(|e| panic!("{name}: the output name holds a broken file: {e}"));
        }
        let (_, done) = journal::read(&journal_path(&out)).unwrap();
        assert!(!done.is_empty() && done.len() < 24, "{name}: {} jobs journalled", done.len());

        let resumed = run(&[
            "sweep",
            cfg.to_str().unwrap(),
            "--output",
            out.to_str().unwrap(),
            "--threads",
            "2",
            "--resume",
            "--json",
        ]);
        ok(&resumed);
        let v: serde_json::Value = serde_json::from_slice(&resumed.stdout).unwrap();
        assert_eq!(v["resumed"].as_u64().unwrap() as usize, done.len(), "{name}");
        assert_identical(&read_sweep(&out).unwrap(), &reference, &format!("{name} fault, resumed"));
    }
}
