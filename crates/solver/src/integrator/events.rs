//! Contact onset and release as events.
//!
//! A contact ([`crate::Contact`]) is open or closed for a whole step; its
//! force law is smooth within a mode but not across a change of mode (a
//! Hertz force starts with an infinite stiffness slope, a linear
//! spring-dashpot with a jump of its damping force). So no step may cross a
//! change: after the error test accepts a candidate step, the event
//! functions are evaluated on its collocation polynomial (the interpolant of
//! the stage values, Hairer and Wanner IV.8's dense output): an open
//! contact's penetration must stay below zero, a closed contact's
//! penetration and force above zero. If one does not, the first crossing is
//! located by bisection on the polynomial, the step is taken again ending
//! there (like a breakpoint), and at its end the contact's mode changes
//! (the integrator then starts afresh: new Jacobian, no extrapolated
//! starting values, a step short against the contact's duration). A
//! contact that closes records its approach speed (the Hertz damping
//! depends on it); one that opens while still penetrating (its force fell
//! to zero first) loses its stored elastic energy, which is booked as
//! contact dissipation so that the energy balance closes.
//!
//! A set of contacts may also carry a force threshold
//! ([`crate::Radau5::set_force_threshold`]): the first time the sum of its
//! closed contacts' forces rises through it is located the same way, the
//! step ends there and the event ([`ContactEventKind::Threshold`], on the
//! set's first contact) is reported without a change of mode (a fuse that
//! breaks there: the caller stops and continues with the broken system,
//! [`crate::Radau5::resume`]); it is reported once. In the located lists a
//! watch `w` is numbered `n + w` after the `n` contacts.
//!
//! Sampling: 8 points per step for every closed contact and every open
//! contact that could reach zero penetration within the step (its
//! penetration at either end plus half the step times its largest rate);
//! open contacts far from touching cost two evaluations per step.

use super::radau5::C;
use super::EnergyBalance;
use crate::assembly::{Assembly, ContactValue, Workspace};

/// A change of a contact's mode at the end of a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactEvent {
    /// The contact (in the order the system added them).
    pub contact: usize,
    /// When \[s\].
    pub time: f64,
    /// Closing or opening.
    pub kind: ContactEventKind,
}

/// What happened to the contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactEventKind {
    /// The contact closed; the approach speed `speed` [m/s] (the rate of
    /// penetration at onset).
    Onset {
        /// Approach speed [m/s].
        speed: f64,
    },
    /// The contact opened with penetration `penetration` \[m\] (zero, or
    /// positive when its force reached zero first) and speed `speed` [m/s]
    /// (negative: separating).
    Release {
        /// Penetration at release \[m\].
        penetration: f64,
        /// Rate of penetration at release [m/s].
        speed: f64,
    },
    /// The sum of the closed contacts' forces of a watched set reached its
    /// threshold ([`crate::Radau5::set_force_threshold`]; the event names
    /// the set's first contact); no mode changes.
    Threshold {
        /// The summed force at the event \[N\] (the threshold to within
        /// the step's local error).
        force: f64,
    },
}

/// A state of the system: time, positions and velocities.
#[derive(Clone, Copy)]
pub(crate) struct State<'a> {
    /// Time [s].
    pub t: f64,
    /// Positions.
    pub q: &'a [f64],
    /// Velocities.
    pub v: &'a [f64],
}

/// A candidate step of length `h` [s] from `start`, with the stage
/// increments of positions `zq` and velocities `zv`.
#[derive(Clone, Copy)]
pub(crate) struct Trial<'a> {
    /// The state at the step's start.
    pub start: State<'a>,
    /// Step size [s].
    pub h: f64,
    /// Stage increments of the positions.
    pub zq: &'a [Vec<f64>; 3],
    /// Stage increments of the velocities.
    pub zv: &'a [Vec<f64>; 3],
}

/// A set of contacts whose summed force is watched for a threshold.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ForceWatch {
    /// The contacts (at least one).
    pub contacts: Vec<usize>,
    /// The threshold \[N\] (infinite once reported).
    pub force: f64,
}

impl ForceWatch {
    /// The summed force of the closed contacts among `values` \[N\].
    fn force_of(&self, values: &[ContactValue]) -> f64 {
        self.contacts.iter().map(|&i| values[i]).filter(|c| c.closed).map(|c| c.force).sum()
    }
}

