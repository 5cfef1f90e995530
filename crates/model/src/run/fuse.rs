//! A run whose joints have fuses (`crate::fuse`): the break located as an
//! event, the run resumed in the broken system ([`run_with_fuses`],
//! [`broken_system`]), and what each fuse did ([`FuseWatch`],
//! [`FuseResult`]).

use std::sync::Arc;

use quakejoint_solver::{
    AppliedLoad, Assembly, AssemblyOptions, Body, BodyId, Contact, ContactValue, Coord, ForceElement, Friction,
    FrictionLaw, IntegratorOptions, Observer, Radau5, System, TimeFunction, NO_GROUP,
};

use crate::config::FuseKind;
use crate::described::{described, Described};
use crate::error::ModelError;
use crate::fuse::{Fuse, FuseBox};
use crate::generator::JointModel;

/// Where a broken fuse box's parts are in the broken system.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FreedParts {
    /// The freed edge beam.
    pub edge: BodyId,
    /// The solver's number of its seat's contact.
    pub seat: usize,
    /// The solver's number of its stop's contact.
    pub stop: usize,
}

/// What a broken fuse freed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Freed {
    /// A fuse box's edge beam, with its seat and stop.
    Edge(FreedParts),
    /// A fuse element's beam (1 to `Nc`), gone out of the plane, the
    /// closing travel the joint gained and the elastic energy its contacts
    /// still held as it left.
    Beam {
        /// Which center beam.
        beam: usize,
        /// The travel, its width \[m\].
        room: f64,
        /// The energy \[J\].
        energy: f64,
    },
}

/// An observer of a run whose joints may have fuses: it says when one
/// broke, and goes on watching in the broken system.
pub trait FuseObserver: Observer {
    /// A joint (index into [`JointModel::joints`]) whose fuse broke at the
    /// end of the last step, if one did (taken: each is given once; none
    /// when the observer stopped the run for another reason).
    fn take_break(&mut self) -> Option<usize>;
    /// The run goes on in `asm`, the system with the fuses broken so far:
    /// `freed` says, for each of their joints (indices into
    /// [`JointModel::joints`], in the order they broke), what its fuse freed.
    fn resumed(&mut self, asm: &Assembly, freed: &[(usize, Freed)]) -> Result<(), ModelError>;
}

/// Runs `sim`, the intact system of `model`, to `t_end` \[s\] with its
/// joints' fuses armed: at each break the run resumes in the broken
/// system (a fuse element's contacts opened first), with the integrator
/// options `options`. Returns the solver at the end and whether it got
/// there (false: `observer` stopped it).
pub fn run_with_fuses(
    model: &JointModel,
    mut sim: Radau5,
    options: &IntegratorOptions,
    t_end: f64,
    observer: &mut dyn FuseObserver,
) -> Result<(Radau5, bool), ModelError> {
    let fuses: Vec<Option<&Fuse>> = model.joints().map(|j| j.fuse.as_ref()).collect();
    for fuse in fuses.iter().flatten() {
        sim.set_force_threshold(fuse.threshold_contacts(), fuse.break_force())?;
    }
    // (each broken fuse's joint, and the elastic energy its contacts held
    // as a fuse element's beam left)
    let mut broken = Vec::new();
    loop {
        if sim.run(t_end, observer)? {
            return Ok((sim, true));
        }
        let before = broken.len();
        while let Some(k) = observer.take_break() {
            let energy = match fuses.get(k).copied().flatten() {
                Some(Fuse::Element(e)) => sim.release_contacts(&e.released)?,
                Some(Fuse::Box(_)) => 0.0,
                None => continue,
            };
            broken.push((k, energy));
        }
        if broken.len() == before {
            return Ok((sim, false));
        }
        let (sys, freed) = broken_system(model, &broken);
        let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default())?);
        sim = Radau5::resume(asm.clone(), options.clone(), &sim)?;
        observer.resumed(&asm, &freed)?;
    }
}

