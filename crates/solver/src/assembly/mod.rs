//! What the solver linearises: the compiled system.
//!
//! [`Assembly`] turns a [`System`] into typed kernel arrays with precomputed
//! scatter indices into
//! - the generalised-force vector `F = Q(t, q, q') - G(q)^T lambda` (length `n`),
//! - the constraint vector `g(q, t)` (length `m`),
//! - three Jacobian arrays laid out like the block iteration matrix: the
//!   stiffness `K = -dF/dq` (the constraint Hessian included), the damping
//!   `D = -dF/dq'` and the constraint gradient `G = dg/dq`.
//!
//! The integrator forms its iteration matrices `c^2 M + c D + K` with the
//! scaled constraint blocks from these arrays
//! ([`crate::integrator::radau5::form_real`]), so each force law is written
//! once and the integrator supplies the factors.
//!
//! Its parts: the force laws (`forces.rs`, `friction.rs`, `contact.rs`),
//! each behind one trait, `ForceKernel` (`element.rs`: force, stiffness
//! and damping, energy, power, reaction), and the constraint primitives
//! (`constraints.rs`) behind another, `Primitive`; their scatter maps
//! (`maps.rs`); the compilation (`build.rs`) and numbering (`layout.rs`);
//! the evaluations, which walk the per-kind lists through the traits:
//! residual and Jacobian (`evaluate.rs`), energies and powers
//! (`energy.rs`), constraint reactions, peak forces and contact states
//! (`reactions.rs`); names of the matrix's rows (`diagnostics.rs`); the
//! value types (`values.rs`) and the scratch space ([`Workspace`]).

mod build;
pub(crate) mod constraints;
pub(crate) mod contact;
mod diagnostics;
pub(crate) mod element;
mod energy;
mod evaluate;
pub(crate) mod forces;
pub(crate) mod friction;
pub(crate) mod kin;
pub(crate) mod layout;
pub(crate) mod linear;
pub(crate) mod maps;
mod reactions;
mod values;
mod workspace;

use crate::error::BuildError;
use crate::linalg::block_lu::BlockSymbolic;
use crate::model::body::{BodyId, Coord};
use crate::model::system::System;
use crate::timefn::TimeFunction;
use constraints::{PrimRef, Primitives};
use element::ForceElements;
use kin::{BodyStatic, V2};
use layout::{Layout, NONE};
use linear::LinearK;
use maps::GEntry;

pub use build::AssemblyOptions;
pub use values::{ContactValue, ForceExtremes, JacobianValues, Powers};
pub use workspace::Workspace;

/// The compiled system.
#[derive(Debug, Clone)]
pub struct Assembly {
    pub(crate) layout: Layout,
    pub(crate) bodies: Vec<BodyStatic>,
    pub(crate) coord_mass: Vec<f64>,
    /// [`crate::Body::tolerance_scale`] of each coordinate's body.
    pub(crate) coord_tolerance_scale: Vec<f64>,
    pub(crate) mass_pos: Vec<u32>,
    /// The force elements, one list per kind.
    pub(crate) elements: ForceElements,
    /// Each body's group ([`crate::System::set_group`]).
    pub(crate) body_group: Vec<u32>,
    /// The number of groups (one more than the largest group of a body).
    pub(crate) groups: usize,
    /// The bodies the contacts touch (not the ground), for evaluating the
    /// contacts alone.
    pub(crate) contact_bodies: Vec<usize>,
    /// The constraint primitives, one list per kind.
    pub(crate) prims: Primitives,
    /// The linear constraints' equations (after the primitives').
    pub(crate) linear: Vec<LinearK>,
    pub(crate) g_entries: Vec<GEntry>,
    /// Reference mass of each equation for scaling the constraint rows.
    pub(crate) eq_mref: Vec<f64>,
    /// Whether each equation is angular (in rad) rather than translational
    /// (in m).
    pub(crate) eq_angular: Vec<bool>,
    pub(crate) constraint_names: Vec<String>,
    pub(crate) constraint_prims: Vec<Vec<PrimRef>>,
    pub(crate) eq_constraint: Vec<u32>,
    pub(crate) gravity: V2,
    pub(crate) ground: [Option<TimeFunction>; 2],
    /// Translational coordinates with their mass, per direction (base excitation, gravity).
    pub(crate) translational: [Vec<(u32, f64)>; 2],
    pub(crate) structural_nnz: usize,
    /// Distinct positions of the damping matrix by row: the entries of row `r` are
    /// `d_cols[d_row_ptr[r]..d_row_ptr[r + 1]]`, as (column coordinate,
    /// position), in the order of their positions.
    pub(crate) d_row_ptr: Vec<u32>,
    pub(crate) d_cols: Vec<(u32, u32)>,
    pub(crate) initial: (Vec<f64>, Vec<f64>),
}

