//! What a coupled run watches at every accepted step ([`EarthquakeObserver`],
//! one per joint): the record's samples (the deck's and the joint's peaks,
//! the histories), the sub-gaps and the validity limits between them, the
//! limits' first crossings on the dense output, the contacts, a link
//! element's state and a modal bridge's points.

use std::time::Instant as Clock;

use quakejoint_solver::{Assembly, BodyId, ConstraintId, Observer, StepView, TimeSeries};

use super::Histories;
use crate::error::ModelError;
use crate::generator::{Bridge, JointModel};
use crate::pounding::{ContactWatch, Pounding};
use crate::run::fuse::Freed;
use crate::validity::Monitor;
use crate::watch::{Gaps, DENSE_OUTPUT};

/// Longest interval between two checks of the sub-gaps and the validity
/// limits \[s\]: 5 ms, the time step of most records; a beam closing a sub-gap
/// at 1 m/s moves 5 mm in it.
pub const CHECK_INTERVAL: f64 = 0.005;

/// The tolerance to which the first crossing of a validity limit is
/// located in time \[s\].
pub const CROSSING_TOLERANCE: f64 = 1e-6;

/// A running maximum of |x| with its time.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Peak {
    pub(super) value: f64,
    pub(super) time: f64,
}

impl Peak {
    fn update(&mut self, x: f64, t: f64) {
        if x.abs() > self.value {
            self.value = x.abs();
            self.time = t;
        }
    }
}

/// Evaluates the reported quantities at the output times.
pub(super) struct EarthquakeObserver {
    pub(super) deck: usize,
    /// The deck's y coordinate, when it moves across.
    pub(super) deck_y: Option<usize>,
    /// The adjacent segment's deck: its x coordinate and body.
    pub(super) far: Option<(usize, BodyId)>,
    pub(super) abutment_links: Vec<ConstraintId>,
    /// The support beams, one per link of `abutment_links`.
    pub(super) supports: Vec<BodyId>,
    /// The joint's force on its abutment side (its links and the
    /// abutment's edge-beam contacts).
    pub(super) abutment_force: Peak,
    pub(super) deck_body: BodyId,
    pub(super) boxes: Vec<ConstraintId>,
    pub(super) bridge: Bridge,
    /// The modes, when the bridge is given by them.
    pub(super) modal: Option<crate::modal::ModalDeck>,
    /// Scratch: the modes' accelerations at a sample, and the forces the
    /// joints' ends pass to them.
    pub(super) modal_acc: Vec<f64>,
    pub(super) modal_forces: Vec<(usize, f64)>,
    pub(super) ground: TimeSeries,
    /// +1, or -1 for a joint turned half a turn: its own x is the bridge's -x.
    pub(super) sign: f64,
    /// The ground's acceleration across, if a record acts across.
    pub(super) ground_y: Option<TimeSeries>,
    pub(super) dt: f64,
    /// The output times: the record's samples after the first.
    pub(super) outputs: quakejoint_solver::OutputTimes,
    pub(super) sa: Peak,
    pub(super) sd: Peak,
    pub(super) sv: Peak,
    pub(super) joint_force: Peak,
    /// Across the bridge: Sa, Sd, Sv and the joint's force.
    pub(super) across: [Peak; 4],
    /// A modal bridge's points (displacement and absolute acceleration) and
    /// base shear, watched by the first joint's observer only.
    pub(super) points: Vec<[Peak; 2]>,
    pub(super) base_shear: Peak,
    /// The adjacent segment: Sa, Sd, the joint's force on it and the decks'
    /// relative displacement.
    pub(super) far_peaks: [Peak; 4],
    pub(super) bushing: f64,
    pub(super) friction: f64,
    /// Its own group of bodies when a run has several joints (its peak
    /// forces and friction energy apart from the others'), with scratch
    /// for every group's peak forces, and its own peaks.
    pub(super) group: Option<usize>,
    pub(super) group_extremes: Vec<quakejoint_solver::ForceExtremes>,
    /// The groups that are joints' (the fuses' freed beams' come after).
    pub(super) joint_groups: usize,
    /// Its fuse, if it has one.
    pub(super) fuse: Option<crate::run::fuse::FuseWatch>,
    /// Scratch: every group's friction power at a sample \[W\].
    pub(super) group_powers: Vec<f64>,
    pub(super) own: quakejoint_solver::ForceExtremes,
    pub(super) gaps: Option<Gaps>,
    pub(super) contacts: Option<ContactWatch>,
    /// The link element, its node's and abutment's x coordinates, and what
    /// is watched of it.
    pub(super) link: Option<LinkObserver>,
    /// Scratch: contact force per sub-gap at a sample.
    pub(super) gap_forces: Vec<f64>,
    pub(super) histories: Option<Histories>,
    /// Interval of the sub-gap and validity checks between output times
    /// [s]: the record's time step divided into pieces of at most
    /// [`CHECK_INTERVAL`] (a coarse record must not hide a collision).
    pub(super) check_dt: f64,
    pub(super) checks: quakejoint_solver::OutputTimes,
    /// Each validity limit's excess at the last step's end \[m\]
    /// ([`Monitor::excesses`]; NaN before the first step).
    pub(super) excess: [f64; crate::validity::LIMITS],
    /// The run's start and wall-clock limit [s], checked as output samples
    /// are written too (a long free vibration is many samples per step).
    pub(super) deadline: Option<(Clock, f64)>,
    pub(super) out_of_time: bool,
    pub(super) monitor: Option<Monitor>,
    pub(super) last_report: f64,
    /// Scratch: the state at an output time or a check.
    pub(super) state: quakejoint_solver::StateBuffer,
}

