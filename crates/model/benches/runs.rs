//! Whole earthquake runs of the reference (paper) model, single thread
//! unless stated (results: docs/performance.md):
//!
//! - `full`: Corralitos 090, w0 = 6.3 rad/s, 5 % damping, the whole record,
//!   default tolerances: wall time, solver counters, peak memory of the
//!   process.
//! - `scaling`: the same run for Nc = 3, 9, 27, 81 center beams on the ten
//!   support beams of the reference joint: cost per step and per Newton
//!   iteration against the number of coordinates. The gap is kept at the
//!   reference 3.64 m (pitch `G0 / (Nc + 1)`): at the reference pitch, 81
//!   beams would need a 10.66 m gap in which the outer joist crosses the
//!   guide. At Nc = 81 (pitch 44 mm) the center beams are 30 mm wide (the
//!   width only enters the clear sub-gaps).
//! - `accuracy`: Sa at default tolerances against runs at 100 times tighter
//!   tolerances (rtol, atol, atol_rotation / 100, and the bearings held
//!   like every other body: `bearing_atol_factor` 1) for 10 log-spaced
//!   periods from 0.1 s to 5 s, on the rayon pool (`RAYON_NUM_THREADS`).
//!   `QUAKEJOINT_BENCH_TOL=1e-5` sets the tolerances compared (rtol, atol
//!   and atol_rotation alike) instead of the defaults (1e-6), and
//!   `QUAKEJOINT_BENCH_BEARING_FACTOR=3` the bearings' factor (default 2).
//!
//! - `contact`: the cost of the contacts between beams: the `full` run with
//!   them (56 contacts, none closing under Corralitos 090) against the same
//!   run without them, each 3 times (the fastest counts); and a pounding run
//!   (Pacoima Dam 164 x 2.5, T = 3.5 s: the joint closes about 80 times)
//!   with and without contact.
//!
//! `cargo bench -p quakejoint-model --bench runs [-- full|scaling|accuracy|contact]`
//! (all four without an argument). Each part also writes its table as JSON
//! to `target/bench-runs/<part>.json` (`scripts/plot_scaling.py` plots the
//! scaling).

use std::path::PathBuf;

use quakejoint_model::resources::peak_memory_mb;
use quakejoint_model::run::{load_records, simulate_records, RunOptions, RunResult};
use quakejoint_model::Config;
use rayon::prelude::*;
use serde_json::json;

fn configs() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../configs")
}

fn out_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/bench-runs")
}

fn paper() -> Config {
    Config::from_file(&configs().join("paper.toml")).expect("configs/paper.toml")
}

fn run(config: &Config, omega: Option<f64>) -> RunResult {
    let (x, y) = load_records(config, &configs()).expect("record");
    let mut config = config.clone();
    if let Some(w) = omega {
        (config.bridge.w0, config.bridge.period) = (Some(w), None);
    }
    simulate_records(&config, &x.record, y.as_ref().map(|y| &y.record), &RunOptions::default()).expect("run")
}

fn write_json(name: &str, value: &serde_json::Value) {
    let dir = out_dir();
    let text = serde_json::to_string_pretty(value).expect("plain data") + "\n";
    if std::fs::create_dir_all(&dir).is_ok() && std::fs::write(dir.join(name), text).is_ok() {
        println!("(written to {})", dir.join(name).display());
    }
}

fn full() {
    let config = paper();
    let r = run(&config, None);
    let s = &r.stats;
    println!("## full run: paper model, Corralitos 090, w0 = 6.3 rad/s, 5 % damping, {:.2} s", r.duration);
    println!("wall time            {:.2} s", r.wall_time_s);
    println!("steps                {}", s.steps);
    println!("rejected steps       {}", s.rejected);
    println!("failed Newton        {}", s.failed_attempts);
    println!("Newton iterations    {}", s.newton_iterations);
    println!("residual evaluations {}", s.residual_evaluations);
    println!("Jacobians            {}", s.jacobian_evaluations);
    println!("factorisations       {}", s.factorizations);
    println!("linear solves        {}", s.linear_solves);
    println!("Sa                   {:.6} m/s^2", r.sa);
    println!("friction energy      {:.1} J", r.friction_energy);
    println!("energy error         {:.1e}", r.energy_error);
    if let Some(mb) = peak_memory_mb() {
        println!("peak memory          {mb:.1} MB (whole process)");
    }
    write_json(
        "full.json",
        &json!({
            "wall_time_s": r.wall_time_s,
            "steps": s.steps,
            "rejected": s.rejected,
            "failed_attempts": s.failed_attempts,
            "newton_iterations": s.newton_iterations,
            "jacobians": s.jacobian_evaluations,
            "factorizations": s.factorizations,
            "sa": r.sa,
            "peak_memory_mb": peak_memory_mb(),
        }),
    );
}

