//! Pounding: what the contacts between the beams do during a run. The
//! integrator locates every onset and release ([`quakejoint_solver::ContactEvent`]);
//! this counts the impacts and follows the contact forces and penetrations
//! at every accepted step (an impact lasts milliseconds, less than a record's
//! time step) and at the output times (the force of the closed joint on the
//! deck enters the deck's force balance there).

use quakejoint_solver::{Assembly, ContactEventKind, ContactValue, StateBuffer, StepView, Workspace};

use crate::generator::{ContactPlace, JointModel};
use crate::validity::Monitor;
use crate::watch::DENSE_OUTPUT;

/// Slowest approach that counts as an impact [m/s]: slower touches (a
/// beam settling against its neighbour after an impact, in bounces of
/// mm/s, as many as the tolerances resolve) are in the impact list but not
/// counted. The Hertz law's damping treats them as this fast
/// ([`quakejoint_solver::MIN_APPROACH_SPEED`]).
pub const IMPACT_SPEED: f64 = quakejoint_solver::MIN_APPROACH_SPEED;

/// The joint's demands from pounding over a run (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pounding {
    /// Impacts: contact onsets at [`IMPACT_SPEED`] or faster, all beam ends
    /// counted.
    pub impacts: u64,
    /// Largest force of one contact (one beam end) \[N\].
    pub peak_contact_force: f64,
    /// Where it acted (None without impacts).
    pub peak_contact_place: Option<ContactPlace>,
    /// When \[s\].
    pub peak_contact_time: f64,
    /// Energy dissipated by the contacts \[J\] (inside the energy balance).
    pub contact_energy: f64,
    /// Largest force of the closed joint on the deck through the deck's
    /// edge beam \[N\].
    pub peak_deck_contact_force: f64,
    /// Deepest penetration of a contact \[m\].
    pub max_penetration: f64,
    /// Fastest approach of two faces at a contact's onset \[m/s\] (NaN
    /// where the joint does not track its impacts: a link element).
    pub max_impact_speed: f64,
}

impl Default for Pounding {
    fn default() -> Self {
        Self {
            impacts: 0,
            peak_contact_force: 0.0,
            peak_contact_place: None,
            peak_contact_time: f64::NAN,
            contact_energy: 0.0,
            peak_deck_contact_force: 0.0,
            max_penetration: 0.0,
            max_impact_speed: 0.0,
        }
    }
}

impl Pounding {
    /// Not computed (the bridge alone): every number NaN.
    pub fn not_computed() -> Self {
        Self {
            impacts: 0,
            peak_contact_force: f64::NAN,
            peak_contact_place: None,
            peak_contact_time: f64::NAN,
            contact_energy: f64::NAN,
            peak_deck_contact_force: f64::NAN,
            max_penetration: f64::NAN,
            max_impact_speed: f64::NAN,
        }
    }
}

/// One impact: a contact's onset.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Impact {
    /// When \[s\].
    pub time: f64,
    /// Where.
    pub place: ContactPlace,
    /// Approach speed [m/s].
    pub speed: f64,
}

/// Points inside a step at which the contacts are evaluated while one is
/// closed.
pub const INTERIOR: usize = 3;

/// Golden-section steps locating the run's peak contact force within a step
/// (the bracket shrinks to 0.618^20, about 1e-4 of it).
const REFINE: usize = 20;

/// Follows the contacts of a running joint.
#[derive(Debug, Clone)]
pub(crate) struct ContactWatch {
    places: Vec<ContactPlace>,
    /// The sub-gap at the deck (Nc).
    deck_gap: usize,
    values: Vec<ContactValue>,
    /// The solver's number of the joint's first contact.
    first: usize,
    /// Every contact of the system, when other joints have some (else
    /// empty: `values` are all of them).
    all: Vec<ContactValue>,
    /// Interpolated positions, velocities and multipliers.
    scratch: Option<StateBuffer>,
    /// Largest contact force across each sub-gap since the last output
    /// time [N] (an impact is shorter than a record's time step).
    interval_peak: Vec<f64>,
    /// Scratch: the force across each sub-gap at one instant [N].
    per_gap: Vec<f64>,
    pub result: Pounding,
    /// Every impact, when asked for (with the histories).
    pub log: Option<Vec<Impact>>,
}