/// The system of `model` with the fuses of its joints `broken` (indices
/// into [`JointModel::joints`], in the order they broke, each with the
/// elastic energy \[J\] its contacts held as a fuse element's beam left)
/// broken, in which
/// the run resumes ([`quakejoint_solver::Radau5::resume`]): a fuse box
/// appends its freed edge beam and that beam's elements after everything
/// else and moves center beam 1's contacts onto it; a fuse element's
/// contacts become its neighbours' across the merged cell and contacts that
/// never close. Returns the system and, for each broken fuse's joint, what
/// it freed.
pub fn broken_system(model: &JointModel, broken: &[(usize, f64)]) -> (System, Vec<(usize, Freed)>) {
    let mut sys = model.system.clone();
    let joints: Vec<&JointModel> = model.joints().collect();
    if joints.len() == 1 {
        // (one joint: its bodies are a group, apart from the freed beam's
        // friction)
        let j = joints[0];
        let slider = j.link.as_ref().map(|l| l.slider);
        for &b in j.center_beams.iter().chain(&j.supports).chain(j.bearings.iter().flatten()).chain(&slider) {
            sys.set_group(b, 0);
        }
    }
    let mut contacts = sys.forces().iter().filter(|(_, f)| matches!(f, ForceElement::Contact(_))).count();
    let mut freed = Vec::with_capacity(broken.len());
    for &(k, energy) in broken {
        let Some(jm) = joints.get(k) else { continue };
        match &jm.fuse {
            Some(Fuse::Box(fuse)) => {
                let parts = free_edge_beam(&mut sys, fuse, jm.sign, contacts);
                contacts += 2;
                freed.push((k, Freed::Edge(parts)));
            }
            Some(Fuse::Element(e)) => {
                for (id, c) in &e.replaced {
                    *sys.force_mut(*id) = ForceElement::Contact(c.clone());
                }
                freed.push((k, Freed::Beam { beam: e.beam, room: e.room, energy }));
            }
            None => {}
        }
    }
    (sys, freed)
}

/// Frees `fuse`'s edge beam in `sys` (a joint turned by `sign`, `contacts`
/// the system's contacts so far): the beam, its friction, lift, seat and
/// stop, and center beam 1's contacts on it.
fn free_edge_beam(sys: &mut System, fuse: &FuseBox, sign: f64, contacts: usize) -> FreedParts {
    sys.add_to_group(fuse.group);
    let body = Body::new(format!("{}edge beam (fuse broken)", fuse.prefix), fuse.mass, 1.0, [0.0; 3]);
    let edge = sys.add_body(crate::generator::turned(body.only(&[Coord::X]), sign));
    sys.add_to_group(NO_GROUP);
    for &id in &fuse.contacts {
        if let ForceElement::Contact(c) = sys.force_mut(id) {
            c.base = edge;
        }
    }
    let named = |what: &str| format!("{}fuse {what}", fuse.prefix);
    if fuse.resistance > 0.0 {
        sys.add_force_named(
            named("friction"),
            ForceElement::Friction(Friction {
                slider: edge,
                point: [0.0, 0.0],
                base: BodyId::GROUND,
                mu: 1.0,
                normal_force: fuse.resistance,
                surfaces: 1.0,
                v_eps: fuse.v_eps,
                law: fuse.friction_law,
            }),
        );
    }
    if fuse.lift != 0.0 {
        sys.add_force_named(
            named("ramp lift"),
            ForceElement::AppliedLoad(AppliedLoad {
                body: edge,
                point: [0.0, 0.0],
                fx: TimeFunction::Constant(fuse.lift),
                fy: TimeFunction::Constant(0.0),
                torque: TimeFunction::Constant(0.0),
            }),
        );
    }
    // the seat (no travel toward the deck) and the stop after the stroke
    for (what, edge_point, edge_normal) in [("seat", 0.0, -1.0), ("stop", -fuse.stroke, 1.0)] {
        sys.add_force_named(
            named(what),
            ForceElement::Contact(Contact {
                body: edge,
                point: [0.0, 0.0],
                base: BodyId::GROUND,
                edge_point: [edge_point, 0.0],
                edge_normal: [edge_normal, 0.0],
                law: fuse.law,
                reduced_mass: None,
            }),
        );
    }
    FreedParts { edge, seat: contacts, stop: contacts + 1 }
}