impl EarthquakeObserver {
    pub(super) fn new(
        model: &JointModel,
        asm: &Assembly,
        ground: TimeSeries,
        dt: f64,
        histories: bool,
    ) -> Result<Self, ModelError> {
        let deck = asm
            .coordinate(model.deck, quakejoint_solver::Coord::X)
            .ok_or_else(|| ModelError::Geometry("the deck has no x coordinate".into()))?;
        let gaps = Gaps::new(model, asm)?;
        let mut contacts = ContactWatch::new(model, asm.contact_count());
        if let (true, Some(c)) = (histories, &mut contacts) {
            c.log = Some(Vec::new());
        }
        // (a link's cells open alike: one series stands for them all)
        let n_gaps = model.geometry.as_ref().map_or(usize::from(model.link.is_some()), |g| g.center_beams + 1);
        let histories = histories.then(|| Histories {
            center_beam_dx: vec![Vec::new(); model.center_beams.len()],
            subgaps: vec![Vec::new(); n_gaps],
            subgaps_wide: vec![Vec::new(); n_gaps],
            contact_force: vec![Vec::new(); if contacts.is_some() { n_gaps } else { 0 }],
            ..Histories::default()
        });
        let check_dt = dt / (dt / CHECK_INTERVAL).ceil().max(1.0);
        let grid = |dt: f64| {
            quakejoint_solver::OutputTimes::uniform(0.0, dt).map_err(|e| ModelError::Invalid {
                field: "record.dt".into(),
                value: dt.to_string(),
                reason: e.to_string(),
            })
        };
        Ok(Self {
            deck,
            deck_y: asm.coordinate(model.deck, quakejoint_solver::Coord::Y),
            far: model.far_deck.and_then(|b| asm.coordinate(b, quakejoint_solver::Coord::X).map(|c| (c, b))),
            abutment_links: model.abutment_links.clone(),
            supports: model.supports.clone(),
            abutment_force: Peak::default(),
            deck_body: model.deck,
            boxes: model.joist_boxes.clone(),
            bridge: model.bridge,
            modal: model.modal.clone(),
            modal_acc: Vec::new(),
            modal_forces: Vec::new(),
            ground,
            sign: model.sign,
            ground_y: None,
            dt,
            outputs: grid(dt)?,
            sa: Peak::default(),
            sd: Peak::default(),
            sv: Peak::default(),
            joint_force: Peak::default(),
            across: [Peak::default(); 4],
            points: Vec::new(),
            base_shear: Peak::default(),
            far_peaks: [Peak::default(); 4],
            bushing: 0.0,
            friction: 0.0,
            group: None,
            group_extremes: Vec::new(),
            joint_groups: 0,
            fuse: crate::run::fuse::FuseWatch::new(model),
            group_powers: Vec::new(),
            own: Default::default(),
            gaps,
            contacts,
            link: LinkObserver::new(model, asm),
            gap_forces: vec![0.0; n_gaps],
            histories,
            check_dt,
            checks: grid(check_dt)?,
            excess: [f64::NAN; crate::validity::LIMITS],
            deadline: None,
            out_of_time: false,
            monitor: None,
            last_report: 0.0,
            state: quakejoint_solver::StateBuffer::new(asm),
        })
    }

