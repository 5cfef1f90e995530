//! A run's config resolved once ([`Scenario`]): checked as a whole, its
//! joints placed (each joint's own config checked), a modal bridge's kept
//! modes selected. The generator and the coupled run take it, so that a
//! run (a sweep's job, say) checks its config once and each joint's once,
//! not again at every step that needs them.

use crate::bridge::Bridge;
use crate::config::Config;
use crate::error::ModelError;
use crate::placement::Place;

/// A config checked and resolved for runs.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// The config, checked ([`Config::validate`]).
    pub config: Config,
    /// Its joints, each with its own config, checked.
    pub places: Vec<Place>,
    /// Its bridge: a single-DOF deck, or the modes it keeps.
    pub bridge: Bridge,
}

impl Scenario {
    /// Checks `config` and resolves its joints and its bridge.
    pub fn new(config: Config) -> Result<Self, ModelError> {
        Self::with_period(config, None)
    }

    /// As [`Scenario::new`], with a single-DOF deck's period \[s\] as a
    /// front end gave it (the config's `bridge.period` holds it too).
    pub(crate) fn with_period(config: Config, period: Option<f64>) -> Result<Self, ModelError> {
        config.validate()?;
        let places = crate::placement::places(&config)?;
        let bridge = Bridge::resolve(&config, &places, period)?;
        Ok(Scenario { config, places, bridge })
    }

    /// The first joint's deck point (a single-DOF deck's: 0).
    pub fn first_point(&self) -> usize {
        self.places[0].deck_point
    }
}
