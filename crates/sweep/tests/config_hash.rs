//! Which config changes a sweep's journal tells apart (`config_sha256`).
//!
//! A journal is continued only with the parameters it was started with.
//! The hash is of the config as resolved, every default filled in. Writing a
//! default out therefore changes nothing, and neither do comments, layout or
//! the per-job limits. A changed value changes the hash. So does a default
//! that changed between versions: `simulation.bearing_atol_factor` became
//! 2 while a journal written with 1 could still be continued (the same
//! parameters as written, different jobs).

use std::path::PathBuf;

use quakejoint_sweep::Plan;

fn hash_of(extra: &str) -> String {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let text = std::fs::read_to_string(root.join("configs/paper.toml")).unwrap();
    let text = text.replacen("[simulation]\n", &format!("[simulation]\n{extra}"), 1);
    Plan::new(&text, "paper.toml", &root.join("configs")).unwrap().config_sha256
}

#[test]
fn the_journal_hash_is_of_the_resolved_config() {
    let plain = hash_of("");
    assert_eq!(hash_of("bearing_atol_factor = 2.0   # the default, written out\n"), plain);
    assert_eq!(hash_of("max_wall_time = 600.0\nmax_steps = 1000000\n"), plain);
    assert_ne!(hash_of("bearing_atol_factor = 1.0\n"), plain);
    assert_ne!(hash_of("rtol = 1e-7\n"), plain);
}