/// Samples per step at which a contact that may change is checked.
const SAMPLES: usize = 8;
/// Bisection steps locating a crossing (2^-48 of the step).
const BISECTIONS: usize = 48;

/// Event detection and the modes' bookkeeping of one integrator.
#[derive(Debug, Clone)]
pub(crate) struct Events {
    /// Contacts.
    n: usize,
    /// The coordinates the contacts depend on (unique).
    coords: Vec<u32>,
    /// Scratch positions and velocities (only `coords` are written).
    q: Vec<f64>,
    v: Vec<f64>,
    /// Contact states at the start of the current step.
    start: Vec<ContactValue>,
    /// Scratch states at a sample.
    at: Vec<ContactValue>,
    /// States at the end of the candidate step (kept apart from `at`, so
    /// that locating needs no allocation while no contact is near).
    end: Vec<ContactValue>,
    /// The located change the current step is fitted to: its time and the
    /// contacts that change there.
    pending: Option<(f64, Vec<usize>)>,
    /// The changes since the observer last saw them (at the end of the last
    /// accepted step, or at its start when due there).
    pub last: Vec<ContactEvent>,
    /// The contacts changed at the very start of the step at this time.
    now: (f64, Vec<usize>),
    /// The watched sets of contacts and their force thresholds.
    watches: Vec<ForceWatch>,
    /// Contacts left closed and unchecked during the step starting at this
    /// time: each had to change back at once, so it sits at zero force
    /// (a resting contact) where either mode is wrong a moment later.
    frozen: (f64, Vec<usize>),
}

/// Lagrange weights of the stage values at `s` in [0, 1] (nodes 0, c1, c2, 1
/// with the increment 0 at node 0).
fn weights(s: f64) -> [f64; 3] {
    let nodes = [0.0, C[0], C[1], C[2]];
    std::array::from_fn(|i| {
        let ci = nodes[i + 1];
        nodes.iter().filter(|&&x| x != ci).map(|&x| (s - x) / (ci - x)).product()
    })
}