    /// Goes on watching in `asm`, the system with fuses broken: its scratch
    /// sized for it, its own group's peaks apart from a freed beam's
    /// friction, and, if its own fuse is among them, what it freed.
    pub(super) fn resumed(&mut self, asm: &Assembly, freed: Option<Freed>) -> Result<(), ModelError> {
        self.state = quakejoint_solver::StateBuffer::new(asm);
        if let Some(l) = &mut self.link {
            l.scratch = None;
        }
        if let Some(c) = &mut self.contacts {
            c.resized();
        }
        self.group_extremes = vec![Default::default(); asm.group_count()];
        if self.group.is_none() {
            // (one joint: its bodies are group 0 in the broken system)
            self.group = Some(0);
            self.joint_groups = 1;
            self.own = quakejoint_solver::ForceExtremes { bushing: self.bushing, friction: self.friction };
        }
        let Some(fuse) = &mut self.fuse else { return Ok(()) };
        match freed {
            Some(Freed::Edge(parts)) => {
                let coord = asm
                    .coordinate(parts.edge, quakejoint_solver::Coord::X)
                    .ok_or_else(|| ModelError::Geometry("the freed edge beam has no x coordinate".to_string()))?;
                fuse.freed(coord, parts);
                if let Some(l) = &mut self.link {
                    // (its cells now end at the freed edge beam)
                    l.abutment = Some(coord);
                }
                if let Some(g) = &mut self.gaps {
                    g.free_edge(coord);
                }
                if let Some(m) = &mut self.monitor {
                    m.free_edge();
                }
            }
            Some(Freed::Beam { beam, room, energy }) => {
                fuse.released(energy);
                if let Some(l) = &mut self.link {
                    // (its gap closes the beam's width later, one cell fewer
                    // in series; the joists keep the other cells where they
                    // were)
                    l.parts.gap += room;
                    l.in_series -= 1;
                }
                if let Some(g) = &mut self.gaps {
                    g.release_beam(beam - 1);
                }
                if let Some(m) = &mut self.monitor {
                    m.release_beam(beam, fuse.result.break_time);
                }
            }
            None => {}
        }
        Ok(())
    }

    /// The sub-gaps and the validity limits at time `t` (positions `q`).
    fn check(&mut self, t: f64, q: &[f64]) {
        if let Some(g) = &mut self.gaps {
            g.check(t, q, q[self.deck], self.monitor.as_mut());
        }
    }

