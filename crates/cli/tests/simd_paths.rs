//! The AVX2 and the portable versions of the solver's kernels give the
//! same numbers bit for bit (`quakejoint_solver::isa`).
//!
//! The kernels where the time goes are compiled twice and chosen at run
//! time; a sweep sharded over cluster nodes with and without AVX2 must still
//! give the results of one machine. Only AVX2 is enabled, not FMA, and
//! vectorised loops keep the order of their sums, so the rounding is the
//! same. Checked on a sweep of the small joint (residuals, block
//! factorisations and solves, local friction solves, energy quadrature,
//! peak forces): once at 0.15 of Corralitos 090, where every gap stays open,
//! and once at full scale, where the beams pound (contact forces and events).
//! Every numeric dataset, time histories included, must be identical.

mod common;

use std::path::Path;

use common::{assert_identical, bin, config, dir};
use quakejoint_sweep::sweep_h5::read_sweep;

#[test]
fn avx2_and_portable_kernels_give_identical_sweeps() {
    let skipped = Path::new(env!("CARGO_TARGET_TMPDIR")).join("simd_paths.skipped");
    if !quakejoint_solver::isa::avx2_in_use() {
        // (both runs below would take the portable kernels: nothing to
        // compare; scripts/test.sh reports the file as a test not run)
        let why = "this processor has no AVX2, or QUAKEJOINT_SIMD=portable is set: the two versions are the same here";
        eprintln!("{why}");
        std::fs::write(&skipped, why).unwrap();
        return;
    }
    let _ = std::fs::remove_file(&skipped);
    let d = dir("simd");
    let record = common::root().join("ground_motions/RSN753_LOMAP_CLS090-hor2.AT2");
    let sweep = format!(
        "[sweep]\n\
         periods = {{ from = 0.4, to = 2.0, count = 3, spacing = \"log\" }}\n\
         damping = [0.05]\n\
         histories = [0.9]\n\
         records = [{{ file = {record:?}, scale = 0.15, name = \"open\" }}, {{ file = {record:?}, scale = 1.0, name = \"pounding\" }}]\n"
    );
    let cfg = config(&d, "grid.toml", &sweep, 6.0);
    let out = |name: &str| d.join(name).to_str().unwrap().to_string();
    let run = |simd: Option<&str>, file: &str| {
        let mut cmd = bin();
        match simd {
            Some(value) => cmd.env("QUAKEJOINT_SIMD", value),
            None => cmd.env_remove("QUAKEJOINT_SIMD"),
        };
        let o = cmd
            .args(["sweep", cfg.to_str().unwrap(), "--output", file, "--threads", "1", "--json"])
            .output()
            .expect("runs");
        // (pounding runs are flagged: exit code 4)
        assert!(matches!(o.status.code(), Some(0 | 4)), "{simd:?}: {}", String::from_utf8_lossy(&o.stderr));
    };
    run(None, &out("avx2.h5"));
    run(Some("portable"), &out("portable.h5"));
    let (a, p) = (read_sweep(Path::new(&out("avx2.h5"))).unwrap(), read_sweep(Path::new(&out("portable.h5"))).unwrap());
    assert_eq!(a.results.status.len(), 6);
    let field = quakejoint_sweep::results::FIELDS.iter().position(|f| *f == "impacts").unwrap();
    let impacts = &a.results.values[field];
    assert!(impacts.iter().any(|&n| n > 0.0), "the full-scale runs pound: {impacts:?}");
    assert_identical(&a, &p, "AVX2 against portable kernels");
}
