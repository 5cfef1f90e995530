//! The cost of a bridge given by its modes: the reference joint
//! (configs/paper.toml) at both ends of the three-span bridge of
//! `tests/data/three_span` (20 modes) against the reference run (one
//! reference joint on the single-DOF deck), both under the whole of
//! Corralitos 090, one thread, each the fastest of three:
//!
//!     cargo bench -p quakejoint-model --bench modal
//!
//! The goal (issue 28): at most 2.2 times the reference run.

use std::path::{Path, PathBuf};
use std::time::Instant;

use quakejoint_model::run::{load_records, simulate_records, RunOptions, RunResult};
use quakejoint_model::verification::modal;
use quakejoint_model::Config;

fn fastest(base_dir: &Path, config: &Config) -> (f64, RunResult) {
    let (x, _) = load_records(config, base_dir).expect("records");
    let mut best = (f64::INFINITY, RunResult::default());
    for _ in 0..3 {
        let start = Instant::now();
        let r = simulate_records(config, &x.record, None, &RunOptions::default()).expect("run");
        let t = start.elapsed().as_secs_f64();
        if t < best.0 {
            best = (t, r);
        }
    }
    best
}

fn main() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let paper = Config::from_file(&root.join("configs/paper.toml")).expect("configs/paper.toml");
    let two = modal::two_joints_on_three_span(&root, "paper.toml", 1.0, "").expect("three-span config");
    let (t1, r1) = fastest(&root.join("configs"), &paper);
    let (t2, r2) = fastest(&root, &two);
    println!("{:<58} {:>8} {:>7} {:>14}", "run", "time [s]", "steps", "factorisations");
    println!(
        "{:<58} {:>8.2} {:>7} {:>14}",
        "reference joint, single-DOF deck", t1, r1.stats.steps, r1.stats.factorizations
    );
    println!(
        "{:<58} {:>8.2} {:>7} {:>14}",
        "two reference joints, three-span bridge (20 modes)", t2, r2.stats.steps, r2.stats.factorizations
    );
    println!("ratio {:.2} (goal: at most 2.2)", t2 / t1);
}