impl Assembly {
    /// Compiles a system.
    pub fn new(system: &System, options: &AssemblyOptions) -> Result<Self, BuildError> {
        build::compile(system, options)
    }

    /// Number of free coordinates `n`.
    pub fn coordinates(&self) -> usize {
        self.layout.n
    }

    /// Number of constraint equations `m`.
    pub fn equations(&self) -> usize {
        self.layout.m
    }

    /// Number of unknowns of the iteration matrix (`n + m`).
    pub fn dim(&self) -> usize {
        self.layout.n + self.layout.m
    }

    /// Structurally non-zero entries of the iteration matrix
    /// `[c^2 M + c D + K, G^T; G, 0]`.
    pub fn jacobian_nnz(&self) -> usize {
        self.structural_nnz
    }

    /// The symbolic block structure.
    pub fn block_structure(&self) -> &BlockSymbolic {
        &self.layout.sym
    }

    /// Coordinate index of a body coordinate (None if locked or ground).
    pub fn coordinate(&self, body: BodyId, coord: Coord) -> Option<usize> {
        let c = self.bodies.get(body.index())?.coord[coord.slot()];
        (c != NONE).then_some(c as usize)
    }

    /// Mass (or inertia) of each coordinate.
    pub fn coordinate_masses(&self) -> &[f64] {
        &self.coord_mass
    }

    /// Initial positions and velocities as given in the system.
    pub fn initial_state(&self) -> (Vec<f64>, Vec<f64>) {
        self.initial.clone()
    }

    /// A workspace sized for this system.
    pub fn workspace(&self) -> Workspace {
        Workspace::new(self.bodies.len(), self.layout.n, self.layout.m, self.elements.contacts.len())
    }

    /// Length of the workspace's force vector, which [`Workspace::swap_results`]
    /// exchanges: the `n` forces of [`Workspace::forces`] and a sink for the
    /// forces on locked coordinates.
    pub fn workspace_forces_len(&self) -> usize {
        self.layout.n + 1
    }

    /// Empty Jacobian arrays.
    pub fn jacobian_values(&self) -> JacobianValues {
        let len = self.layout.sym.nnz() + 1;
        JacobianValues { k: vec![0.0; len], d: vec![0.0; len], g: vec![0.0; self.g_entries.len()] }
    }

    /// Number of contacts.
    pub fn contact_count(&self) -> usize {
        self.elements.contacts.len()
    }

    /// First breakpoint of any time function strictly after `t`.
    pub fn next_breakpoint(&self, t: f64) -> Option<f64> {
        let mut best: Option<f64> = None;
        let mut consider = |x: Option<f64>| {
            if let Some(x) = x {
                best = Some(best.map_or(x, |b: f64| b.min(x)));
            }
        };
        for g in self.ground.iter().flatten() {
            consider(g.next_breakpoint(t));
        }
        for (k, _) in &self.elements.loads {
            consider(k.next_breakpoint(t));
        }
        for (k, _) in &self.prims.drivers {
            consider(k.motion.next_breakpoint(t));
        }
        best
    }
}
