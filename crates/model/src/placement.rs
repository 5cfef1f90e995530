//! Where the joints of a run sit: the one joint of `[joint]`, or each of
//! `[[joints]]` at its points of a modal bridge, each with the config it
//! is built from (the run's, with its own `[joint]`).

use crate::config::Config;
use crate::error::ModelError;
use crate::modal::Direction;

/// One joint of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Place {
    /// Its name ("joint" for the one of `[joint]`).
    pub name: String,
    /// What starts the names of its bodies and elements ("" for the one of
    /// `[joint]`, "name: " otherwise).
    pub prefix: String,
    /// The run's config with this joint as its `[joint]`.
    pub config: Config,
    /// +1, or -1 for a joint turned half a turn.
    pub sign: f64,
    /// Its deck side's point in the modes file (0 on a single-DOF deck).
    pub deck_point: usize,
    /// Its deck side's point across, if its deck end moves across.
    pub deck_point_y: Option<usize>,
    /// Its abutment side's point at an in-span hinge; none: the ground.
    pub abutment_point: Option<usize>,
    /// How much later the ground motion reaches its abutment \[s\] (0: as
    /// the other supports).
    pub abutment_lag: f64,
}

pub use crate::config::MAX_ABUTMENT_LAG;

/// The joints of `config`, checked (each joint's values as `[joint]`'s are,
/// named `joints[k].joint.<key>`).
pub fn places(config: &Config) -> Result<Vec<Place>, ModelError> {
    let modal = config.bridge.modal.as_ref().map(crate::modal::loaded).transpose()?;
    if config.joints.is_empty() {
        let deck_point = match (modal, config.bridge.modal.as_ref().and_then(|m| m.joint_point.as_ref())) {
            (Some(b), Some(p)) => b.point(p, Direction::X, "bridge.modal.joint_point")?,
            _ => 0,
        };
        let deck_point_y = match (modal, config.bridge.modal.as_ref().and_then(|m| m.joint_point_y.as_ref())) {
            (Some(b), Some(p)) => Some(b.point(p, Direction::Y, "bridge.modal.joint_point_y")?),
            _ => None,
        };
        return Ok(vec![Place {
            name: "joint".to_string(),
            prefix: String::new(),
            config: config.clone(),
            sign: 1.0,
            deck_point,
            deck_point_y,
            abutment_point: None,
            abutment_lag: 0.0,
        }]);
    }
    let Some(bridge) = modal else {
        return Err(ModelError::Invalid {
            field: "joints".to_string(),
            value: format!("{} joints", config.joints.len()),
            reason: "joints are placed at points of a bridge given by its modes: add [bridge.modal]".to_string(),
        });
    };
    let mut out: Vec<Place> = Vec::with_capacity(config.joints.len());
    for (k, j) in config.joints.iter().enumerate() {
        // (names unique: Config::validate)
        let field = |key: &str| format!("joints[{k}].{key}");
        let mut c = config.clone();
        if let Some(joint) = &j.joint {
            c.joint = joint.clone();
        }
        c.validate().map_err(|e| rename(e, k, j.joint.is_some()))?;
        let deck_point = bridge.point(&j.deck_point, Direction::X, &field("deck_point"))?;
        let deck_point_y =
            j.deck_point_y.as_ref().map(|p| bridge.point(p, Direction::Y, &field("deck_point_y"))).transpose()?;
        let abutment_point =
            j.abutment_point.as_ref().map(|a| bridge.point(a, Direction::X, &field("abutment_point"))).transpose()?;
        if abutment_point == Some(deck_point) {
            return Err(ModelError::Invalid {
                field: field("abutment_point"),
                value: format!("\"{}\"", j.deck_point),
                reason: "a joint's abutment and deck sides cannot move with the same point".to_string(),
            });
        }
        // (its range checked with the config: Config::validate)
        let abutment_lag = j.abutment_lag.unwrap_or(0.0);
        out.push(Place {
            name: j.name.clone(),
            prefix: format!("{}: ", j.name),
            config: c,
            sign: j.deck_side.sign(),
            deck_point,
            deck_point_y,
            abutment_point,
            abutment_lag,
        });
    }
    Ok(out)
}

/// An error about `joint.<key>` of joint `k`'s own `[joints.joint]` names
/// it `joints[k].joint.<key>`.
fn rename(e: ModelError, k: usize, own: bool) -> ModelError {
    match e {
        ModelError::Invalid { field, value, reason } if own && field.starts_with("joint.") => {
            ModelError::Invalid { field: format!("joints[{k}].{field}"), value, reason }
        }
        ModelError::Geometry(g) if own => ModelError::Geometry(format!("joints[{k}]: {g}")),
        other => other,
    }
}
