//! A joint's seismic fuse (`[joint.fuse]`, docs/model.md "Seismic fuse"):
//! the fuse box at the abutment-side edge beam.
//!
//! Intact, the edge beam is the abutment (the plan model's edge line at
//! `x = 0`). Its connection fails when the closing force on it, the sum of
//! the contact forces of center beam 1 at both its ends, reaches the break
//! force: the solver locates that instant as an event
//! ([`quakejoint_solver::Radau5::set_force_threshold`]). From there the run
//! goes on ([`quakejoint_solver::Radau5::resume`]) in the broken system
//! ([`crate::run::fuse::broken_system`]): the edge beam is a body of its own along x, center
//! beam 1 strikes it, it slides toward the abutment against the box's
//! resistance (friction, and on a ramp the lift's constant component that
//! pushes it back toward its seat), and it meets a hard stop after the
//! stroke. Until the break no extra body exists, so a fuse that never
//! breaks leaves the run as it is without one, bit for bit.
//!
//! This module resolves a joint's `[joint.fuse]` ([`FuseBox`]); the run
//! breaks it and watches it (`crate::run::fuse`).

use quakejoint_solver::{BodyId, ContactLaw, ForceId, FrictionLaw};

use crate::config::{Config, FuseKind};
use crate::error::ModelError;

/// Standard gravity [m/s^2]: the freed edge beam's weight.
const G: f64 = 9.81;

/// A joint's fuse box, resolved: its break force and what resists the
/// freed edge beam.
#[derive(Debug, Clone, PartialEq)]
pub struct FuseBox {
    /// The closing force on the edge beam at which it breaks free \[N\].
    pub break_force: f64,
    /// Travel toward the abutment to the box's stop \[m\].
    pub stroke: f64,
    /// Mass of the freed edge beam \[kg\].
    pub mass: f64,
    /// Constant force pushing the freed beam back to its seat (a ramp's
    /// lift, `(H_up + H_down) / 2`; 0 on a level floor) \[N\].
    pub lift: f64,
    /// Its sliding resistance (`(H_up - H_down) / 2`: the friction) \[N\].
    pub resistance: f64,
    /// The friction's regularisation velocity, the joint's
    /// (`joint.friction.v_eps`) [m/s]: a beam held on a ramp by friction
    /// alone creeps back toward its seat at up to `v_eps lift /
    /// resistance`.
    pub v_eps: f64,
    /// The friction's regularised law: the smooth one, whatever the
    /// bearings' (with the linear law's kink at `v_eps` the freed beam's
    /// stick-slip made the integrator crawl and its energy balance drift:
    /// docs/model.md, "Seismic fuse").
    pub friction_law: FrictionLaw,
    /// The contacts of center beam 1 on the edge beam (both ends).
    pub(crate) contacts: Vec<ForceId>,
    /// The solver's numbers of those contacts.
    pub(crate) contact_numbers: Vec<usize>,
    /// The law of the seat's and the stop's contact (the joint's).
    pub(crate) law: ContactLaw,
    /// The joint's group of bodies for the freed beam's friction energy.
    pub(crate) group: u32,
    /// What starts its bodies' names.
    pub(crate) prefix: String,
}

impl FuseBox {
    /// The fuse box of `config`'s joint (none without `[joint.fuse]`),
    /// with the joint's contacts on its edge beam, numbered from `first`,
    /// the law of its seat's and stop's contacts (the joint's), and its
    /// bodies' group and names.
    pub(crate) fn new(
        config: &Config,
        contacts: Vec<ForceId>,
        first: usize,
        law: ContactLaw,
        (group, prefix): (u32, &str),
    ) -> Option<Self> {
        let f = config.joint.fuse.as_ref()?;
        let (mass, [lift, resistance]) = box_forces(&config.joint)?;
        let contact_numbers = (first..first + contacts.len()).collect();
        Some(Self {
            break_force: f.break_force,
            stroke: f.stroke,
            mass,
            lift,
            resistance,
            v_eps: config.joint.friction.v_eps,
            friction_law: FrictionLaw::Smooth,
            contacts,
            contact_numbers,
            law,
            group,
            prefix: prefix.to_string(),
        })
    }
}

/// The freed edge beam of `joint`'s fuse box (none without one): its mass
/// \[kg\] and `[lift, resistance]` \[N\] ([`ramp_forces`] of its weight).
pub fn box_forces(joint: &crate::config::JointConfig) -> Option<(f64, [f64; 2])> {
    let f = joint.fuse.as_ref()?;
    match f.kind {
        FuseKind::Box => {}
    }
    let mass = f.mass.unwrap_or(joint.center_beam.mass);
    Some((mass, ramp_forces(mass * G, f.ramp_deg, f.mu)))
}

/// A block of weight `w` \[N\] on a ramp of `angle_deg` with friction `mu`:
/// the horizontal push that moves it up, `H_up = w (sin a + mu cos a) /
/// (cos a - mu sin a)`, and the one that holds it from sliding down, `H_down
/// = w (sin a - mu cos a) / (cos a + mu sin a)` (negative: it stays without
/// a hold), as a constant pull toward the seat `(H_up + H_down) / 2` and a
/// friction `(H_up - H_down) / 2` \[N\]. A level floor: no pull, friction
/// `mu w`.
pub fn ramp_forces(w: f64, angle_deg: f64, mu: f64) -> [f64; 2] {
    let (s, c) = angle_deg.to_radians().sin_cos();
    let up = w * (s + mu * c) / (c - mu * s);
    let down = w * (s - mu * c) / (c + mu * s);
    [0.5 * (up + down), 0.5 * (up - down)]
}

/// Checks that a fuse box's edge beam rests on the ground: a joint whose
/// abutment side moves (an adjacent segment, an in-span hinge, a lagged
/// abutment) cannot have one yet. `field` names the joint's fuse.
pub(crate) fn check_abutment(abutment: BodyId, field: &str) -> Result<(), ModelError> {
    if abutment.is_ground() {
        return Ok(());
    }
    Err(ModelError::Invalid {
        field: field.to_string(),
        value: "[joint.fuse]".to_string(),
        reason: "a fuse box needs the joint's abutment side on the ground: not on an adjacent segment \
                 ([bridge.far]), an in-span hinge (abutment_point) or a lagged abutment (abutment_lag)"
            .to_string(),
    })
}