/// What a joint's fuse did in a run.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FuseResult {
    /// What kind of fuse (a fuse element has no stroke: its stroke's
    /// values are NaN in every output).
    pub kind: FuseKind,
    /// A fuse element's beam, 1 to `Nc` (0 for a box).
    pub beam: usize,
    /// Whether it broke.
    pub broke: bool,
    /// When \[s\] (NaN: it did not).
    pub break_time: f64,
    /// The closing force on the edge beam when it broke \[N\] (NaN: it did
    /// not).
    pub break_force: f64,
    /// The farthest the freed edge beam travelled toward the abutment \[m\].
    pub stroke_used: f64,
    /// Where it rests at the end of the run, from its seat toward the
    /// abutment \[m\]: the joint must be reset by this much.
    pub residual_offset: f64,
    /// Whether it reached the box's stop (the stroke was exhausted: the
    /// joint pushes the abutment again through the stop).
    pub stroke_exhausted: bool,
    /// A box: the energy the freed beam's friction dissipated; an
    /// element: the elastic energy its beam's contacts still held as it
    /// left \[J\].
    pub energy: f64,
}

/// A fuse's values in every output (a joint's `/joints/<k>`, and the
/// first joint's as the run's fields), in the order of
/// [`FuseResult::values`]; NaN for a joint without a fuse.
pub const FUSE_FIELDS: [Described; 7] = [
    described("fuse_broken", "1", "1 if its fuse broke, 0 if not (NaN without `[joint.fuse]`, as every `fuse_` value)"),
    described("fuse_break_time", "s", "when its fuse broke (NaN: it did not)"),
    described("fuse_break_force", "N", "the closing force on the edge beam (a fuse element: on its beam) when its fuse broke (the break force to within the step's error)"),
    described("fuse_stroke_used", "m", "the farthest its freed edge beam travelled toward the abutment (NaN for a fuse element, as its other stroke values)"),
    described("fuse_residual_offset", "m", "where its freed edge beam rests at the end, from its seat toward the abutment: the joint must be reset by this much (a lower bound where a ramp holds it by friction alone: the regularised friction lets it creep back, docs/model.md)"),
    described("fuse_stroke_exhausted", "1", "1 if its freed edge beam reached the fuse box's stop (the joint pushes the abutment again through it), 0 if not"),
    described("fuse_energy", "J", "the energy its freed edge beam's friction dissipated (apart from `friction_energy`); a fuse element: the elastic energy its beam's contacts held as it left (apart from `contact_energy`)"),
];

impl FuseResult {
    /// A fuse element that left the plane: its beam (1 to `Nc`) and when
    /// \[s\] (none for a box or an element that held).
    pub fn released(&self) -> Option<(usize, f64)> {
        (self.kind == FuseKind::Element && self.broke).then_some((self.beam, self.break_time))
    }

    /// The values of [`FUSE_FIELDS`] for a joint's fuse (NaN without one).
    pub fn values(fuse: Option<&FuseResult>) -> [f64; 7] {
        let Some(f) = fuse else { return [f64::NAN; 7] };
        let flag = |b: bool| f64::from(u8::from(b));
        let stroke = |x: f64| if f.kind == FuseKind::Element { f64::NAN } else { x };
        [
            flag(f.broke),
            f.break_time,
            f.break_force,
            stroke(f.stroke_used),
            stroke(f.residual_offset),
            stroke(flag(f.stroke_exhausted)),
            f.energy,
        ]
    }
}

