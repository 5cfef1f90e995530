//! A joint's seismic fuse (`[joint.fuse]`, docs/model.md "Seismic fuse"):
//! what the engineer gives, and its checks.

use serde::{Deserialize, Serialize};

use super::{check, invalid, JointConfig};
use crate::error::ModelError;

/// What kind of seismic fuse the joint has.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FuseKind {
    /// A fuse box at the abutment-side edge beam (MAURER types I and II,
    /// mageba's FUSE-BOX): the edge beam is held until the closing force on
    /// it reaches the break force, then travels toward the abutment against
    /// the box's resistance for its stroke, to a hard stop.
    #[default]
    Box,
    /// A fuse element (mageba's Fuse-Element): a designated center beam
    /// that leaves the plane of the joint once the closing force on it
    /// reaches its release force, so that its two cells act as one.
    Element,
}

/// A seismic fuse (docs/model.md "Seismic fuse"). No manufacturer
/// publishes its break force, ramp, stroke or friction: each is the
/// engineer's input, the defaults are stated assumptions.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FuseConfig {
    /// What breaks.
    pub kind: FuseKind,
    /// A box: the closing force on the edge beam at which its connection
    /// fails (the sum of the contact forces of center beam 1 on it); an
    /// element: the closing force on its beam at which it leaves the
    /// plane (the sum of the contact forces on the beam's abutment side)
    /// \[N\].
    pub break_force: f64,
    /// A box's travel of the freed edge beam toward the abutment before it
    /// meets the box's stop \[m\] (a box needs it; an element has none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stroke: Option<f64>,
    /// An element's beam: which center beam leaves the plane, 1 (next to
    /// the abutment) to `Nc` [-] (an element needs it; a box has none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beam: Option<usize>,
    /// Angle of the ramp the freed edge beam rides up (MAURER type I)
    /// \[deg\]; 0: a level floor it slides on (a drop-in box, type II).
    #[serde(default)]
    pub ramp_deg: f64,
    /// Friction coefficient of the edge beam on the ramp or the floor [-]
    /// (default [`DEFAULT_FUSE_MU`]).
    #[serde(default = "default_fuse_mu")]
    pub mu: f64,
    /// Mass of the edge beam and what moves with it \[kg\] (default: a
    /// center beam's, `joint.center_beam.mass`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
}

/// The fuse's friction coefficient by default [-]: steel on steel, greased
/// (0.1 to 0.2; dry 0.3 to 0.6). An assumption: no fuse maker gives it.
pub const DEFAULT_FUSE_MU: f64 = 0.15;

fn default_fuse_mu() -> f64 {
    DEFAULT_FUSE_MU
}

/// Checks `[joint.fuse]`: its values in range, and what its kind needs
/// and does not have.
pub(super) fn check_fuse(j: &JointConfig, f: &FuseConfig) -> Result<(), ModelError> {
    check("joint.fuse.break_force", f.break_force)?;
    let fail = |reason: &str| {
        Err(ModelError::Invalid { field: "joint.fuse".into(), value: "[joint.fuse]".into(), reason: reason.into() })
    };
    if !j.contact.enabled {
        return fail("a fuse breaks on the beams' contact force: it needs joint.contact.enabled = true");
    }
    match f.kind {
        FuseKind::Box => check_fuse_box(j, f),
        FuseKind::Element => check_fuse_element(j, f),
    }
}

/// Checks a fuse box's `[joint.fuse]`.
fn check_fuse_box(j: &JointConfig, f: &FuseConfig) -> Result<(), ModelError> {
    let Some(stroke) = f.stroke else {
        return Err(invalid_text(
            "joint.fuse.stroke",
            "(missing)",
            "a fuse box needs its stroke: the freed edge beam's travel to the box's stop [m]",
        ));
    };
    if let Some(beam) = f.beam {
        return Err(invalid(
            "joint.fuse.beam",
            beam as f64,
            "is a fuse element's (kind = \"element\"): a fuse box frees the abutment's edge beam",
        ));
    }
    for (key, v) in [
        ("joint.fuse.stroke", stroke),
        ("joint.fuse.ramp_deg", f.ramp_deg),
        ("joint.fuse.mu", f.mu),
        ("joint.fuse.mass", f.mass.unwrap_or(j.center_beam.mass)),
    ] {
        check(key, v)?;
    }
    let a = f.ramp_deg.to_radians();
    if a.cos() - f.mu * a.sin() <= 0.0 {
        return Err(invalid(
            "joint.fuse.ramp_deg",
            f.ramp_deg,
            &format!(
                "with joint.fuse.mu = {} the edge beam locks on the ramp (no push moves it up: \
                 cos(angle) - mu sin(angle) must be positive)",
                quakejoint_motion::number(f.mu)
            ),
        ));
    }
    Ok(())
}

/// Checks a fuse element's `[joint.fuse]`: its beam among the joint's,
/// with a neighbour on each side that is not both edge beams, and none of
/// a box's values.
fn check_fuse_element(j: &JointConfig, f: &FuseConfig) -> Result<(), ModelError> {
    let Some(beam) = f.beam else {
        return Err(invalid_text(
            "joint.fuse.beam",
            "(missing)",
            &format!("a fuse element needs its beam: which center beam leaves the plane, 1 to {}", j.center_beams),
        ));
    };
    check("joint.fuse.beam", beam as f64)?;
    if beam > j.center_beams {
        return Err(invalid(
            "joint.fuse.beam",
            beam as f64,
            &format!("the joint has {} center beams (joint.center_beams)", j.center_beams),
        ));
    }
    if j.center_beams < 2 {
        return Err(invalid(
            "joint.fuse.beam",
            beam as f64,
            "a fuse element needs a joint of 2 center beams or more: with one, the deck would meet the abutment",
        ));
    }
    let box_only = [
        ("joint.fuse.stroke", f.stroke.is_some()),
        ("joint.fuse.mass", f.mass.is_some()),
        ("joint.fuse.ramp_deg", f.ramp_deg != 0.0),
        // (its default cannot be told from a value written)
        ("joint.fuse.mu", f.mu != DEFAULT_FUSE_MU),
    ];
    if let Some((key, _)) = box_only.iter().find(|(_, given)| *given) {
        return Err(invalid_text(
            key,
            "(given)",
            "is a fuse box's (kind = \"box\"): a fuse element's beam leaves the plane, it has no stroke, ramp, friction or \
             mass of its own",
        ));
    }
    Ok(())
}

/// A refused key whose value is not a number (`value` says what it is).
fn invalid_text(field: &str, value: &str, reason: &str) -> ModelError {
    ModelError::Invalid { field: field.to_string(), value: value.to_string(), reason: reason.to_string() }
}
