//! The values the assembly hands out: Jacobian arrays, power flows, peak
//! forces and contact states.

/// Stiffness, damping and constraint-gradient values of one Jacobian
/// evaluation, in the layout of the block iteration matrix.
#[derive(Debug, Clone)]
pub struct JacobianValues {
    /// `K = -dF/dq` (constraint Hessian included); one extra sink entry at the end.
    pub k: Vec<f64>,
    /// `D = -dF/dq'`; one extra sink entry at the end.
    pub d: Vec<f64>,
    /// `G = dg/dq`, one value per stored gradient entry.
    pub g: Vec<f64>,
}

impl JacobianValues {
    /// `K` without the sink entry.
    pub fn stiffness(&self) -> &[f64] {
        &self.k[..self.k.len() - 1]
    }
    /// `D` without the sink entry.
    pub fn damping(&self) -> &[f64] {
        &self.d[..self.d.len() - 1]
    }
}

/// Power flows at one state, for the energy balance \[W\].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Powers {
    /// Dissipated by dampers (bushings, spring-dampers, coordinate dampers); never negative.
    pub damping: f64,
    /// Dissipated by friction; never negative.
    pub friction: f64,
    /// Delivered by applied loads and custom forces.
    pub applied: f64,
    /// Delivered by the base excitation (`-m a_g` on every body).
    pub base: f64,
    /// Delivered by rheonomic constraints (drivers).
    pub constraints: f64,
    /// Dissipated by the damping of closed contacts; never negative.
    pub contact: f64,
}

/// Largest element forces at one state.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ForceExtremes {
    /// Largest bushing force magnitude \[N\].
    pub bushing: f64,
    /// Largest friction force magnitude \[N\].
    pub friction: f64,
}

/// A contact's state at one instant ([`super::Assembly::contacts`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactValue {
    /// Whether the contact is closed.
    pub closed: bool,
    /// Penetration \[m\] (positive when overlapping, whatever the mode).
    pub penetration: f64,
    /// Its rate [m/s].
    pub rate: f64,
    /// Force of the law \[N\]: of a closed contact (may be below zero just
    /// before a release event); of an open one, the force the law would
    /// give at this penetration and rate (0 when not penetrating), whose
    /// sign says whether closing it would push or pull.
    pub force: f64,
}