    /// The times within the step at which a validity limit is first crossed,
    /// located on the dense output to [`CROSSING_TOLERANCE`] (the samples
    /// of the sub-gaps and the limits find the worst excess, but an excess
    /// between two samples, or where it began, only the root finding sees).
    fn locate_crossings(&mut self, view: &StepView<'_>) {
        let (Some(gaps), Some(monitor)) = (&mut self.gaps, &mut self.monitor) else { return };
        let deck = self.deck;
        let excess = |gaps: &mut Gaps, monitor: &mut Monitor, q: &[f64]| {
            gaps.fill(q, q[deck]);
            monitor.excesses(q, q[deck], &gaps.smallest, &gaps.largest)
        };
        // the step's end against the last one's: a limit crossed within
        // the step is located there (one crossing per step and limit; one
        // that goes and comes back within a step is the samples' to see)
        let end = excess(gaps, monitor, view.q);
        for (limit, &(now, _)) in end.iter().enumerate() {
            let before = std::mem::replace(&mut self.excess[limit], now);
            // (NaN: the first step, whose start the dense output gives)
            if before > 0.0 || now <= 0.0 {
                continue;
            }
            let root = view
                .locate_root(CROSSING_TOLERANCE, &mut self.state, |s| excess(gaps, monitor, &s.q)[limit].0)
                .expect(DENSE_OUTPUT);
            // (none: the dense output at the step's start, which differs from
            // the last end state by its projection, is beyond already)
            let t = root.map_or(view.t_prev, |r| r.t);
            let (e, place) = excess(gaps, monitor, &self.state.q)[limit];
            monitor.crossed(limit, t, e, place);
        }
    }

    /// The checks between the output times up to the step's end (none when
    /// the record's time step is already at most [`CHECK_INTERVAL`]), on the
    /// dense output.
    fn check_between(&mut self, view: &mut StepView<'_>) {
        if self.gaps.is_none() || self.check_dt >= self.dt {
            return;
        }
        while let Some(tk) = self.checks.next_in(view) {
            let mut state = std::mem::take(&mut self.state);
            view.sample(&tk, &mut state).expect(DENSE_OUTPUT);
            self.check(tk.t(), &state.q);
            self.state = state;
        }
    }

    /// Quantities at one output time.
    pub(super) fn sample(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        lam: &[f64],
        asm: &Assembly,
        ws: &mut quakejoint_solver::Workspace,
    ) {
        let (u, ud) = (q[self.deck], v[self.deck]);
        // the joint holds the deck through the joist boxes and, once closed,
        // pushes it through the deck's edge beam
        let pushed = match &mut self.contacts {
            Some(c) => c.at(asm, ws, q, v, Some(&mut self.gap_forces)),
            None => 0.0,
        };
        let reaction = asm.reaction_sum(ws, t, q, lam, &self.boxes, self.deck_body);
        let mut fj = reaction[0] + pushed;
        if !self.abutment_links.is_empty() {
            // the abutment's edge-beam contacts, or once its fuse broke the
            // freed edge beam's box
            let pushed = match self.fuse.as_mut().and_then(|f| f.sample(asm, ws, q, v)) {
                Some(push) => push,
                None => self.contacts.as_ref().map_or(0.0, |w| w.far_push()),
            };
            self.abutment_update(Instant { t, q, v, lam }, pushed, asm, ws);
        }
        if let Some(l) = &mut self.link {
            fj = l.update(t, q, v, asm, ws);
            // (its freed edge beam's travel)
            if let Some(f) = &mut self.fuse {
                f.sample(asm, ws, q, v);
            }
        }
        let b = self.bridge;
        // a modal deck end's absolute acceleration across, in the joint's y
        let (a_abs, modal_ay) = match self.modal.is_some() {
            true => self.modal_sample(Instant { t, q, v, lam }, asm, ws),
            false => ((-b.stiffness() * u - b.damper() * ud + fj) / b.mass, None),
        };
        if let (Some((c, body)), Some((mass, w, zeta))) = (self.far, b.far) {
            let (uf, vf) = (q[c], v[c]);
            let pushed_far = self.contacts.as_ref().map_or(0.0, |w| w.far_push());
            let ff = asm.reaction_sum(ws, t, q, lam, &self.abutment_links, body)[0] + pushed_far;
            let a = (-mass * w * w * uf - 2.0 * zeta * mass * w * vf + ff) / mass;
            for (peak, x) in self.far_peaks.iter_mut().zip([a, uf, ff, u - uf]) {
                peak.update(x, t);
            }
        }
        // across: the joist boxes alone hold the deck (contacts push along x)
        let across = match (self.deck_y, b.transverse, modal_ay) {
            (Some(c), _, Some(a)) => Some((q[c], v[c], a)),
            (Some(c), Some((w, zeta)), None) => {
                let (uy, vy, fy) = (q[c], v[c], reaction[1]);
                Some((uy, vy, (-b.mass * w * w * uy - 2.0 * zeta * b.mass * w * vy + fy) / b.mass))
            }
            _ => None,
        };
        let across = across.map(|(uy, vy, a)| {
            for (peak, x) in self.across.iter_mut().zip([a, uy, vy, reaction[1]]) {
                peak.update(x, t);
            }
            (uy, a, reaction[1])
        });
        self.sa.update(a_abs, t);
        self.sd.update(u, t);
        self.sv.update(ud, t);
        self.joint_force.update(fj, t);
        self.check(t, q);
        if self.gaps.is_some() || self.link.is_some() {
            self.force_peaks(asm, ws, q, v);
        }
        if self.histories.is_some() {
            let at = Instant { t, q, v, lam };
            self.record(at, [u, ud, a_abs, fj], across, asm, ws);
        }
    }

