//! A run's config resolved once ([`Scenario`]): checked as a whole, its
//! joints placed (each joint's own config checked), a modal bridge's kept
//! modes selected. The generator and the coupled run take it, so that a
//! run (a sweep's job, say) checks its config once and each joint's once,
//! not again at every step that needs them.

use crate::config::Config;
use crate::error::ModelError;
use crate::modal::KeptMode;
use crate::placement::Place;

/// A config checked and resolved for runs.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// The config, checked ([`Config::validate`]).
    pub config: Config,
    /// Its joints, each with its own config, checked.
    pub places: Vec<Place>,
    /// A bridge given by its modes: the modes it keeps.
    pub kept: Option<Vec<KeptMode>>,
}

impl Scenario {
    /// Checks `config` and resolves its joints and kept modes.
    pub fn new(config: Config) -> Result<Self, ModelError> {
        config.validate()?;
        let kept =
            config.bridge.modal.as_ref().map(|m| crate::modal::kept_modes(m, config.bridge.damping)).transpose()?;
        let places = crate::placement::places(&config)?;
        if let (Some(m), Some(kept)) = (config.bridge.modal.as_ref().filter(|m| m.corrected()), &kept) {
            // the static correction at the joints' points, as the model
            // builds it: a `[static]` table of other modes is refused here,
            // before any run (a sweep's check and plan too)
            // (the deck ends first, then the hinges' abutment sides, as the
            // generator orders them)
            let decks = places.iter().flat_map(|p| std::iter::once(p.deck_point).chain(p.deck_point_y));
            let points: Vec<usize> = decks.chain(places.iter().filter_map(|p| p.abutment_point)).collect();
            crate::modal::loaded(m)?.static_correction(kept, &points, m.scale(), &m.modes)?;
        }
        Ok(Scenario { config, places, kept })
    }
}
