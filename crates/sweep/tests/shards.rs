//! Shard balancing by the measured cost model (docs/sweep.md, "Cost of a
//! job"): short bridge periods cost less, not more (measured on the
//! reference model: T = 0.1 s takes about 60 % of the time of T = 1 s), and
//! the longest-processing-time deal of the reference sweep's 50 jobs to 16
//! shards keeps every shard's estimated cost within 25 % of the others
//! (measured with the jobs' real wall times: 14.3 to 17.6 s, docs/sweep.md).

use std::path::PathBuf;

use quakejoint_sweep::plan::cost_seconds;
use quakejoint_sweep::Plan;

fn paper() -> Plan {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let path = root.join("configs/paper.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    Plan::new(&text, "paper.toml", &root.join("configs")).unwrap()
}

#[test]
fn short_periods_cost_less_and_cost_grows_with_bodies_and_samples() {
    // measured on the reference model (307 bodies, 7,999 samples; the jobs'
    // cpu_time_s in a sweep of configs/paper.toml, docs/sweep.md): 2.2 s at
    // T = 0.1 s, 3.1 to 4.4 s from 0.2 s to 5 s, 3.7 s at 1.1 s
    let at = |t: f64| cost_seconds(307, 7999.0, t);
    assert!(at(0.1) / at(1.0) > 0.5 && at(0.1) / at(1.0) < 0.7, "{}", at(0.1) / at(1.0));
    assert!((at(1.0) - 3.6).abs() < 0.4, "{}", at(1.0));
    assert!(cost_seconds(15, 7999.0, 1.0) < 0.1 * at(1.0));
    assert!((cost_seconds(307, 2.0 * 7999.0, 1.0) / at(1.0) - 2.0).abs() < 1e-12);
}

#[test]
fn sixteen_shards_of_the_reference_sweep_are_balanced() {
    let plan = paper();
    let loads: Vec<f64> = (1..=16).map(|k| plan.estimate(&plan.shard(k, 16), 1).seconds).collect();
    let (lo, hi) = loads.iter().fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
    assert!(hi / lo <= 1.25, "shard costs from {lo:.1} to {hi:.1} s");
    // every job in exactly one shard
    let mut all: Vec<usize> = (1..=16).flat_map(|k| plan.shard(k, 16)).collect();
    all.sort_unstable();
    assert_eq!(all, (0..50).collect::<Vec<_>>());
}