    /// The joint's force on its abutment side at `at`: its links'
    /// reactions on the support beams, turned round, and `pushed`, the edge
    /// beam's push along x \[N\], into its peak.
    fn abutment_update(&mut self, at: Instant<'_>, pushed: f64, asm: &Assembly, ws: &mut quakejoint_solver::Workspace) {
        let Instant { t, q, lam, .. } = at;
        let held: f64 = self
            .abutment_links
            .iter()
            .zip(&self.supports)
            .map(|(&c, &b)| asm.reaction_sum(ws, t, q, lam, &[c], b)[0])
            .sum();
        self.abutment_force.update(pushed - held, t);
    }

    /// The peak bushing and friction forces: the whole system's and, in a
    /// run of several joints, this joint's group's (every bushing and
    /// bearing is some joint's, so the system's are the groups' largest).
    fn force_peaks(&mut self, asm: &Assembly, ws: &mut quakejoint_solver::Workspace, q: &[f64], v: &[f64]) {
        let x = match self.group {
            None => asm.force_extremes(ws, q, v),
            Some(g) => {
                self.group_extremes.iter_mut().for_each(|x| *x = Default::default());
                asm.force_extremes_by_group(ws, q, v, &mut self.group_extremes);
                let own = self.group_extremes[g];
                self.own.bushing = self.own.bushing.max(own.bushing);
                self.own.friction = self.own.friction.max(own.friction);
                // (the joints' groups: a freed edge beam's friction is its fuse's)
                let joints = &self.group_extremes[..self.joint_groups];
                joints.iter().fold(Default::default(), |m: quakejoint_solver::ForceExtremes, x| {
                    quakejoint_solver::ForceExtremes {
                        bushing: m.bushing.max(x.bushing),
                        friction: m.friction.max(x.friction),
                    }
                })
            }
        };
        self.bushing = self.bushing.max(x.bushing);
        self.friction = self.friction.max(x.friction);
    }

    /// A modal deck end's absolute acceleration along and across (in the
    /// joint's own x and y) at `at`, and the points' and base shear's
    /// peaks when this observer watches them.
    fn modal_sample(
        &mut self,
        at: Instant<'_>,
        asm: &Assembly,
        ws: &mut quakejoint_solver::Workspace,
    ) -> (f64, Option<f64>) {
        let Instant { t, q, v, lam } = at;
        let m = self.modal.as_ref().expect("called for a modal deck");
        let ag = [self.ground.value(t), self.ground_y.as_ref().map_or(0.0, |g| g.value(t))];
        let mut acc = std::mem::take(&mut self.modal_acc);
        let at = crate::modal::Instant { t, q, v, lam, ag };
        m.parts.accelerations(asm, ws, at, &mut self.modal_forces, &mut acc);
        let end = &m.parts.ends[m.end];
        // (in the joint's own x and y)
        let a = end.sign * m.parts.point(asm, end.point, q, v, &acc, ag[0])[2];
        let ay = end.across.map(|(py, _)| end.sign * m.parts.point(asm, py, q, v, &acc, ag[1])[2]);
        for (p, peaks) in self.points.iter_mut().enumerate() {
            let [up, _, ap] = m.parts.point(asm, p, q, v, &acc, ag[0]);
            peaks[0].update(up, t);
            peaks[1].update(ap, t);
            if let Some(h) = &mut self.histories {
                h.points_u[p].push(up);
                h.points_a_abs[p].push(ap);
            }
        }
        if !self.points.is_empty() {
            self.base_shear.update(m.parts.base_shear(asm, q, v), t);
        }
        self.modal_acc = acc;
        (a, ay)
    }

