//! The proptest configuration of the fuzz tests of every crate, included
//! with `#[path]`: the number of cases per property comes from
//! `QUAKEJOINT_FUZZ_CASES` (a long run) or the file's default (the bounded
//! run of `cargo test`), and no failure files are written into the source
//! tree (proptest prints the shrunk input of a failing case).

use proptest::test_runner::Config;

/// The configuration with `default_cases` cases unless
/// `QUAKEJOINT_FUZZ_CASES` says otherwise.
pub fn config(default_cases: u32) -> Config {
    let cases = match std::env::var("QUAKEJOINT_FUZZ_CASES") {
        Ok(v) => v.trim().parse().unwrap_or_else(|_| panic!("QUAKEJOINT_FUZZ_CASES = {v:?} is not a whole number")),
        Err(_) => default_cases,
    };
    Config { cases, failure_persistence: None, ..Config::default() }
}
