//! Runs reference problems of the verification manual (`docs/verification.md`)
//! and prints each outcome against its band:
//!
//!     cargo run --release -p quakejoint-model --example verify [-- ID ...]
//!
//! Without an id, every problem.

use std::path::PathBuf;
use std::process::ExitCode;

use quakejoint_model::verification::{problem, PROBLEMS};

fn main() -> ExitCode {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let ids: Vec<String> = std::env::args().skip(1).collect();
    let chosen: Vec<_> = if ids.is_empty() {
        PROBLEMS.iter().collect()
    } else {
        match ids.iter().map(|id| problem(id).ok_or(id)).collect::<Result<Vec<_>, _>>() {
            Ok(p) => p,
            Err(id) => {
                let known: Vec<&str> = PROBLEMS.iter().map(|p| p.id).collect();
                eprintln!("no problem `{id}`; the problems are {}", known.join(", "));
                return ExitCode::from(2);
            }
        }
    };
    let mut failed = 0;
    for p in chosen {
        match (p.run)(&root) {
            Ok(o) => {
                let error = p.band.error(o.computed, o.reference);
                let pass = error <= p.band.limit();
                failed += usize::from(!pass);
                println!(
                    "{}: {} computed {:e}, reference {:e}, error {error:.2e} ({}): {}",
                    p.id,
                    p.quantity,
                    o.computed,
                    o.reference,
                    p.band.describe(),
                    if pass { "pass" } else { "FAIL" }
                );
            }
            Err(e) => {
                failed += 1;
                println!("{}: failed to run: {e}", p.id);
            }
        }
    }
    if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