    /// Appends one output time to the histories: the deck's `[u, v, a_abs,
    /// joint force]`, across `(uy, a_abs_y, force_y)` if the deck moves
    /// across, the friction power and the joint's cells.
    fn record(
        &mut self,
        at: Instant<'_>,
        deck: [f64; 4],
        across: Option<(f64, f64, f64)>,
        asm: &Assembly,
        ws: &mut quakejoint_solver::Workspace,
    ) {
        let Instant { t, q, v, lam } = at;
        let Some(h) = &mut self.histories else { return };
        let [u, ud, a_abs, fj] = deck;
        h.t.push(t);
        // (in the joint's own x, as its deck point's motion)
        h.ag.push(self.sign * self.ground.value(t));
        h.u.push(u);
        h.v.push(ud);
        h.a_abs.push(a_abs);
        h.joint_force.push(fj);
        if let Some((uy, a, fy)) = across {
            h.uy.push(uy);
            h.a_abs_y.push(a);
            h.joint_force_y.push(fy);
        }
        // (its own group's, in a run of several joints; else the system's)
        let friction_power = match self.group {
            Some(g) => {
                let mut powers = std::mem::take(&mut self.group_powers);
                powers.clear();
                powers.resize(asm.group_count(), 0.0);
                asm.friction_powers_by_group(ws, t, q, v, &mut powers);
                let own = powers[g];
                self.group_powers = powers;
                own
            }
            None => asm.powers(ws, t, q, v, lam).friction,
        };
        h.friction_power.push(friction_power);
        if let Some(g) = &self.gaps {
            for (i, &c) in g.beams.iter().enumerate() {
                h.center_beam_dx[i].push(q[c] - g.geometry.center_x[i]);
            }
            for (series, &gap) in h.subgaps.iter_mut().zip(&g.smallest) {
                series.push(gap);
            }
            for (series, &gap) in h.subgaps_wide.iter_mut().zip(&g.largest) {
                series.push(gap);
            }
            for (series, &f) in h.contact_force.iter_mut().zip(&self.gap_forces) {
                series.push(f);
            }
        }
        if let Some(l) = &self.link {
            let cell = l.cell();
            for series in h.subgaps.iter_mut().chain(h.subgaps_wide.iter_mut()) {
                series.push(cell);
            }
        }
    }
}

/// The state at one output time.
#[derive(Clone, Copy)]
struct Instant<'a> {
    t: f64,
    q: &'a [f64],
    v: &'a [f64],
    lam: &'a [f64],
}

impl EarthquakeObserver {
    /// The joint's forces on the deck and on the abutment at `at`, the
    /// instant its fuse broke, into their peaks.
    fn break_peaks(&mut self, at: Instant<'_>, view: &mut StepView<'_>) {
        let (asm, ws) = (view.assembly, &mut *view.workspace);
        let on_deck = match (&mut self.link, &mut self.contacts) {
            (Some(l), _) => l.forces(at.q, at.v, asm, ws).2,
            (None, c) => {
                let pushed = c.as_mut().map_or(0.0, |c| c.at(asm, ws, at.q, at.v, Some(&mut self.gap_forces)));
                asm.reaction_sum(ws, at.t, at.q, at.lam, &self.boxes, self.deck_body)[0] + pushed
            }
        };
        self.joint_force.update(on_deck, at.t);
        if let Some(f) = self.fuse.as_ref().filter(|_| !self.abutment_links.is_empty()) {
            // (a box's edge beam takes the break force to the abutment; an
            // element's beam takes its force off its neighbours, and the
            // abutment has the edge cell's, just loaded above)
            let pushed = match f.result.kind {
                crate::config::FuseKind::Box => -f.result.break_force,
                crate::config::FuseKind::Element => self.contacts.as_ref().map_or(0.0, |c| c.far_push()),
            };
            self.abutment_update(at, pushed, asm, ws);
        }
    }
}

