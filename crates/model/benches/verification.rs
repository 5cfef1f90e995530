//! Times the reference problems of the verification manual
//! (`docs/verification.md`), each the fastest of three runs:
//!
//!     cargo bench -p quakejoint-model --bench verification

use std::path::PathBuf;
use std::time::Instant;

use quakejoint_model::verification::PROBLEMS;

fn main() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    println!("{:<26} {:>10}", "problem", "time [s]");
    for p in PROBLEMS {
        let fastest = (0..3)
            .map(|_| {
                let start = Instant::now();
                let outcome = (p.run)(&root);
                assert!(outcome.is_ok(), "{}: {outcome:?}", p.id);
                start.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min);
        println!("{:<26} {:>10.4}", p.id, fastest);
    }
}
