//! A run continued in a changed system: a fuse that broke at a located
//! event ([`Radau5::set_force_threshold`]) frees a body the intact system
//! did not have, and the run goes on from the event's state
//! ([`Radau5::resume`]).

use std::sync::Arc;

use super::Radau5;
use crate::assembly::Assembly;
use crate::error::{BuildError, SolverError};
use crate::integrator::IntegratorOptions;

impl Radau5 {
    /// Watches the sum of the forces of the closed contacts among
    /// `contacts` for `force` \[N\]: the first time it rises through it,
    /// the step ends there and reports a
    /// [`crate::ContactEventKind::Threshold`] event on `contacts[0]` (once;
    /// no contact's mode changes). A fuse held by the contacts' force
    /// breaks there.
    pub fn set_force_threshold(&mut self, contacts: &[usize], force: f64) -> Result<(), SolverError> {
        let n = self.asm.contact_count();
        if contacts.is_empty() || contacts.iter().any(|&c| c >= n) || force.is_nan() || force <= 0.0 {
            return Err(SolverError::Build(BuildError::InvalidParameter {
                what: format!("contacts {contacts:?} of {n}"),
                name: "force threshold",
                value: force,
                reason: "a positive force on a set of the system's contacts",
            }));
        }
        self.events.add_watch(contacts.to_vec(), force);
        Ok(())
    }

    /// Opens `contacts` where they are closed, as a body that leaves the
    /// plane takes them with it (a fuse element; [`Radau5::resume`] then
    /// goes on in a system where they no longer touch): the elastic energy
    /// they still store is lost with them, booked as the contacts'
    /// dissipation ([`crate::EnergyBalance::contact`]). Returns that energy
    /// \[J\].
    pub fn release_contacts(&mut self, contacts: &[usize]) -> Result<f64, SolverError> {
        let n = self.asm.contact_count();
        if let Some(&c) = contacts.iter().find(|&&c| c >= n) {
            return Err(SolverError::Build(BuildError::InvalidParameter {
                what: format!("contact {c} of {n}"),
                name: "released contact",
                value: c as f64,
                reason: "one of the system's contacts",
            }));
        }
        let mut values = vec![crate::ContactValue::default(); n];
        self.asm.contacts(&mut self.ws, &self.q, &self.v, &mut values);
        let mut released = 0.0;
        for &i in contacts {
            if self.ws.closed_contacts()[i] {
                released += self.asm.contact_energy(i, values[i].penetration);
                self.ws.set_contact(i, false, 0.0);
            }
        }
        self.energy.contact += released;
        Ok(released)
    }

    /// Continues the run of `from` in the system `asm`, which has `from`'s
    /// bodies, constraints, force elements and contacts first, in the same
    /// order, and may add bodies and force elements after them (their
    /// coordinates follow `from`'s and start at their reference state, at
    /// rest). The time, the state, the contacts' modes and force thresholds,
    /// the energy balance, the counters and the step size carry over; the
    /// multipliers are made consistent again and the integrator starts
    /// afresh (a new Jacobian, no extrapolated starting values), as after a
    /// contact event.
    pub fn resume(asm: Arc<Assembly>, opt: IntegratorOptions, from: &Radau5) -> Result<Self, SolverError> {
        let (n0, contacts0) = (from.n, from.asm.contact_count());
        if asm.coordinates() < n0 || asm.equations() != from.m || asm.contact_count() < contacts0 {
            return Err(SolverError::Build(BuildError::NotAnExtension {
                detail: format!(
                    "{} coordinates, {} equations, {} contacts; the run has {n0}, {}, {contacts0}",
                    asm.coordinates(),
                    asm.equations(),
                    asm.contact_count(),
                    from.m
                ),
            }));
        }
        let mut s = Radau5::new(asm, opt)?;
        s.t = from.t;
        s.t_prev = from.t;
        s.q[..n0].copy_from_slice(&from.q);
        s.v[..n0].copy_from_slice(&from.v);
        s.v[n0..].iter_mut().for_each(|v| *v = 0.0);
        for i in 0..contacts0 {
            s.ws.set_contact(i, from.ws.closed_contacts()[i], from.ws.contact_speed(i));
        }
        s.events.set_watches(from.events.watches().to_vec());
        s.energy = from.energy;
        s.potential0 = from.potential0;
        s.stats = from.stats;
        s.stats.jacobian_evaluations += 1;
        for (g, f) in s.group_friction.iter_mut().zip(&from.group_friction) {
            *g = *f;
        }
        s.max_residual = from.max_residual;
        s.h = from.h;
        s.started = from.started;
        s.consistent_state(false)?;
        Ok(s)
    }
}