impl Observer for EarthquakeObserver {
    /// Watches the step; false when its fuse broke at the step's end (the
    /// run then goes on in the broken system, [`crate::run::fuse::run_with_fuses`]).
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        let broke = self.fuse.as_mut().is_some_and(|f| f.step(view.events));
        if broke {
            // (the break force reaches the deck and the abutment at the
            // break, between two output times)
            self.break_peaks(Instant { t: view.t, q: view.q, v: view.v, lam: view.lambda }, view);
        } else if let Some(l) = &mut self.link {
            // (a link's closed gap: its impacts last less than an output
            // interval)
            l.step(view, &mut self.joint_force);
        }
        self.locate_crossings(view);
        self.check_between(view);
        if let Some(c) = &mut self.contacts {
            c.step(view, self.monitor.as_mut());
        }
        // the record's samples: the step's end state at the samples it ends
        // on (every one while the record lasts), the dense output between
        while let Some(tj) = self.outputs.next_in(view) {
            if let Some((start, limit)) = self.deadline {
                if (tj.index() + 1).is_multiple_of(1024) && start.elapsed().as_secs_f64() > limit {
                    self.out_of_time = true;
                    return false;
                }
            }
            let mut state = std::mem::take(&mut self.state);
            view.sample(&tj, &mut state).expect(DENSE_OUTPUT);
            self.sample(state.t, &state.q, &state.v, &state.lambda, view.assembly, view.workspace);
            self.state = state;
        }
        !broke
    }
}

/// A link element's watch in a run: its parts, coordinates and extremes.
pub(super) struct LinkObserver {
    parts: crate::link::LinkParts,
    /// Scratch: the contacts' states.
    contacts: Vec<quakejoint_solver::ContactValue>,
    deck: usize,
    slider: usize,
    abutment: Option<usize>,
    watch: crate::link::LinkWatch,
    /// The opening at the last update \[m\].
    u: f64,
    /// Scratch: a state inside a step.
    scratch: Option<quakejoint_solver::StateBuffer>,
    /// The opening at the end of the last step \[m\].
    step_u: f64,
    /// The cells the closed joint squeezes in series (one fewer once a
    /// fuse element's beam left).
    in_series: usize,
}

impl LinkObserver {
    pub(super) fn new(model: &JointModel, asm: &Assembly) -> Option<Self> {
        let parts = model.link.clone()?;
        let deck = asm.coordinate(parts.deck, quakejoint_solver::Coord::X)?;
        let slider = asm.coordinate(parts.slider, quakejoint_solver::Coord::X)?;
        let abutment = asm.coordinate(parts.abutment, quakejoint_solver::Coord::X);
        let in_series = parts.cells;
        Some(Self {
            parts,
            contacts: Vec::new(),
            deck,
            slider,
            abutment,
            watch: crate::link::LinkWatch::default(),
            u: 0.0,
            scratch: None,
            step_u: 0.0,
            in_series,
        })
    }