impl Events {
    pub fn new(asm: &Assembly) -> Self {
        let n = asm.contact_count();
        let nc = asm.coordinates() as u32;
        let mut coords: Vec<u32> = (0..n).flat_map(|i| asm.contact_coords(i)).filter(|&c| c < nc).collect();
        coords.sort_unstable();
        coords.dedup();
        Self {
            n,
            coords,
            q: vec![0.0; asm.coordinates()],
            v: vec![0.0; asm.coordinates()],
            start: vec![ContactValue::default(); n],
            at: vec![ContactValue::default(); n],
            end: vec![ContactValue::default(); n],
            pending: None,
            last: Vec::new(),
            now: (f64::NAN, Vec::new()),
            watches: Vec::new(),
            frozen: (f64::NAN, Vec::new()),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// The time the current step must end at, if a change is pending.
    pub fn pending_time(&self) -> Option<f64> {
        self.pending.as_ref().map(|p| p.0)
    }

    /// Watches the summed force of `contacts` for `force` \[N\] (see the
    /// module documentation).
    pub fn add_watch(&mut self, contacts: Vec<usize>, force: f64) {
        self.watches.push(ForceWatch { contacts, force });
    }

    /// The watched sets (to carry over to a resumed run).
    pub fn watches(&self) -> &[ForceWatch] {
        &self.watches
    }

    /// The watched sets, carried over from another run.
    pub fn set_watches(&mut self, watches: Vec<ForceWatch>) {
        self.watches = watches;
    }

    /// Whether contact `i` in `values` must change mode ([`Events::wrong`]),
    /// or watch `i - n` has reached its force threshold.
    fn due(&self, i: usize, values: &[ContactValue]) -> bool {
        match i.checked_sub(self.n) {
            None => Self::wrong(&values[i]),
            Some(w) => self.watches[w].force_of(values) >= self.watches[w].force,
        }
    }

    /// Whether entry `i` (a contact, or watch `i - n`) may change within a
    /// step of length `h`: a closed contact, one that could reach zero
    /// penetration, one due at the step's end; a watch with a closed
    /// contact at either end.
    fn near(&self, i: usize, h: f64) -> bool {
        if let Some(w) = i.checked_sub(self.n) {
            let watch = &self.watches[w];
            return watch.force.is_finite()
                && watch.contacts.iter().any(|&c| self.start[c].closed || self.end[c].closed);
        }
        let (a, b) = (&self.start[i], &self.end[i]);
        let reach = 0.5 * h * a.rate.abs().max(b.rate.abs());
        a.closed || Self::wrong(b) || a.penetration.max(b.penetration) + reach > 0.0
    }

    /// Records the contact states at the start of a step.
    pub fn record_start(&mut self, asm: &Assembly, ws: &mut Workspace, q: &[f64], v: &[f64]) {
        if self.n > 0 {
            asm.contacts(ws, q, v, &mut self.start);
        }
    }

    /// Whether contact `i` in state `c` must change mode (and why it is
    /// "wrong" for its mode): an open one that penetrates and whose law
    /// would push (an approach; not the separation after a release at zero
    /// force while still penetrating), a closed one that no longer
    /// penetrates or pulls.
    fn wrong(c: &ContactValue) -> bool {
        if c.closed {
            c.penetration < 0.0 || c.force < 0.0
        } else {
            c.penetration > 0.0 && c.force > 0.0
        }
    }

    /// The states of every contact at `s` of the candidate step, into
    /// `self.at`.
    fn sample(&mut self, asm: &Assembly, ws: &mut Workspace, trial: &Trial, s: f64) {
        let w = weights(s);
        let (q, v, zq, zv) = (trial.start.q, trial.start.v, trial.zq, trial.zv);
        for &c in &self.coords {
            let c = c as usize;
            self.q[c] = q[c] + w[0] * zq[0][c] + w[1] * zq[1][c] + w[2] * zq[2][c];
            self.v[c] = v[c] + w[0] * zv[0][c] + w[1] * zv[1][c] + w[2] * zv[2][c];
        }
        asm.contacts(ws, &self.q, &self.v, &mut self.at);
    }

    /// Looks for a change of mode within the candidate step `[t, t + h]`.
    /// Returns the time of the first one and the contacts changing there,
    /// ignoring the pending change the step was fitted to.
    pub fn locate(&mut self, asm: &Assembly, ws: &mut Workspace, trial: &Trial) -> Option<(f64, Vec<usize>)> {
        let (t, h) = (trial.start.t, trial.h);
        // the end of the step, and which contacts need the interior
        self.sample(asm, ws, trial, 1.0);
        std::mem::swap(&mut self.at, &mut self.end);
        let frozen = if self.frozen.0 == t { self.frozen.1.as_slice() } else { &[] };
        let watch: Vec<usize> =
            (0..self.n + self.watches.len()).filter(|&i| !frozen.contains(&i) && self.near(i, h)).collect();
        if watch.is_empty() {
            return None;
        }
        let pending: Vec<usize> = self.pending.as_ref().map_or(Vec::new(), |p| p.1.clone());
        // the fitted step's own change lies at its very end: not a new one
        let fresh = |i: usize, s: f64| !(pending.contains(&i) && s > 1.0 - 1e-6);
        let mut s_ok = 0.0;
        for k in 1..=SAMPLES {
            let s = k as f64 / SAMPLES as f64;
            if k < SAMPLES {
                self.sample(asm, ws, trial, s);
            } else {
                self.at.copy_from_slice(&self.end);
            }
            let bad: Vec<usize> = watch.iter().copied().filter(|&i| self.due(i, &self.at) && fresh(i, s)).collect();
            if bad.is_empty() {
                s_ok = s;
                continue;
            }
            // bisection between the last good sample and this one
            let (mut lo, mut hi) = (s_ok, s);
            let mut changing = bad;
            for _ in 0..BISECTIONS {
                let mid = 0.5 * (lo + hi);
                self.sample(asm, ws, trial, mid);
                let now: Vec<usize> =
                    watch.iter().copied().filter(|&i| self.due(i, &self.at) && fresh(i, mid)).collect();
                if now.is_empty() {
                    lo = mid;
                } else {
                    hi = mid;
                    changing = now;
                }
            }
            return Some((t + hi * h, changing));
        }
        None
    }

    /// Changes the modes of `contacts` at the very start of the step at `t`
    /// (the located change is due now). A contact that must change back at
    /// once (it changed at this `t` already) sits at zero force, where
    /// either mode is wrong a moment later: it is left closed and unchecked
    /// for this step, and the next one decides. Returns how many changed
    /// and how many changes were made at `t` so far.
    pub fn change_now(
        &mut self,
        asm: &Assembly,
        ws: &mut Workspace,
        at: State,
        contacts: Vec<usize>,
        energy: &mut EnergyBalance,
    ) -> (usize, usize) {
        let t = at.t;
        if self.now.0 != t {
            self.now = (t, Vec::new());
        }
        if self.frozen.0 != t {
            self.frozen = (t, Vec::new());
        }
        let (again, fresh): (Vec<usize>, Vec<usize>) = contacts.into_iter().partition(|i| self.now.1.contains(i));
        let reopened: Vec<usize> = again.iter().copied().filter(|&i| i < self.n && !ws.closed_contacts()[i]).collect();
        let mut n = self.change(asm, ws, at, &reopened, energy);
        self.frozen.1.extend(again);
        n += self.change(asm, ws, at, &fresh, energy);
        self.now.1.extend(fresh);
        self.now.1.extend(reopened);
        (n, self.now.1.len())
    }

    /// Fits the current step to end at a change located at `time`.
    pub fn set_pending(&mut self, time: f64, contacts: Vec<usize>) {
        self.pending = Some((time, contacts));
    }

    /// At the end of an accepted step at `t`: if it is the step fitted to a
    /// pending change, changes the modes of its contacts ([`Events::change`])
    /// and returns how many changed.
    pub fn apply_pending(
        &mut self,
        asm: &Assembly,
        ws: &mut Workspace,
        at: State,
        energy: &mut EnergyBalance,
    ) -> usize {
        let t = at.t;
        let Some((time, contacts)) = self.pending.take() else { return 0 };
        if (time - t).abs() > 1e-9 * time.abs().max(1.0) {
            // the step did not reach the change (it was shortened further)
            self.pending = Some((time, contacts));
            return 0;
        }
        self.change(asm, ws, at, &contacts, energy)
    }

    /// Changes the mode of every contact in `contacts` in the state `at`:
    /// the crossing was located on the candidate step, and the
    /// step retaken to it ends there to within its local error (about
    /// `atol`), so a contact may close at a penetration of -1e-6 m or open at
    /// a force a little above zero; the energy stored or lost is booked.
    /// Returns how many changed.
    pub fn change(
        &mut self,
        asm: &Assembly,
        ws: &mut Workspace,
        at: State,
        contacts: &[usize],
        energy: &mut EnergyBalance,
    ) -> usize {
        let t = at.t;
        asm.contacts(ws, at.q, at.v, &mut self.at);
        for &i in contacts {
            if let Some(w) = i.checked_sub(self.n) {
                let watch = &mut self.watches[w];
                let force = watch.force_of(&self.at);
                watch.force = f64::INFINITY;
                self.last.push(ContactEvent {
                    contact: watch.contacts[0],
                    time: t,
                    kind: ContactEventKind::Threshold { force },
                });
                continue;
            }
            let c = self.at[i];
            if c.closed {
                // the elastic energy still stored is lost with the contact
                energy.contact += asm.contact_energy(i, c.penetration);
                ws.set_contact(i, false, 0.0);
                self.last.push(ContactEvent {
                    contact: i,
                    time: t,
                    kind: ContactEventKind::Release { penetration: c.penetration, speed: c.rate },
                });
            } else {
                // closing at a small penetration stores a little energy
                energy.contact -= asm.contact_energy(i, c.penetration);
                ws.set_contact(i, true, c.rate.max(0.0));
                self.last.push(ContactEvent { contact: i, time: t, kind: ContactEventKind::Onset { speed: c.rate } });
            }
        }
        contacts.len()
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn weights_interpolate_the_nodes() {
        use super::{weights, C};
        for (i, &c) in C.iter().enumerate() {
            let w = weights(c);
            for (j, &x) in w.iter().enumerate() {
                assert!((x - f64::from(u8::from(i == j))).abs() < 1e-12, "{i} {j} {x}");
            }
        }
        let w0 = weights(0.0);
        assert!(w0.iter().all(|x| x.abs() < 1e-15));
    }
}
