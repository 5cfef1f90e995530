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

use quakejoint_model::run::RunResult;
use quakejoint_model::verification::modal;
use quakejoint_model::Config;

fn fastest(base_dir: &Path, config: &Config) -> (f64, RunResult) {
    quakejoint_model::verification::fastest_run(base_dir, config, 3).expect("run")
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
