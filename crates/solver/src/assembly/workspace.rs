//! Scratch space of the evaluations, and the contacts' modes.

use super::kin::BodyKin;

/// Scratch space for evaluations; one per thread. It also holds the modes
/// of the contacts (open or closed, set by the integrator's events), which
/// the evaluations read.
#[derive(Debug, Clone)]
pub struct Workspace {
    /// Kinematics of every body at the last evaluation (the ground's at 0).
    pub(crate) kin: Vec<BodyKin>,
    /// `F = Q - G^T lambda` and the sink entry of locked coordinates.
    pub(crate) f: Vec<f64>,
    /// `g` (or `gamma`).
    pub(crate) g: Vec<f64>,
    /// `G q' + g_t`.
    pub(crate) w: Vec<f64>,
    /// The velocities with a zero sink entry.
    pub(crate) vx: Vec<f64>,
    /// Whether each contact is closed (the integrator's mode of the step).
    pub(crate) closed: Vec<bool>,
    /// Approach speed of each closed contact at its onset [m/s].
    pub(crate) v0: Vec<f64>,
}

impl Workspace {
    /// A workspace for `bodies` bodies (the ground included), `n`
    /// coordinates, `m` equations and `contacts` contacts, all open.
    pub(crate) fn new(bodies: usize, n: usize, m: usize, contacts: usize) -> Self {
        Self {
            kin: vec![BodyKin::default(); bodies],
            f: vec![0.0; n + 1],
            g: vec![0.0; m],
            w: vec![0.0; m],
            vx: vec![0.0; n + 1],
            closed: vec![false; contacts],
            v0: vec![0.0; contacts],
        }
    }

    /// Whether each contact is closed.
    pub fn closed_contacts(&self) -> &[bool] {
        &self.closed
    }

    /// Closes (with the approach speed `v0` [m/s]) or opens contact `i`.
    /// The integrator does this at its events; a check of the closed
    /// contacts' derivatives sets the modes itself.
    pub fn set_contact(&mut self, i: usize, closed: bool, v0: f64) {
        self.closed[i] = closed;
        self.v0[i] = v0;
    }

    /// The approach speed contact `i` closed with [m/s].
    pub(crate) fn contact_speed(&self, i: usize) -> f64 {
        self.v0[i]
    }

    /// Copies the contact modes of another workspace.
    pub(crate) fn copy_contacts(&mut self, other: &Workspace) {
        self.closed.copy_from_slice(&other.closed);
        self.v0.copy_from_slice(&other.v0);
    }

    /// Generalised forces `F = Q - G^T lambda` of the last
    /// [`super::Assembly::residual`] call (stale after
    /// [`Workspace::swap_results`]) [N, N m].
    pub fn forces(&self) -> &[f64] {
        &self.f[..self.f.len() - 1]
    }
    /// Constraint values `g` of the last [`super::Assembly::residual`] call
    /// (or `gamma` of the last [`super::Assembly::constraint_gamma`] call).
    pub fn constraints(&self) -> &[f64] {
        &self.g
    }
    /// Velocity constraint `G q' + g_t` of the last
    /// [`super::Assembly::residual`] call (stale after
    /// [`Workspace::swap_results`]).
    pub fn velocity_constraints(&self) -> &[f64] {
        &self.w
    }
    /// Exchanges the forces and velocity constraints of the last
    /// [`super::Assembly::residual`] call with `forces` (as long as
    /// [`super::Assembly::workspace_forces_len`]) and `velocity_constraints`
    /// (length `m`): the caller keeps them without a copy, and the
    /// workspace's are stale until the next evaluation. Panics if a length
    /// differs (a caller's error, not an input's).
    pub fn swap_results(&mut self, forces: &mut Vec<f64>, velocity_constraints: &mut Vec<f64>) {
        assert_eq!(forces.len(), self.f.len(), "forces to swap with the workspace's");
        assert_eq!(velocity_constraints.len(), self.w.len(), "velocity constraints to swap with the workspace's");
        std::mem::swap(&mut self.f, forces);
        std::mem::swap(&mut self.w, velocity_constraints);
    }
}

#[cfg(test)]
mod tests {
    use crate::{Assembly, AssemblyOptions};

    /// `swap_results` hands over exactly what the residual put in the
    /// workspace (checked against copies taken before), and refuses vectors
    /// of the wrong length.
    #[test]
    fn swap_results_hands_over_the_last_residual() {
        let asm = Assembly::new(&crate::reference::element_zoo(), &AssemblyOptions::default()).unwrap();
        let mut ws = asm.workspace();
        let (q, v) = asm.initial.clone();
        let lam: Vec<f64> = (0..asm.layout.m).map(|e| 0.1 * e as f64 - 0.3).collect();
        let v: Vec<f64> = v.iter().enumerate().map(|(c, x)| x + 0.01 * c as f64).collect();
        asm.residual(&mut ws, 0.2, &q, &v, &lam);
        let (f, w) = (ws.forces().to_vec(), ws.velocity_constraints().to_vec());
        assert!(f.iter().chain(&w).any(|x| *x != 0.0), "a residual worth comparing");
        let mut forces = vec![0.0; asm.workspace_forces_len()];
        let mut velocity = vec![0.0; asm.layout.m];
        ws.swap_results(&mut forces, &mut velocity);
        assert_eq!(forces[..asm.layout.n], f[..]);
        assert_eq!(velocity, w);
        let short = std::panic::catch_unwind(move || {
            let mut ws = ws;
            ws.swap_results(&mut vec![0.0; asm.layout.n], &mut vec![0.0; asm.layout.m]);
        });
        assert!(short.is_err(), "a force vector without the sink slot is refused");
    }
}
