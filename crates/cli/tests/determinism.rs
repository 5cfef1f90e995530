//! Determinism of sweeps: the same config gives bit-identical numbers
//! whatever the thread count and however the jobs are split into shards.
//!
//! The grid has 2 cases (the reference joint and one with mu = 0.1),
//! 2 records (Corralitos 090 and 000), 2 damping ratios and 6 periods:
//! 48 jobs, with time histories at one period. It runs on 1, 2 and 4
//! threads, and as 2 and as 5 shards merged; every numeric dataset (the
//! wall times aside) must equal the 1-thread run bit for bit. This holds
//! because each job runs single-threaded with a fixed operation order, and
//! the writer places each result by its job index, not by arrival order.

mod common;

use std::path::Path;

use common::{assert_identical, config, dir, ok, root, run};
use quakejoint_sweep::results::status;
use quakejoint_sweep::sweep_h5::read_sweep;

/// The `[sweep]` table of the grid.
fn grid() -> String {
    let record = |name: &str| root().join("ground_motions").join(name);
    format!(
        "[sweep]\n\
         periods = {{ from = 0.25, to = 2.5, count = 6, spacing = \"log\" }}\n\
         damping = [0.02, 0.05]\n\
         histories = [0.63]\n\
         records = [{{ file = {:?}, scale = 0.15 }}, {{ file = {:?}, scale = 0.15 }}]\n\
         [[sweep.cases]]\nname = \"reference\"\n\
         [[sweep.cases]]\nname = \"mu 0.1\"\njoint.friction.mu = 0.1\n",
        record("RSN753_LOMAP_CLS090-hor2.AT2"),
        record("RSN753_LOMAP_CLS000-hor1.AT2"),
    )
}

#[test]
fn thread_counts_and_shardings_give_identical_numbers() {
    let d = dir("determinism");
    let cfg = config(&d, "grid.toml", &grid(), 4.0);
    let cfgs = cfg.to_str().unwrap();
    let path = |n: &str| d.join(n).to_str().unwrap().to_string();
    let sweep = |out: &str, extra: &[&str]| {
        let mut args = vec!["sweep", cfgs, "--output", out, "--json"];
        args.extend_from_slice(extra);
        ok(&run(&args));
    };

    sweep(&path("t1.h5"), &["--threads", "1"]);
    let one = read_sweep(Path::new(&path("t1.h5"))).unwrap();
    assert_eq!(one.results.status.len(), 48);
    assert!(one.results.status.iter().all(|&s| s == status::OK), "every job runs");
    assert_eq!(one.records.len(), 2);
    assert_eq!(one.results.histories.len(), 8, "histories of 2 cases x 2 records x 2 dampings");
    for threads in ["2", "4"] {
        let out = path(&format!("t{threads}.h5"));
        sweep(&out, &["--threads", threads]);
        assert_identical(&read_sweep(Path::new(&out)).unwrap(), &one, &format!("{threads} threads vs 1"));
    }

    for n in [2, 5] {
        let mut shards = Vec::new();
        for k in 1..=n {
            let out = path(&format!("s{k}of{n}.h5"));
            sweep(&out, &["--shard", &format!("{k}/{n}"), "--threads", "2"]);
            let part = read_sweep(Path::new(&out)).unwrap();
            let ran = part.results.status.iter().filter(|&&s| s != status::NOT_RUN).count();
            assert!(ran > 0 && ran < 48, "shard {k}/{n} runs part of the jobs ({ran})");
            shards.push(out);
        }
        let merged = path(&format!("merged{n}.h5"));
        let mut args = vec!["merge"];
        args.extend(shards.iter().map(String::as_str));
        args.extend(["--output", &merged, "--json"]);
        ok(&run(&args));
        let merged = read_sweep(Path::new(&merged)).unwrap();
        assert_eq!(merged.shard, "all");
        assert_identical(&merged, &one, &format!("{n} shards merged vs 1 thread"));
    }
}
