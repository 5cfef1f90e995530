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
