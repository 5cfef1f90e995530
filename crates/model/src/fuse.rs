//! A joint's seismic fuse (`[joint.fuse]`, docs/model.md "Seismic fuse"):
//! the fuse box at the abutment-side edge beam ([`FuseBox`]), or the fuse
//! element, a center beam that leaves the plane ([`FuseElement`]).
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
//! A fuse element's beam stays where it is until the closing force on it,
//! the sum of its neighbour's contact forces on its abutment side at both
//! ends, reaches its release force (the same located event). It then
//! leaves the plane: the solver opens its contacts, booking the elastic
//! energy they still held ([`quakejoint_solver::Radau5::release_contacts`]),
//! and the run goes on in a system where its neighbours meet each other
//! across the one cell its two cells have become. No body is added or
//! removed (the beam keeps its bearings, out of the others' way), so the
//! solver's numbers of every body and contact stay.
//!
//! This module resolves a joint's `[joint.fuse]` ([`Fuse`]); the run
//! breaks it and watches it (`crate::run::fuse`).

use quakejoint_solver::{BodyId, Contact, ContactLaw, ForceId, FrictionLaw};

use crate::cells::{cell_contact, CellBodies, Side};
use crate::config::{Config, FuseKind};
use crate::error::ModelError;
use crate::geometry::Geometry;

/// A joint's seismic fuse, resolved.
#[derive(Debug, Clone, PartialEq)]
pub enum Fuse {
    /// A fuse box at the abutment-side edge beam.
    Box(FuseBox),
    /// A fuse element: a center beam that leaves the plane.
    Element(FuseElement),
}

impl Fuse {
    /// The closing force at which it breaks \[N\].
    pub fn break_force(&self) -> f64 {
        match self {
            Fuse::Box(b) => b.break_force,
            Fuse::Element(e) => e.break_force,
        }
    }

    /// The solver's numbers of the contacts whose summed force breaks it.
    pub(crate) fn threshold_contacts(&self) -> &[usize] {
        match self {
            Fuse::Box(b) => &b.contact_numbers,
            Fuse::Element(e) => &e.contact_numbers,
        }
    }
}

/// Where an edge beam 1 km behind the abutment would be \[m\]: a contact
/// on it never closes (a fuse element's released beam keeps its contacts'
/// numbers in the solver, and they no longer touch).
const FAR: f64 = -1.0e3;

/// A joint's fuse element, resolved: its beam, its release force, and
/// what its contacts become when it leaves the plane.
#[derive(Debug, Clone, PartialEq)]
pub struct FuseElement {
    /// The closing force on the beam at which it leaves \[N\].
    pub break_force: f64,
    /// Which center beam leaves, 1 (next to the abutment) to `Nc`.
    pub beam: usize,
    /// The closing travel the joint gains as it leaves, its width \[m\].
    pub room: f64,
    /// The solver's numbers of its contacts on its abutment side (both
    /// ends): their summed force releases it.
    pub(crate) contact_numbers: Vec<usize>,
    /// The solver's numbers of its contacts on both sides: opened as it
    /// leaves.
    pub(crate) released: Vec<usize>,
    /// Those contacts and what each becomes once it left: its neighbours'
    /// contacts across the merged cell (in the slots of its abutment-side
    /// cell, or of its deck-side cell when its neighbour there is the
    /// deck, so that the cells at the abutment and the deck keep theirs),
    /// and contacts that never close.
    pub(crate) replaced: Vec<(ForceId, Contact)>,
}

/// A joint's contacts as [`FuseElement::new`] finds them: their ids in
/// the solver's order, the solver's number of the first, the bodies its
/// cells lie between, and the masses impacts at the abutment and at the
/// deck meet.
pub(crate) struct ElementSides<'a> {
    pub ids: &'a [ForceId],
    pub first: usize,
    pub bodies: CellBodies<'a>,
    pub impacts: [Option<f64>; 2],
}

impl FuseElement {
    /// The fuse element of `config`'s joint (none without one), of
    /// geometry `geo`, whose contacts (of law `law`) are `sides`.
    pub(crate) fn new(config: &Config, geo: &Geometry, law: ContactLaw, sides: ElementSides<'_>) -> Option<Self> {
        let f = config.joint.fuse.as_ref().filter(|f| f.kind == FuseKind::Element)?;
        let (k, nc) = (f.beam?, sides.bodies.beams.len());
        if k == 0 || k > nc || nc < 2 {
            return None;
        }
        // (its cells k - 1 and k: contacts 2 (k - 1) to 2 k + 1, end 0 first)
        let cells = 2 * (k - 1)..2 * (k + 1);
        let left = if k == 1 { Side::Abutment } else { Side::Beam(k - 2) };
        let right = if k == nc { Side::Deck } else { Side::Beam(k) };
        let merged = if k == nc { 2 * k } else { 2 * (k - 1) };
        let replaced = cells
            .clone()
            .map(|i| {
                let contact = if i / 2 == merged / 2 {
                    let y = if i % 2 == 0 { -geo.half_length } else { geo.half_length };
                    cell_contact(&sides.bodies, geo, (left, right), y, (law, sides.impacts))
                } else {
                    Contact {
                        body: sides.bodies.beams[k - 1],
                        point: [0.0, 0.0],
                        base: BodyId::GROUND,
                        edge_point: [FAR, 0.0],
                        edge_normal: [1.0, 0.0],
                        law,
                        reduced_mass: None,
                    }
                };
                (sides.ids[i], contact)
            })
            .collect();
        Some(Self {
            break_force: f.break_force,
            beam: k,
            room: geo.width,
            contact_numbers: vec![sides.first + cells.start, sides.first + cells.start + 1],
            released: cells.map(|i| sides.first + i).collect(),
            replaced,
        })
    }
}

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
            stroke: f.stroke?,
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

impl FuseElement {
    /// The fuse element of `config`'s joint modelled as a link element
    /// (none without one): the link's gap contact `gap` (its id, the
    /// solver's number and the contact) is released at the release force,
    /// and becomes the gap of the joint less one cell: it closes the beam's
    /// width later, its cells' contacts one fewer in series (the linear
    /// law's stiffness `(Nc + 1) / Nc` times, the Hertz law's that to the
    /// power 1.5).
    pub(crate) fn in_link(config: &Config, (id, number, contact): (ForceId, usize, &Contact)) -> Option<Self> {
        let f = config.joint.fuse.as_ref().filter(|f| f.kind == FuseKind::Element)?;
        let cells = config.joint.cells() as f64;
        let stiffer = cells / (cells - 1.0);
        let room = config.joint.center_beam.width;
        let mut after = contact.clone();
        after.edge_point[0] -= room;
        after.law = match after.law {
            ContactLaw::Linear { stiffness, restitution } => {
                ContactLaw::Linear { stiffness: stiffness * stiffer, restitution }
            }
            ContactLaw::Hertz { stiffness, restitution, damping } => {
                ContactLaw::Hertz { stiffness: stiffness * stiffer.powf(1.5), restitution, damping }
            }
        };
        Some(Self {
            break_force: f.break_force,
            beam: f.beam?,
            room,
            contact_numbers: vec![number],
            released: vec![number],
            replaced: vec![(id, after)],
        })
    }
}

/// The freed edge beam of `joint`'s fuse box (none without one): its mass
/// \[kg\] and `[lift, resistance]` \[N\] ([`ramp_forces`] of its weight).
pub fn box_forces(joint: &crate::config::JointConfig) -> Option<(f64, [f64; 2])> {
    let f = joint.fuse.as_ref()?;
    if f.kind != FuseKind::Box {
        return None;
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
