//! Helpers shared by the model tests.
#![allow(dead_code)]

use std::path::PathBuf;

use quakejoint_model::Config;

/// The repository's `configs/` directory.
pub fn configs_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../configs")
}

/// A shipped config.
pub fn shipped(name: &str) -> Config {
    Config::from_file(&configs_dir().join(name)).expect("shipped config")
}

/// A shipped config with extra TOML appended (later keys must be new tables).
pub fn shipped_with(name: &str, extra: &str) -> Config {
    let text = std::fs::read_to_string(configs_dir().join(name)).unwrap();
    Config::from_toml(&format!("{text}\n{extra}"), name).expect("config")
}

/// `config` with the bridge's circular frequency `omega` [rad/s] (as a
/// front end's period override sets it: the frequency replaces the period).
pub fn at_omega(mut config: Config, omega: f64) -> Config {
    (config.bridge.w0, config.bridge.period) = (Some(omega), None);
    config
}

/// An OpenSees transient of the three-span bridge (`tests/data/three_span/<csv>`):
/// time, then (u, a_abs) of each point in the modes file's order; the
/// header must name the left end's u second and the right end's fourth.
pub fn opensees_csv(csv: &str) -> (Vec<f64>, Vec<Vec<f64>>) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/three_span").join(csv);
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert!(header[1].starts_with("left end u") && header[3].starts_with("right end u"), "{header:?}");
    let mut t = Vec::new();
    let mut cols = vec![Vec::new(); header.len() - 1];
    for l in lines {
        let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
        t.push(v[0]);
        for (c, x) in cols.iter_mut().zip(&v[1..]) {
            c.push(*x);
        }
    }
    (t, cols)
}
pub mod closing;
