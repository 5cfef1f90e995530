//! A sweep over a bridge given by its modes (`[bridge.modal]`): its swept
//! axis `sweep.period_scales` (and the refusal of `sweep.periods` and
//! `sweep.damping`) and the modes file's identity (its path and hash).

use std::path::{Path, PathBuf};

use quakejoint_model::config::ModalConfig;
use quakejoint_model::runspec::{Named, Overrides};
use quakejoint_model::Config;

use super::grid::grid_of;
use super::sweep_err;
use crate::error::SweepError;

/// What a sweep over a bridge given by its modes (`[bridge.modal]`) adds
/// to its plan: the swept factors on the modes' periods, the modes file
/// and its joints.
#[derive(Debug, Clone)]
pub struct ModalSweep {
    /// The swept factors on every period of the modes [-]
    /// (`sweep.period_scales`; each job's `bridge.modal.period_scale`).
    pub period_scales: Vec<f64>,
    /// Whether they are `sweep.period_scales` (else the config's own
    /// `bridge.modal.period_scale`, 1 by default: one job per record and
    /// case, each the config's run as it stands).
    pub swept: bool,
    /// The modes file as the config names it (`bridge.modal.modes`).
    pub file: String,
    /// The modes file, resolved against the config's folder.
    pub path: PathBuf,
    /// SHA-256 of its bytes (hex), part of the config's hash: a changed
    /// modes file is another sweep.
    pub sha256: String,
    /// The names of every joint of the run, in the order of `[[joints]]` (their
    /// values are stored per joint).
    pub joints: Vec<String>,
}

impl ModalSweep {
    /// The override of the jobs at period scale `t` (an index), named as
    /// the sweep names it (none when the scale is the config's own).
    pub fn overrides(&self, t: usize) -> Overrides {
        Overrides {
            period_scale: self.swept.then(|| Named::new(self.period_scales[t], format!("sweep.period_scales[{t}]"))),
            ..Overrides::default()
        }
    }
}

/// The swept axis of a bridge given by its modes (`sweep.period_scales`,
/// default the config's `bridge.modal.period_scale`, 1) and what the sweep
/// keeps of its modes file; `sweep.periods` and `sweep.damping` are
/// refused.
pub(super) fn modal_axis(
    sweep: &super::SweepSection,
    m: &ModalConfig,
    config: &Config,
    base_dir: &Path,
) -> Result<ModalSweep, SweepError> {
    if sweep.periods.is_some() {
        return Err(sweep_err(
            "sweep.periods",
            "the bridge is given by its modes ([bridge.modal]): sweep its periods with sweep.period_scales, a \
             factor on every period of the modes (period_scales = [0.8, 1.0, 1.25], or { from, to, count, spacing })",
        ));
    }
    if sweep.damping.is_some() {
        return Err(sweep_err(
            "sweep.damping",
            "the bridge is given by its modes ([bridge.modal]): their damping ratios are the modes file's, or \
             bridge.damping where it gives none, and are not swept; sweep the periods with sweep.period_scales (and \
             run one sweep per bridge.damping to study the damping)",
        ));
    }
    let swept = sweep.period_scales.is_some();
    let period_scales = match &sweep.period_scales {
        Some(v) => {
            if let Some(f) = m.period_scale {
                return Err(sweep_err(
                    "bridge.modal.period_scale",
                    format!(
                        "{}: the sweep sets every job's period scale (sweep.period_scales); remove \
                         bridge.modal.period_scale, or sweep.period_scales to run the config's scale alone",
                        quakejoint_motion::number(f)
                    ),
                ));
            }
            grid_of(v, "sweep.period_scales", "bridge.modal.period_scale", "1")?
        }
        None => vec![m.scale()],
    };
    Ok(ModalSweep {
        period_scales,
        swept,
        file: m.modes.clone(),
        path: base_dir.join(&m.modes),
        sha256: quakejoint_model::modal::loaded(m)?.sha256.clone(),
        joints: quakejoint_model::placement::places(config)?.into_iter().map(|p| p.name).collect(),
    })
}
