//! `simulation.max_wall_time` holds wherever a run can loop: between steps
//! and, every 1024 samples, while a step writes its output samples (one per
//! record time step, each a force balance over the whole joint). The
//! reference model at rest under a two-sample record (dt = 5 ms) followed by
//! 40,000 s of free vibration would write 8 million samples; with a limit of
//! 0.5 s the run must stop with the limit's error soon after 0.5 s. (The
//! case that used to overrun, a record with dt = 1e-9 s writing a billion
//! samples in one step, is refused as input now: dt must be at least
//! 1e-5 s.)

mod common;

use std::time::Instant;

use quakejoint_model::run::{simulate, RunOptions};
use quakejoint_model::ModelError;
use quakejoint_solver::SolverError;

#[test]
fn the_wall_clock_limit_holds_during_long_free_vibration() {
    let dir = std::env::temp_dir().join(format!("qj-wall-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("rest.txt"), "0 0\n0.005 0\n").unwrap();
    let text = "[record]\nfile = \"rest.txt\"\nunits = \"g\"\n\
                [simulation]\nextra_time = 40000.0\nmax_wall_time = 0.5\n";
    let config = quakejoint_model::Config::from_toml(text, "rest.toml").unwrap();
    let start = Instant::now();
    let err = simulate(&config, &dir, &RunOptions::default()).unwrap_err();
    let wall = start.elapsed().as_secs_f64();
    assert!(matches!(err, ModelError::Solver(SolverError::WallClockLimit { .. })), "{err}");
    assert!(wall < 3.0, "stopped after {wall} s for a limit of 0.5 s");
    std::fs::remove_dir_all(&dir).unwrap();
}
