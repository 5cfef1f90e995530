//! A run whose joints have fuses (`crate::fuse`): the break located as an
//! event, the run resumed in the broken system ([`run_with_fuses`],
//! [`broken_system`]), and what each fuse did ([`FuseWatch`],
//! [`FuseResult`]).

use std::sync::Arc;

use quakejoint_solver::{
    AppliedLoad, Assembly, AssemblyOptions, Body, BodyId, Contact, ContactValue, Coord, ForceElement, Friction,
    FrictionLaw, IntegratorOptions, Observer, Radau5, System, TimeFunction, NO_GROUP,
};

use crate::described::{described, Described};
use crate::error::ModelError;
use crate::generator::JointModel;

/// Where a broken fuse's parts are in the broken system.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FreedParts {
    /// The freed edge beam.
    pub edge: BodyId,
    /// The solver's number of its seat's contact.
    pub seat: usize,
    /// The solver's number of its stop's contact.
    pub stop: usize,
}

/// An observer of a run whose joints may have fuses: it says when one
/// broke, and goes on watching in the broken system.
pub trait FuseObserver: Observer {
    /// A joint (index into [`JointModel::joints`]) whose fuse broke at the
    /// end of the last step, if one did (taken: each is given once; none
    /// when the observer stopped the run for another reason).
    fn take_break(&mut self) -> Option<usize>;
    /// The run goes on in `asm`, the system with the fuses of `broken`
    /// broken (in that order), their parts where `parts` says.
    fn resumed(&mut self, asm: &Assembly, broken: &[usize], parts: &[FreedParts]) -> Result<(), ModelError>;
}

/// Runs `sim`, the intact system of `model`, to `t_end` \[s\] with its
/// joints' fuses armed: at each break the run resumes in the broken
/// system, with the integrator options `options`. Returns the solver at the
/// end and whether it got there (false: `observer` stopped it).
pub fn run_with_fuses(
    model: &JointModel,
    mut sim: Radau5,
    options: &IntegratorOptions,
    t_end: f64,
    observer: &mut dyn FuseObserver,
) -> Result<(Radau5, bool), ModelError> {
    for fuse in model.joints().filter_map(|j| j.fuse.as_ref()) {
        sim.set_force_threshold(&fuse.contact_numbers, fuse.break_force)?;
    }
    let mut broken = Vec::new();
    loop {
        if sim.run(t_end, observer)? {
            return Ok((sim, true));
        }
        let before = broken.len();
        while let Some(k) = observer.take_break() {
            broken.push(k);
        }
        if broken.len() == before {
            return Ok((sim, false));
        }
        let (sys, parts) = broken_system(model, &broken);
        let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default())?);
        sim = Radau5::resume(asm.clone(), options.clone(), &sim)?;
        observer.resumed(&asm, &broken, &parts)?;
    }
}

/// The system of `model` with the fuses of its joints `broken` (indices
/// into [`JointModel::joints`], in the order they broke) broken: each
/// appends its freed edge beam and that beam's elements after everything
/// else, and moves center beam 1's contacts onto it, so that the run
/// resumes in it ([`quakejoint_solver::Radau5::resume`]). Returns the
/// system and where each broken fuse's parts are.
pub fn broken_system(model: &JointModel, broken: &[usize]) -> (System, Vec<FreedParts>) {
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
    let mut parts = Vec::with_capacity(broken.len());
    for &k in broken {
        let (jm, fuse) = match joints.get(k).and_then(|j| j.fuse.as_ref().map(|f| (*j, f))) {
            Some(x) => x,
            None => continue,
        };
        sys.add_to_group(fuse.group);
        let body = Body::new(format!("{}edge beam (fuse broken)", fuse.prefix), fuse.mass, 1.0, [0.0; 3]);
        let edge = sys.add_body(crate::generator::turned(body.only(&[Coord::X]), jm.sign));
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
        parts.push(FreedParts { edge, seat: contacts, stop: contacts + 1 });
        contacts += 2;
    }
    (sys, parts)
}

/// What a joint's fuse did in a run.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FuseResult {
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
    /// The energy the freed beam's friction dissipated \[J\].
    pub energy: f64,
}

/// A fuse's values in every output (a joint's `/joints/<k>`, and the
/// first joint's as the run's fields), in the order of
/// [`FuseResult::values`]; NaN for a joint without a fuse.
pub const FUSE_FIELDS: [Described; 7] = [
    described("fuse_broken", "1", "1 if its fuse broke, 0 if not (NaN without `[joint.fuse]`, as every `fuse_` value)"),
    described("fuse_break_time", "s", "when its fuse broke (NaN: it did not)"),
    described("fuse_break_force", "N", "the closing force on the edge beam when its fuse broke (the break force to within the step's error)"),
    described("fuse_stroke_used", "m", "the farthest its freed edge beam travelled toward the abutment"),
    described("fuse_residual_offset", "m", "where its freed edge beam rests at the end, from its seat toward the abutment: the joint must be reset by this much (a lower bound where a ramp holds it by friction alone: the regularised friction lets it creep back, docs/model.md)"),
    described("fuse_stroke_exhausted", "1", "1 if its freed edge beam reached the fuse box's stop (the joint pushes the abutment again through it), 0 if not"),
    described("fuse_energy", "J", "the energy its freed edge beam's friction dissipated (apart from `friction_energy`)"),
];

impl FuseResult {
    /// The values of [`FUSE_FIELDS`] for a joint's fuse (NaN without one).
    pub fn values(fuse: Option<&FuseResult>) -> [f64; 7] {
        let Some(f) = fuse else { return [f64::NAN; 7] };
        let flag = |b: bool| f64::from(u8::from(b));
        [
            flag(f.broke),
            f.break_time,
            f.break_force,
            f.stroke_used,
            f.residual_offset,
            flag(f.stroke_exhausted),
            f.energy,
        ]
    }
}

/// A joint's fuse watched in a run: the break, then the freed beam.
#[derive(Debug, Clone)]
pub struct FuseWatch {
    /// The joint's first contact on the edge beam (the break event's).
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
        let f = model.fuse.as_ref()?;
        Some(Self {
            first_contact: f.contact_numbers[0],
            lift: f.lift,
            resistance: f.resistance,
            v_eps: f.v_eps,
            law: f.friction_law,
            pending: false,
            freed: None,
            values: Vec::new(),
            result: FuseResult { break_time: f64::NAN, break_force: f64::NAN, ..FuseResult::default() },
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