    /// Watches a step into `peak` (its force on the deck) where the gap is
    /// closed at either end of it (a closure lasts less than an output
    /// interval, the first after a fuse broke less than a step): at
    /// [`crate::pounding::INTERIOR`] points inside it on the dense output,
    /// then at its end. Elsewhere the output times watch it.
    fn step(&mut self, view: &mut StepView<'_>, peak: &mut Peak) {
        let closed = |u: f64, gap: f64| u + gap < 0.0;
        let u_end = view.q[self.deck] - self.abutment.map_or(0.0, |c| view.q[c]);
        let u_start = std::mem::replace(&mut self.step_u, u_end);
        if !(closed(u_start, self.parts.gap) || closed(u_end, self.parts.gap)) || view.t <= view.t_prev {
            return;
        }
        let mut s = self.scratch.take().unwrap_or_else(|| quakejoint_solver::StateBuffer::new(view.assembly));
        let dt = (view.t - view.t_prev) / (crate::pounding::INTERIOR + 1) as f64;
        // (the peaks alone: the output times watch the rest, in order)
        let mut at = |link: &mut Self, t: f64, q: &[f64], v: &[f64], ws: &mut quakejoint_solver::Workspace| {
            let (_, gap, on_deck) = link.forces(q, v, view.assembly, ws);
            peak.update(on_deck, t);
            if gap > link.watch.peak_gap_force {
                (link.watch.peak_gap_force, link.watch.peak_gap_time) = (gap, t);
            }
        };
        for k in 1..=crate::pounding::INTERIOR {
            let t = view.t_prev + dt * k as f64;
            view.state_at(t, &mut s).expect(DENSE_OUTPUT);
            at(self, t, &s.q, &s.v, view.workspace);
        }
        self.scratch = Some(s);
        at(self, view.t, view.q, view.v, view.workspace);
    }

    /// Watches the state `(q, v)` at `t`; returns the link's force on the
    /// deck (its spring's and damper's and, closed, its gap's) \[N\].
    fn update(&mut self, t: f64, q: &[f64], v: &[f64], asm: &Assembly, ws: &mut quakejoint_solver::Workspace) -> f64 {
        let (u, gap, on_deck) = self.forces(q, v, asm, ws);
        self.u = u;
        self.watch.update(&self.parts, t, u, gap);
        on_deck
    }

    /// At the state `(q, v)`: the opening \[m\], the closed gap's force and
    /// the link's whole force on the deck \[N\].
    fn forces(
        &mut self,
        q: &[f64],
        v: &[f64],
        asm: &Assembly,
        ws: &mut quakejoint_solver::Workspace,
    ) -> (f64, f64, f64) {
        let u = q[self.deck] - self.abutment.map_or(0.0, |c| q[c]);
        let gap = match self.parts.contact {
            Some(i) => {
                self.contacts.resize(asm.contact_count(), Default::default());
                asm.contacts(ws, q, v, &mut self.contacts);
                let c = &self.contacts[i];
                if c.closed {
                    c.force
                } else {
                    0.0
                }
            }
            None => 0.0,
        };
        let p = &self.parts;
        (u, gap, p.stiffness * (q[self.slider] - q[self.deck]) + p.damping * (v[self.slider] - v[self.deck]) + gap)
    }

    pub(super) fn cells(&self) -> [f64; 2] {
        self.watch.cells(&self.parts)
    }

    /// The cells' clear width at the last update \[m\].
    fn cell(&self) -> f64 {
        self.parts.clear + self.u / self.parts.cells as f64
    }

    /// The closures as pounding: the closed joint's force on the deck.
    pub(super) fn pounding(&self) -> Pounding {
        let w = &self.watch;
        Pounding {
            // (the racked cell's closures: the detailed joint's first impacts)
            impacts: w.cell_closures,
            peak_contact_force: w.peak_gap_force,
            peak_contact_time: w.peak_gap_time,
            peak_deck_contact_force: w.peak_gap_force,
            max_penetration: w.max_overlap / self.in_series as f64,
            // (a link's closure is no one beam's impact)
            max_impact_speed: f64::NAN,
            ..Pounding::default()
        }
    }

    /// A cell beyond its capacity, flagged as the detailed joint's.
    pub(super) fn validity(&self, v: &mut crate::validity::Validity) {
        if let Some(t) = self.watch.beyond_capacity_at {
            v.flags |= crate::validity::Flags::CAPACITY_EXCEEDED;
            v.findings.push(format!(
                "capacity_exceeded: the link's widest cell (the average with its racking of {:.1} mm) opened to \
                 {:.1} mm, beyond the capacity of {:.0} mm (joint.capacity.max_subgap; first at t = {t:.3} s)",
                self.parts.racking[1] * 1e3,
                self.cells()[1] * 1e3,
                self.parts.max_subgap * 1e3
            ));
        }
    }
}