impl ContactWatch {
    /// The watch of `model`'s contacts (None when it has none), among the
    /// `total` contacts of the system.
    pub fn new(model: &JointModel, total: usize) -> Option<Self> {
        if model.contacts.is_empty() {
            return None;
        }
        Some(Self {
            places: model.contacts.clone(),
            deck_gap: model.center_beams.len(),
            values: vec![ContactValue::default(); model.contacts.len()],
            first: model.first_contact,
            all: if total > model.contacts.len() { vec![ContactValue::default(); total] } else { Vec::new() },
            scratch: None,
            interval_peak: vec![0.0; model.center_beams.len() + 1],
            per_gap: vec![0.0; model.center_beams.len() + 1],
            result: Pounding::default(),
            log: None,
        })
    }

    /// After an accepted step: counts the impacts and takes the forces and
    /// penetrations at the step's end and, while a contact is closed, at
    /// [`INTERIOR`] points inside the step (an impact's peak falls between
    /// step ends).
    pub fn step(&mut self, view: &mut StepView<'_>, mut monitor: Option<&mut Monitor>) {
        let own = self.first..self.first + self.places.len();
        for e in view.events.iter().filter(|e| own.contains(&e.contact)) {
            if let ContactEventKind::Onset { speed } = e.kind {
                self.result.impacts += u64::from(speed >= IMPACT_SPEED);
                self.result.max_impact_speed = self.result.max_impact_speed.max(speed);
                if let Some(log) = &mut self.log {
                    log.push(Impact { time: e.time, place: self.places[e.contact - self.first], speed });
                }
            }
        }
        self.load(view.assembly, view.workspace, view.q, view.v);
        let closed = self.values.iter().any(|c| c.closed);
        let peak_before = self.result.peak_contact_force;
        self.take(view.t, monitor.as_deref_mut());
        if closed && view.t > view.t_prev {
            let mut s = self.scratch.take().unwrap_or_else(|| StateBuffer::new(view.assembly));
            let dt = (view.t - view.t_prev) / (INTERIOR + 1) as f64;
            for k in 1..=INTERIOR {
                let t = view.t_prev + dt * k as f64;
                view.state_at(t, &mut s).expect(DENSE_OUTPUT);
                self.load(view.assembly, view.workspace, &s.q, &s.v);
                self.take(t, monitor.as_deref_mut());
            }
            if self.result.peak_contact_force > peak_before {
                // the run's peak is in this step: located on the dense output
                let t0 = self.result.peak_contact_time;
                let bracket = ((t0 - dt).max(view.t_prev), (t0 + dt).min(view.t));
                self.refine_peak(view, bracket, &mut s);
            }
            self.scratch = Some(s);
        }
    }

    /// Golden-section search for the largest force of the peak's contact
    /// within `bracket` (around the best sample of the step, its end
    /// included): a sampled impact's peak is otherwise low by about
    /// `(pi dt / duration)^2 / 8`. (The deck's force from the closed joint,
    /// a sum over contacts, and the per-gap histories stay sampled: they may
    /// fall short of the located peak by that much.)
    fn refine_peak(&mut self, view: &mut StepView<'_>, bracket: (f64, f64), s: &mut StateBuffer) {
        let Some(place) = self.result.peak_contact_place else { return };
        let Some(i) = self.places.iter().position(|p| *p == place) else { return };
        let mut force_at = |t: f64| {
            view.state_at(t, s).expect(DENSE_OUTPUT);
            self.load(view.assembly, view.workspace, &s.q, &s.v);
            let c = self.values[i];
            if c.closed {
                c.force
            } else {
                0.0
            }
        };
        const INV_PHI: f64 = 0.618_033_988_749_894_8;
        let (mut a, mut b) = bracket;
        let (mut x1, mut x2) = (b - INV_PHI * (b - a), a + INV_PHI * (b - a));
        let (mut f1, mut f2) = (force_at(x1), force_at(x2));
        for _ in 0..REFINE {
            if f1 > f2 {
                (b, x2, f2) = (x2, x1, f1);
                x1 = b - INV_PHI * (b - a);
                f1 = force_at(x1);
            } else {
                (a, x1, f1) = (x1, x2, f2);
                x2 = a + INV_PHI * (b - a);
                f2 = force_at(x2);
            }
        }
        let (t, f) = if f1 > f2 { (x1, f1) } else { (x2, f2) };
        if f > self.result.peak_contact_force {
            self.result.peak_contact_force = f;
            self.result.peak_contact_time = t;
        }
    }