/// A joint's fuse watched in a run: the break, then a fuse box's freed
/// beam (a fuse element's beam is gone: nothing more to watch).
#[derive(Debug, Clone)]
pub struct FuseWatch {
    /// The first of the contacts whose force breaks it (the event's).
    first_contact: usize,
    /// The freed beam's resistances \[N\].
    lift: f64,
    resistance: f64,
    v_eps: f64,
    law: FrictionLaw,
    /// Broken at the end of the last step, not yet taken by the run.
    pending: bool,
    /// The freed beam's x coordinate and its seat's and stop's contacts.
    freed: Option<(usize, FreedParts)>,
    /// Scratch: every contact's state.
    values: Vec<ContactValue>,
    /// What it did so far (its energy is the run's to fill in, from the
    /// fuse's group of bodies).
    pub result: FuseResult,
}

impl FuseWatch {
    /// The watch of `model`'s fuse (none without one).
    pub fn new(model: &JointModel) -> Option<Self> {
        let fuse = model.fuse.as_ref()?;
        let unbroken = FuseResult { break_time: f64::NAN, break_force: f64::NAN, ..FuseResult::default() };
        let watch = Self {
            first_contact: fuse.threshold_contacts()[0],
            lift: 0.0,
            resistance: 0.0,
            v_eps: 1.0,
            law: FrictionLaw::Smooth,
            pending: false,
            freed: None,
            values: Vec::new(),
            result: unbroken,
        };
        Some(match fuse {
            Fuse::Box(f) => {
                Self { lift: f.lift, resistance: f.resistance, v_eps: f.v_eps, law: f.friction_law, ..watch }
            }
            Fuse::Element(e) => {
                Self { result: FuseResult { kind: FuseKind::Element, beam: e.beam, ..unbroken }, ..watch }
            }
        })
    }

    /// Looks at a step's events: whether the fuse broke at its end (then
    /// the run must stop and resume in the broken system), and whether the
    /// freed beam reached its stop.
    pub fn step(&mut self, events: &[quakejoint_solver::ContactEvent]) -> bool {
        for e in events {
            match e.kind {
                quakejoint_solver::ContactEventKind::Threshold { force } if e.contact == self.first_contact => {
                    self.result.broke = true;
                    self.result.break_time = e.time;
                    self.result.break_force = force;
                    self.pending = true;
                }
                quakejoint_solver::ContactEventKind::Onset { .. }
                    if self.freed.is_some_and(|(_, p)| p.stop == e.contact) =>
                {
                    self.result.stroke_exhausted = true;
                }
                _ => {}
            }
        }
        self.pending
    }

    /// Whether it broke at the end of the last step (once).
    pub fn take_pending(&mut self) -> bool {
        std::mem::take(&mut self.pending)
    }

    /// Watches the freed beam in the broken system (`coord`: its x).
    pub fn freed(&mut self, coord: usize, parts: FreedParts) {
        self.freed = Some((coord, parts));
    }

    /// A fuse element's beam left, its contacts holding `energy` \[J\].
    pub fn released(&mut self, energy: f64) {
        self.result.energy = energy;
    }

    /// At a sample: the freed beam's travel, and its push on the abutment
    /// along x (the reactions of its friction, lift, seat and stop; none
    /// while intact) \[N\].
    pub fn sample(
        &mut self,
        asm: &quakejoint_solver::Assembly,
        ws: &mut quakejoint_solver::Workspace,
        q: &[f64],
        v: &[f64],
    ) -> Option<f64> {
        let (c, parts) = self.freed?;
        let (x, vx) = (q[c], v[c]);
        self.result.stroke_used = self.result.stroke_used.max(-x);
        self.result.residual_offset = -x;
        self.values.resize(asm.contact_count(), ContactValue::default());
        asm.contacts(ws, q, v, &mut self.values);
        let force = |i: usize| if self.values[i].closed { self.values[i].force } else { 0.0 };
        if self.values[parts.stop].penetration > 0.0 {
            self.result.stroke_exhausted = true;
        }
        let phi = match self.law {
            FrictionLaw::Linear => vx / vx.abs().max(self.v_eps),
            FrictionLaw::Smooth => vx / vx.hypot(self.v_eps),
        };
        Some(self.resistance * phi - self.lift + force(parts.seat) - force(parts.stop))
    }
}
