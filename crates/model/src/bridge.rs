//! A run's bridge, resolved once ([`Bridge`]): a single-DOF deck, or a
//! bridge given by its modes with the modes a run keeps and their static
//! correction. Each variant has its one implementation of the bridge
//! without its joints (`SingleDof::alone`, `Modal::alone_at`, both behind
//! `Bridge::alone`, in [`crate::linear`]), which the run with `--no-joint`,
//! the histories and peaks "without the joint" of every run, a sweep's
//! spectra without the joint and its check of the record's window take.

use std::sync::Arc;

use quakejoint_motion::Record;

use crate::config::Config;
use crate::error::ModelError;
use crate::modal::{KeptMode, ModalAlone, ModalBridge, StaticCorrection};
use crate::placement::Place;

/// A run's bridge.
#[derive(Debug, Clone, PartialEq)]
pub enum Bridge {
    /// A deck of one mass on a spring and a damper (`[bridge]`).
    SingleDof(SingleDof),
    /// A bridge given by its modes (`[bridge.modal]`).
    Modal(Modal),
}

/// A single-DOF deck along the bridge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SingleDof {
    /// Natural period \[s\]: the override as given, else the config's.
    pub period: f64,
    /// Circular frequency \[rad/s\] (the config's, `2 pi / period`).
    pub omega: f64,
    /// Damping ratio \[-\].
    pub damping: f64,
}

/// A bridge given by its modes, as a run uses it.
#[derive(Debug, Clone, PartialEq)]
pub struct Modal {
    /// The modes file.
    pub file: Arc<ModalBridge>,
    /// The modes a run keeps, the longest period first, its period scale
    /// applied.
    pub kept: Vec<KeptMode>,
    /// The static correction of the modes left out at the joints' points
    /// (`bridge.modal.static_correction`).
    pub correction: Option<StaticCorrection>,
    /// With the static correction: the static displacement per unit
    /// ground acceleration along x of the modes left out at each point of
    /// the file \[s^2\], which the bridge without its joints adds
    /// ([`ModalBridge::ground_residual`]).
    pub ground_residual: Option<Vec<f64>>,
}

impl Bridge {
    /// The bridge of a checked `config` with its joints at `places`
    /// (their deck points for the static correction); `period` overrides
    /// a single-DOF deck's.
    pub(crate) fn resolve(config: &Config, places: &[Place], period: Option<f64>) -> Result<Self, ModelError> {
        let Some(m) = &config.bridge.modal else {
            let period = period.unwrap_or_else(|| config.bridge.natural_period());
            let (omega, damping) = (config.bridge.omega(), config.bridge.damping);
            return Ok(Bridge::SingleDof(SingleDof { period, omega, damping }));
        };
        let file = crate::modal::loaded_arc(m)?;
        let kept = file.kept(m.modes_used, m.scale(), config.bridge.damping);
        let (correction, ground_residual) = if m.corrected() {
            // at the joints' points as the model builds them: the deck ends
            // first, then the hinges' abutment sides (a `[static]` table of
            // other modes is refused here, before any run)
            let decks = places.iter().flat_map(|p| std::iter::once(p.deck_point).chain(p.deck_point_y));
            let points: Vec<usize> = decks.chain(places.iter().filter_map(|p| p.abutment_point)).collect();
            let correction = file.static_correction(&kept, &points, m.scale(), &m.modes)?;
            (Some(correction), file.ground_residual(&kept, m.scale()))
        } else {
            (None, None)
        };
        Ok(Bridge::Modal(Modal { file, kept, correction, ground_residual }))
    }

    /// The bridge's period \[s\]: a single-DOF deck's, a modal bridge's
    /// longest kept one.
    pub fn period(&self) -> f64 {
        match self {
            Bridge::SingleDof(b) => b.period,
            Bridge::Modal(m) => 2.0 * std::f64::consts::PI / m.kept[0].omega,
        }
    }

    /// The modes, when the bridge is given by them.
    pub fn modal(&self) -> Option<&Modal> {
        match self {
            Bridge::SingleDof(_) => None,
            Bridge::Modal(m) => Some(m),
        }
    }
}

impl Modal {
    /// The kept modes' exact superposition under `record` along the
    /// ground's direction `dir` (0: x, 1: y), with the ground's part of
    /// the static correction along x.
    pub fn superposition(&self, record: &Record, dir: usize) -> ModalAlone {
        let all = crate::modal::modal_superposition(record, &self.kept, dir);
        match dir {
            0 => all.with_ground_static(self.ground_residual.as_deref(), record),
            _ => all,
        }
    }
}