    /// The joint's contacts' states at `(q, v)` into `self.values`.
    fn load(&mut self, asm: &Assembly, ws: &mut Workspace, q: &[f64], v: &[f64]) {
        if self.all.is_empty() {
            asm.contacts(ws, q, v, &mut self.values);
        } else {
            asm.contacts(ws, q, v, &mut self.all);
            let n = self.values.len();
            self.values.copy_from_slice(&self.all[self.first..self.first + n]);
        }
    }

    /// The peaks of the contact states in `self.values` at time `t`.
    fn take(&mut self, t: f64, monitor: Option<&mut Monitor>) {
        let r = &mut self.result;
        let mut deepest = (0.0f64, 0usize);
        for (i, c) in self.values.iter().enumerate() {
            if !c.closed {
                continue;
            }
            if c.force > r.peak_contact_force {
                r.peak_contact_force = c.force;
                r.peak_contact_place = Some(self.places[i]);
                r.peak_contact_time = t;
            }
            if c.penetration > deepest.0 {
                deepest = (c.penetration, i);
            }
        }
        r.max_penetration = r.max_penetration.max(deepest.0);
        if let Some(m) = monitor {
            m.contact(t, deepest.0, deepest.1);
        }
        self.gap_forces();
        for (peak, f) in self.interval_peak.iter_mut().zip(&self.per_gap) {
            *peak = peak.max(*f);
        }
        let deck = self.deck_force_of_values();
        self.result.peak_deck_contact_force = self.result.peak_deck_contact_force.max(deck);
    }

    /// Each sub-gap's contact force (both ends) in `self.values` into
    /// `self.per_gap`.
    fn gap_forces(&mut self) {
        self.per_gap.iter_mut().for_each(|x| *x = 0.0);
        for (c, p) in self.values.iter().zip(&self.places) {
            if c.closed {
                self.per_gap[p.gap] += c.force;
            }
        }
    }

    /// The force of the joint on the deck through its edge beam at an
    /// output time's state (x, pushing the deck open) [N], and into
    /// `per_gap`, if given, the largest contact force across each sub-gap
    /// (both ends) since the last output time, this one included.
    pub fn at(&mut self, asm: &Assembly, ws: &mut Workspace, q: &[f64], v: &[f64], per_gap: Option<&mut [f64]>) -> f64 {
        self.load(asm, ws, q, v);
        self.gap_forces();
        if let Some(out) = per_gap {
            for ((o, peak), f) in out.iter_mut().zip(&mut self.interval_peak).zip(&self.per_gap) {
                *o = peak.max(*f);
                *peak = 0.0;
            }
        }
        let deck = self.deck_force_of_values();
        self.result.peak_deck_contact_force = self.result.peak_deck_contact_force.max(deck);
        deck
    }

    /// Goes on in a system with more bodies (a fuse broke): its scratch
    /// state is made again at the next step.
    pub fn resized(&mut self) {
        self.scratch = None;
    }

    /// The abutment-side contacts push an adjacent segment's deck along -x
    /// (their edge normal is +x on a deck that does not turn), from the
    /// values of the last [`ContactWatch::at`].
    pub(crate) fn far_push(&self) -> f64 {
        -self.values.iter().zip(&self.places).filter(|(c, p)| c.closed && p.gap == 0).map(|(c, _)| c.force).sum::<f64>()
    }

    /// The deck's edge contacts push the deck along +x (their edge normal is
    /// -x on a deck that does not turn).
    fn deck_force_of_values(&self) -> f64 {
        self.values
            .iter()
            .zip(&self.places)
            .filter(|(c, p)| c.closed && p.gap == self.deck_gap)
            .map(|(c, _)| c.force)
            .sum()
    }
}
