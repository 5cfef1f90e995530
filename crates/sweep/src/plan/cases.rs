//! A sweep's cases (`[[sweep.cases]]`): the parameter sets that differ
//! from the base config, what a case may not change of the bridge (the
//! swept keys; of a bridge given by its modes, also its modes file, period
//! scale and damping), and how a case's table merges into the base
//! config's.

use quakejoint_model::Config;

/// One named parameter set.
#[derive(Debug, Clone)]
pub struct Case {
    /// Name, unique within the sweep.
    pub name: String,
    /// The full config of this case.
    pub config: Config,
    /// Number of joint bodies (for the cost estimate).
    pub bodies: usize,
}

/// The key of a case's `[bridge]` table `b` that a case may not change,
/// and why (`modal`: the sweep's bridge is given by its modes).
pub(super) fn refused_in_case(b: &toml::Table, modal: bool) -> Option<(String, &'static str)> {
    let modal_table = b.get("modal").and_then(|m| m.as_table());
    if !modal {
        if b.contains_key("modal") {
            return Some((
                "modal".into(),
                "the sweep's bridge is a single-DOF deck; a case cannot give it modes (a sweep of a bridge given by \
                 its modes has [bridge.modal] in its base config)",
            ));
        }
        return ["w0", "period", "damping"]
            .into_iter()
            .find(|k| b.contains_key(*k))
            .map(|k| (k.to_string(), "the bridge period and damping are swept, not set per case"));
    }
    for k in ["w0", "period"] {
        if b.contains_key(k) {
            return Some((
                k.into(),
                "the bridge is given by its modes: its periods are the modes file's times sweep.period_scales",
            ));
        }
    }
    if b.contains_key("damping") {
        return Some((
            "damping".into(),
            "the modes' damping (the modes file's, or bridge.damping) is the sweep's damping axis, shared by its \
             cases: run one sweep per bridge.damping",
        ));
    }
    match modal_table {
        Some(m) if m.contains_key("modes") => Some((
            "modal.modes".into(),
            "the modes file is the sweep's bridge, shared by its cases (a case may keep fewer or more of its modes: \
             bridge.modal.modes_used)",
        )),
        Some(m) if m.contains_key("period_scale") => {
            Some(("modal.period_scale".into(), "the period scale is swept (sweep.period_scales), not set per case"))
        }
        _ => None,
    }
}

/// Recursively merges `over` into `base` (tables merge, other values replace).
pub(super) fn merge(base: &mut toml::Table, over: &toml::Table) {
    for (k, v) in over {
        match (base.get_mut(k), v) {
            (Some(toml::Value::Table(b)), toml::Value::Table(o)) => merge(b, o),
            _ => {
                base.insert(k.clone(), v.clone());
            }
        }
    }
}
