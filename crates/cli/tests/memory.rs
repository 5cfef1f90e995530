//! Resource bounds: a sweep's memory does not grow with its number of jobs.
//!
//! A job's result is a fixed set of numbers; the writer keeps those for all
//! jobs (24 numbers and a status each: about 200 bytes per job) and the
//! time histories only of the periods listed in `sweep.histories`, which
//! the user bounds. Everything else (the model, the solver's matrices, the
//! record) is held per worker thread and dropped with the job. So 10 and
//! 200 jobs of the same model on the same threads must peak at the same
//! resident memory, to within allocator noise.
//!
//! The peak is the sweep's own report (`peak_memory_mb`, Linux `VmHWM`).
//! The estimate of `quakejoint plan` (which sizes cluster memory requests)
//! must bound it, for the small model and for the reference model.

mod common;

use common::{config, dir, ok, root, run};

fn peak_mb(periods: usize, d: &std::path::Path) -> f64 {
    let sweep = format!(
        "[sweep]\nperiods = {{ from = 1.0, to = 4.0, count = {periods}, spacing = \"log\" }}\ndamping = [0.05]\n\
         histories = [1.0]\n"
    );
    let cfg = config(d, &format!("n{periods}.toml"), &sweep, 4.0);
    let out = d.join(format!("n{periods}.h5"));
    let res = run(&["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap(), "--threads", "2", "--json"]);
    ok(&res);
    let v: serde_json::Value = serde_json::from_slice(&res.stdout).unwrap();
    assert_eq!(v["jobs"].as_u64(), Some(periods as u64));
    v["peak_memory_mb"].as_f64().expect("peak memory on Linux")
}

#[test]
fn peak_memory_does_not_grow_with_the_number_of_jobs() {
    if !cfg!(target_os = "linux") {
        return;
    }
    let d = dir("memory");
    let ten = peak_mb(10, &d);
    let two_hundred = peak_mb(200, &d);
    eprintln!("peak memory: 10 jobs {ten:.1} MB, 200 jobs {two_hundred:.1} MB");
    // 190 more jobs' results are 40 kB; allow 2 MB of allocator noise
    assert!(two_hundred < ten + 2.0, "10 jobs: {ten:.1} MB, 200 jobs: {two_hundred:.1} MB");
}

/// Measured peak and `quakejoint plan`'s estimate for a sweep config.
fn peak_and_estimate(cfg: &std::path::Path, out: &std::path::Path) -> (f64, f64) {
    let plan = run(&["plan", cfg.to_str().unwrap(), "--threads", "2", "--json"]);
    ok(&plan);
    let plan: serde_json::Value = serde_json::from_slice(&plan.stdout).unwrap();
    let res = run(&["sweep", cfg.to_str().unwrap(), "--output", out.to_str().unwrap(), "--threads", "2", "--json"]);
    ok(&res);
    let v: serde_json::Value = serde_json::from_slice(&res.stdout).unwrap();
    (v["peak_memory_mb"].as_f64().unwrap(), plan["shards"][0]["memory_mb"].as_f64().unwrap())
}

#[test]
fn the_plan_estimate_bounds_the_measured_peak_memory() {
    if !cfg!(target_os = "linux") {
        return;
    }
    let d = dir("memory-estimate");
    let small = config(&d, "small.toml", "[sweep]\nperiods = [0.5, 1.0, 2.0, 3.0]\nhistories = [1.0]\n", 20.0);
    let mut paper = std::fs::read_to_string(root().join("configs/paper.toml")).unwrap();
    paper = paper.replace("../ground_motions", root().join("ground_motions").to_str().unwrap());
    paper = paper.replace("[simulation]\n", "[simulation]\nduration = 3.0\n");
    paper = paper.replace("count = 50", "count = 4").replace("histories = [1.0]", "histories = [0.1]");
    let paper_cfg = d.join("paper.toml");
    std::fs::write(&paper_cfg, paper).unwrap();
    for (cfg, name) in [(small, "small"), (paper_cfg, "paper")] {
        let (peak, estimate) = peak_and_estimate(&cfg, &d.join(format!("{name}.h5")));
        eprintln!("{name}: peak {peak:.1} MB, estimate {estimate:.1} MB");
        assert!(peak <= estimate, "{name}: peak {peak:.1} MB above the estimate {estimate:.1} MB");
        assert!(estimate < 2.0 * peak, "{name}: the estimate {estimate:.1} MB is far above the peak {peak:.1} MB");
    }
}
