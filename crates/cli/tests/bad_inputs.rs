//! The bad-input corpus `tests/bad_inputs/`: every config there (and every
//! record under `records/` that a config points to) is wrong in exactly one
//! way, and says how in its header (`# Bad input: ...`) and which fragments
//! the error must contain (`# expect: ...`, one per line).
//!
//! Each is run the way an engineer would run it: `quakejoint sweep` when it
//! has a `[sweep]` table, `quakejoint simulate` otherwise, both with
//! `--output` into an empty directory. Each must
//! - exit with code 2 (bad input), not 0, 1 or a signal;
//! - print an error that names the config file and contains every expected
//!   fragment (the field, the value, or `file:line` of a record);
//! - not panic;
//! - leave the output directory empty: no HDF5 file, no journal, no
//!   temporary file.

use std::path::{Path, PathBuf};
use std::process::Command;

fn corpus() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/bad_inputs")
}

/// The `# expect:` fragments of a corpus file.
fn expectations(text: &str) -> Vec<&str> {
    text.lines().filter_map(|l| l.strip_prefix("# expect: ")).map(str::trim).collect()
}

/// Runs one corpus config; returns what is wrong with the outcome, if anything.
fn check(config: &Path, scratch: &Path) -> Option<String> {
    let text = std::fs::read_to_string(config).unwrap();
    let name = config.file_name().unwrap().to_str().unwrap();
    let expect = expectations(&text);
    if expect.is_empty() {
        return Some("no `# expect:` line".into());
    }
    let out_dir = scratch.join(name.trim_end_matches(".toml"));
    std::fs::create_dir_all(&out_dir).unwrap();
    let command = if text.lines().any(|l| l.trim() == "[sweep]") { "sweep" } else { "simulate" };
    let res = Command::new(env!("CARGO_BIN_EXE_quakejoint"))
        .current_dir(corpus())
        .args([command, name, "--output", out_dir.join("out.h5").to_str().unwrap(), "--json"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&res.stderr);
    let mut problems = Vec::new();
    if res.status.code() != Some(2) {
        problems.push(format!("exit {:?} instead of 2", res.status.code()));
    }
    if stderr.contains("panicked") {
        problems.push("panicked".into());
    }
    if !stderr.contains(name) {
        problems.push("the message does not name the config file".into());
    }
    for e in expect {
        if !stderr.contains(e) {
            problems.push(format!("the message lacks `{e}`"));
        }
    }
    let left: Vec<String> =
        std::fs::read_dir(&out_dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    if !left.is_empty() {
        problems.push(format!("files left behind: {left:?}"));
    }
    (!problems.is_empty()).then(|| format!("{name} ({command}): {}\n  stderr: {stderr}", problems.join("; ")))
}

#[test]
fn every_bad_input_is_refused_with_a_message_naming_file_and_field() {
    let scratch = std::env::temp_dir().join(format!("quakejoint-bad-inputs-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&scratch);
    let mut configs: Vec<PathBuf> = std::fs::read_dir(corpus())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    configs.sort();
    let records = std::fs::read_dir(corpus().join("records")).unwrap().count();
    assert!(configs.len() + records >= 30, "the corpus has {} configs and {records} records", configs.len());
    // every bad record is used by some config
    for entry in std::fs::read_dir(corpus().join("records")).unwrap() {
        let file = format!("records/{}", entry.unwrap().file_name().to_string_lossy());
        assert!(
            configs.iter().any(|c| std::fs::read_to_string(c).unwrap().contains(&file)),
            "{file} is not used by any config"
        );
    }
    let failures: Vec<String> = configs.iter().filter_map(|c| check(c, &scratch)).collect();
    let _ = std::fs::remove_dir_all(&scratch);
    assert!(
        failures.is_empty(),
        "{} of {} bad inputs mishandled:\n{}",
        failures.len(),
        configs.len(),
        failures.join("\n")
    );
}