fn scaling() {
    println!("## scaling: cost per step against the number of coordinates");
    println!("| Nc | bodies | coordinates | equations | steps | Newton it. | factorisations | wall [s] | per step [us] | per Newton it. [us] | per step / coordinate [ns] |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    let mut rows = Vec::new();
    for nc in [3usize, 9, 27, 81] {
        let mut config = paper();
        let gap = (config.joint.center_beams + 1) as f64 * config.joint.pitch;
        config.joint.center_beams = nc;
        config.joint.pitch = gap / (nc + 1) as f64;
        config.joint.center_beam.width = config.joint.center_beam.width.min(0.6 * config.joint.pitch);
        // cells of up to 0.91 m (Nc = 3): the capacity only flags, set to its
        // largest value
        config.joint.capacity.max_subgap = 1.0;
        let model =
            quakejoint_model::generator::build(&config, None, quakejoint_model::generator::Drive::None).expect("model");
        let (bodies, coords, eqs) = counts(&model.system);
        let r = run(&config, None);
        let s = &r.stats;
        let per_step = r.wall_time_s / s.steps as f64 * 1e6;
        let per_newton = r.wall_time_s / s.newton_iterations as f64 * 1e6;
        println!(
            "| {nc} | {bodies} | {coords} | {eqs} | {} | {} | {} | {:.2} | {per_step:.0} | {per_newton:.0} | {:.0} |",
            s.steps,
            s.newton_iterations,
            s.factorizations,
            r.wall_time_s,
            per_step / coords as f64 * 1e3
        );
        rows.push(json!({
            "nc": nc,
            "bodies": bodies,
            "coordinates": coords,
            "equations": eqs,
            "steps": s.steps,
            "newton_iterations": s.newton_iterations,
            "factorizations": s.factorizations,
            "wall_time_s": r.wall_time_s,
        }));
    }
    write_json("scaling.json", &rows.into());
}

/// Bodies, coordinates and constraint equations of a system.
fn counts(system: &quakejoint_solver::System) -> (usize, usize, usize) {
    let asm =
        quakejoint_solver::Assembly::new(system, &quakejoint_solver::AssemblyOptions::default()).expect("assembly");
    (system.bodies().len(), asm.coordinates(), asm.equations())
}

fn accuracy() {
    let mut base = paper();
    if let Ok(text) = std::env::var("QUAKEJOINT_BENCH_TOL") {
        let tol: f64 = text.parse().expect("QUAKEJOINT_BENCH_TOL must be a number");
        base.simulation.rtol = tol;
        base.simulation.atol = tol;
        base.simulation.atol_rotation = tol;
    }
    if let Ok(text) = std::env::var("QUAKEJOINT_BENCH_BEARING_FACTOR") {
        base.simulation.bearing_atol_factor = text.parse().expect("QUAKEJOINT_BENCH_BEARING_FACTOR must be a number");
    }
    let mut tight = base.clone();
    tight.simulation.rtol /= 100.0;
    tight.simulation.atol /= 100.0;
    tight.simulation.atol_rotation /= 100.0;
    tight.simulation.bearing_atol_factor = 1.0;
    let periods: Vec<f64> = (0..10).map(|i| 0.1 * 50f64.powf(i as f64 / 9.0)).collect();
    let jobs: Vec<(usize, bool)> = (0..10).flat_map(|i| [(i, false), (i, true)]).collect();
    let results: Vec<RunResult> = jobs
        .par_iter()
        .map(|&(i, is_tight)| {
            let omega = 2.0 * std::f64::consts::PI / periods[i];
            run(if is_tight { &tight } else { &base }, Some(omega))
        })
        .collect();
    println!(
        "## accuracy: tolerances {:e} (bearings x {}) against 100 times tighter ones (bearings x 1)",
        base.simulation.rtol, base.simulation.bearing_atol_factor
    );
    println!(
        "| T [s] | Sa default [m/s^2] | Sa tight [m/s^2] | Sa difference | friction energy difference | peak joint force difference | wall default [s] | wall tight [s] |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let mut worst = 0.0f64;
    let mut rows = Vec::new();
    for (i, t) in periods.iter().enumerate() {
        let (d, g) = (&results[2 * i], &results[2 * i + 1]);
        let rel = (d.sa - g.sa) / g.sa;
        worst = worst.max(rel.abs());
        let ef = (d.friction_energy - g.friction_energy) / g.friction_energy;
        let fj = (d.peak_joint_force - g.peak_joint_force) / g.peak_joint_force;
        println!(
            "| {t:.3} | {:.6} | {:.6} | {rel:+.1e} | {ef:+.1e} | {fj:+.1e} | {:.2} | {:.2} |",
            d.sa, g.sa, d.wall_time_s, g.wall_time_s
        );
        rows.push(json!({
            "period": t,
            "sa": d.sa,
            "sa_tight": g.sa,
            "friction_energy": d.friction_energy,
            "friction_energy_tight": g.friction_energy,
            "peak_joint_force": d.peak_joint_force,
            "peak_joint_force_tight": g.peak_joint_force,
            "wall_time_s": d.wall_time_s,
            "wall_time_tight_s": g.wall_time_s,
        }));
    }
    println!("largest |Sa difference| {worst:.1e} (target at the default tolerances: 1e-5)");
    write_json("accuracy.json", &rows.into());
}

fn main() {
    // cargo passes `--bench`; the parts to run are the other arguments
    let parts: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    let want = |p: &str| parts.is_empty() || parts.iter().any(|a| a == p);
    if want("full") {
        full();
    }
    if want("scaling") {
        scaling();
    }
    if want("accuracy") {
        accuracy();
    }
    if want("contact") {
        contact();
    }
}

fn contact() {
    println!("## contact: the reference run with and without the contacts between beams");
    let fastest = |config: &Config, omega: Option<f64>| {
        (0..3).map(|_| run(config, omega)).min_by(|a, b| a.wall_time_s.total_cmp(&b.wall_time_s)).expect("3 runs")
    };
    let mut rows = Vec::new();
    println!("| run | contacts | impacts | steps | Newton it. | factorisations | wall [s] (fastest of 3) |");
    println!("|---|---|---|---|---|---|---|");
    let mut pacoima = paper();
    let mut spec = quakejoint_motion::RecordSpec::new("../ground_motions/RSN77_SFERN_PUL164-hor1.AT2");
    spec.scale = 2.5;
    pacoima.record = Some(spec);
    let pounding = Some(2.0 * std::f64::consts::PI / 3.5);
    for (name, base, omega) in
        [("Corralitos 090, T = 0.997 s", paper(), None), ("Pacoima Dam x 2.5, T = 3.5 s", pacoima, pounding)]
    {
        for enabled in [true, false] {
            let mut config = base.clone();
            config.joint.contact.enabled = enabled;
            let r = fastest(&config, omega);
            let s = &r.stats;
            println!(
                "| {name} | {} | {} | {} | {} | {} | {:.2} |",
                if enabled { "on" } else { "off" },
                r.pounding.impacts,
                s.steps,
                s.newton_iterations,
                s.factorizations,
                r.wall_time_s
            );
            rows.push(json!({"run": name, "contact": enabled, "impacts": r.pounding.impacts, "steps": s.steps,
                "newton_iterations": s.newton_iterations, "wall_time_s": r.wall_time_s}));
        }
    }
    write_json("contact.json", &rows.into());
}
