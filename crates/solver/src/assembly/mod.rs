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
//! scaled constraint blocks (see [`Assembly::form`]) from these arrays, so
//! each force law is written once and the integrator supplies the factors.

mod build;
pub(crate) mod constraints;
pub(crate) mod contact;
pub(crate) mod forces;
pub(crate) mod kin;
pub(crate) mod layout;

use crate::error::BuildError;
use crate::linalg::block_lu::BlockSymbolic;
use crate::linalg::scalar::{Complex64, Scalar};
use crate::model::body::{BodyId, Coord};
use crate::model::constraint::ConstraintId;
use crate::model::system::System;
use crate::timefn::TimeFunction;
use constraints::{AngleK, DriverK, LineK, PointK, Rows};
use contact::ContactK;
use forces::{BushingK, CoordSpringK, CustomK, FrictionK, LoadK, SpringK};
use kin::{BodyKin, Mat6, Rot, V2};
use layout::{Layout, NONE};

pub use build::AssemblyOptions;

/// Scatter map of a two-body element.
#[derive(Debug, Clone)]
pub(crate) struct PairMap {
    /// Index into `F` of each of the 6 slots (the sink `n` when locked).
    pub f: [u32; 6],
    /// Position in the Jacobian arrays of each entry of the 6x6 block.
    pub jac: [u32; 36],
}

/// Scatter map of a constraint primitive.
#[derive(Debug, Clone)]
pub(crate) struct PrimMap {
    /// First equation index.
    pub eq: u32,
    /// Number of equations (1 or 2).
    pub rows: u8,
    /// Index into `F` of each of the 6 slots.
    pub f: [u32; 6],
    /// Hessian positions (6x6).
    pub h: [u32; 36],
    /// First entry in [`Assembly::g_entries`] and how many.
    pub g_start: u32,
    pub g_count: u8,
}

/// One stored entry of `G`: its position in the matrix, the position of its
/// transpose, and which row and slot of the primitive it is.
#[derive(Debug, Clone, Copy)]
pub(crate) struct GEntry {
    pub pos: u32,
    pub pos_t: u32,
    pub eq: u32,
    pub coord: u32,
    pub row: u8,
    pub slot: u8,
}

/// Per-body data for the kinematics cache.
#[derive(Debug, Clone)]
pub(crate) struct BodyStatic {
    pub coord: [u32; 3],
    pub pose0: [f64; 3],
    /// Rotation at `pose0[2]` (used while the angle is not a coordinate).
    pub rot0: Rot,
}

/// A friction element whose slider runs on a line of its base, for the
/// integrator's local solve ([`Assembly::line_sliders`]).
#[derive(Debug, Clone)]
pub(crate) struct SliderInfo {
    /// Index of the friction element.
    pub friction: u32,
    /// Index of the line primitive.
    line: u32,
    /// The slider's x and y coordinates.
    pub coords: [u32; 2],
    /// Positions of the slider's x-y block (xx, xy, yx, yy) in the Jacobian arrays.
    pub jac: [u32; 4],
    /// `mu n F_N` [N].
    pub force: f64,
    /// Regularisation velocity [m/s].
    pub v_eps: f64,
    kernel: FrictionK,
}

impl SliderInfo {
    /// The law's `phi` along a unit direction and its slope, for a relative
    /// velocity with components `a` along the direction and `b` across it.
    #[inline]
    pub fn law_along(&self, a: f64, b: f64) -> (f64, f64) {
        self.kernel.law_along(a, b)
    }

    /// Whether the law is linear inside the zone `|v| < v_eps` and, along a
    /// line crossed by no velocity, constant outside it (the linear law).
    pub fn is_linear_law(&self) -> bool {
        self.kernel.law == crate::model::force::FrictionLaw::Linear
    }
}

/// Which primitive a user constraint consists of.
#[derive(Debug, Clone, Copy)]
pub(crate) enum PrimRef {
    Point(u32),
    Angle(u32),
    Line(u32),
    Driver(u32),
}

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

/// Power flows at one state, for the energy balance [W].
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
    /// Largest bushing force magnitude [N].
    pub bushing: f64,
    /// Largest friction force magnitude [N].
    pub friction: f64,
}

/// Scratch space for evaluations; one per thread.
#[derive(Debug, Clone)]
pub struct Workspace {
    kin: Vec<BodyKin>,
    f: Vec<f64>,
    g: Vec<f64>,
    w: Vec<f64>,
    vx: Vec<f64>,
    km: Mat6,
    dm: Mat6,
    /// Whether each contact is closed (the integrator's mode of the step).
    closed: Vec<bool>,
    /// Approach speed of each closed contact at its onset [m/s].
    v0: Vec<f64>,
}

/// A contact's state at one instant ([`Assembly::contacts`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactValue {
    /// Whether the contact is closed.
    pub closed: bool,
    /// Penetration [m] (positive when overlapping, whatever the mode).
    pub penetration: f64,
    /// Its rate [m/s].
    pub rate: f64,
    /// Force of the law [N]: of a closed contact (may be below zero just
    /// before a release event); of an open one, the force the law would
    /// give at this penetration and rate (0 when not penetrating), whose
    /// sign says whether closing it would push or pull.
    pub force: f64,
}

impl Workspace {
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

    /// Copies the contact modes of another workspace.
    pub(crate) fn copy_contacts(&mut self, other: &Workspace) {
        self.closed.copy_from_slice(&other.closed);
        self.v0.copy_from_slice(&other.v0);
    }

    /// Generalised forces `F = Q - G^T lambda` of the last [`Assembly::residual`]
    /// call (stale after [`Workspace::swap_results`]).
    pub fn forces(&self) -> &[f64] {
        &self.f[..self.f.len() - 1]
    }
    /// Constraint values `g` of the last [`Assembly::residual`] call (or
    /// `gamma` of the last [`Assembly::constraint_gamma`] call).
    pub fn constraints(&self) -> &[f64] {
        &self.g
    }
    /// Velocity constraint `G q' + g_t` of the last [`Assembly::residual`] call
    /// (stale after [`Workspace::swap_results`]).
    pub fn velocity_constraints(&self) -> &[f64] {
        &self.w
    }
    /// Exchanges the forces and velocity constraints of the last
    /// [`Assembly::residual`] call with `forces` (as long as
    /// [`Assembly::workspace_forces_len`]) and `velocity_constraints`
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

/// The compiled system.
#[derive(Debug, Clone)]
pub struct Assembly {
    pub(crate) layout: Layout,
    pub(crate) bodies: Vec<BodyStatic>,
    pub(crate) coord_mass: Vec<f64>,
    /// [`crate::Body::tolerance_scale`] of each coordinate's body.
    pub(crate) coord_tolerance_scale: Vec<f64>,
    pub(crate) mass_pos: Vec<u32>,
    pub(crate) bushings: Vec<(BushingK, PairMap)>,
    pub(crate) frictions: Vec<(FrictionK, PairMap)>,
    pub(crate) springs: Vec<(SpringK, PairMap)>,
    pub(crate) coord_springs: Vec<(CoordSpringK, u32, u32)>,
    pub(crate) loads: Vec<(LoadK, PairMap)>,
    pub(crate) customs: Vec<(CustomK, PairMap)>,
    pub(crate) contacts: Vec<(ContactK, PairMap)>,
    /// The bodies the contacts touch (not the ground), for evaluating the
    /// contacts alone.
    pub(crate) contact_bodies: Vec<usize>,
    pub(crate) points: Vec<(PointK, PrimMap)>,
    pub(crate) angles: Vec<(AngleK, PrimMap)>,
    pub(crate) lines: Vec<(LineK, PrimMap)>,
    pub(crate) drivers: Vec<(DriverK, PrimMap)>,
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

#[inline]
fn scatter6(f: &mut [f64], idx: &[u32; 6], q: &[f64; 6]) {
    for i in 0..6 {
        f[idx[i] as usize] += q[i];
    }
}

#[inline]
fn scatter36(vals: &mut [f64], pos: &[u32; 36], m: &Mat6) {
    for i in 0..6 {
        for j in 0..6 {
            vals[pos[i * 6 + j] as usize] += m[i][j];
        }
    }
}

#[inline]
fn zero6(m: &mut Mat6) {
    *m = [[0.0; 6]; 6];
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
        Workspace {
            kin: vec![BodyKin::default(); self.bodies.len()],
            f: vec![0.0; self.workspace_forces_len()],
            g: vec![0.0; self.layout.m],
            w: vec![0.0; self.layout.m],
            vx: vec![0.0; self.layout.n + 1],
            km: [[0.0; 6]; 6],
            dm: [[0.0; 6]; 6],
            closed: vec![false; self.contacts.len()],
            v0: vec![0.0; self.contacts.len()],
        }
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

    /// Structural non-zeros of the iteration matrix as (row, column) pairs in
    /// natural numbering: coordinates `0..n` in body order, then constraint
    /// equations `n..n+m` (for plotting the sparsity pattern).
    pub fn jacobian_pattern(&self) -> Vec<(u32, u32)> {
        let lay = &self.layout;
        let n = lay.n as u32;
        let mut natural = vec![0u32; self.dim()];
        for (c, &u) in lay.unknown_of_coord.iter().enumerate() {
            natural[u as usize] = c as u32;
        }
        for (e, &u) in lay.unknown_of_eq.iter().enumerate() {
            natural[u as usize] = n + e as u32;
        }
        let mut entries: Vec<(u32, u32)> = build::structural_positions(self)
            .into_iter()
            .filter_map(|p| self.position_unknowns(p as usize))
            .map(|(r, c)| (natural[r], natural[c]))
            .collect();
        entries.sort_unstable();
        entries
    }

    /// Body index of each coordinate (natural numbering).
    pub fn coordinate_bodies(&self) -> Vec<u32> {
        self.layout.coord_body.iter().map(|&(b, _)| b).collect()
    }

    /// Row and column unknowns of a position in the Jacobian arrays.
    pub fn position_unknowns(&self, pos: usize) -> Option<(usize, usize)> {
        let sym = &self.layout.sym;
        sym.sub_blocks().find_map(|(i, j, off, _)| {
            let (si, ni) = sym.span(i);
            let (sj, nj) = sym.span(j);
            (pos >= off && pos < off + ni * nj).then(|| (si + (pos - off) / nj, sj + (pos - off) % nj))
        })
    }

    /// A readable name of an unknown of the iteration matrix, such as
    /// `phi of "beam 3"` or `equation 1 of "pivot"`.
    pub fn unknown_label(&self, unknown: usize) -> String {
        if let Some(c) = self.layout.unknown_of_coord.iter().position(|&u| u as usize == unknown) {
            let (b, s) = self.layout.coord_body[c];
            let body = self.layout.position_names[self.layout.unknown_place[unknown].0 as usize].clone();
            let _ = b;
            return format!("{} of {body}", ["x", "y", "phi"][s as usize]);
        }
        if let Some(e) = self.layout.unknown_of_eq.iter().position(|&u| u as usize == unknown) {
            let ci = self.eq_constraint[e] as usize;
            let first = self.eq_constraint.iter().position(|&x| x as usize == ci).unwrap_or(e);
            return format!("equation {} of \"{}\"", e - first, self.constraint_names[ci]);
        }
        format!("unknown {unknown}")
    }

    /// Name of a constraint.
    pub fn constraint_name(&self, id: usize) -> &str {
        &self.constraint_names[id]
    }

    /// The user constraint an equation belongs to.
    pub fn equation_constraint(&self, eq: usize) -> usize {
        self.eq_constraint[eq] as usize
    }

    #[inline(always)]
    fn load_kin(&self, ws: &mut Workspace, q: &[f64], v: &[f64]) {
        // (into a slice: see `constraint_rows`)
        let kin = &mut ws.kin[..];
        for b in 1..self.bodies.len() {
            kin[b] = self.body_kin(b, q, v);
        }
    }

    #[inline(always)]
    fn load_body(&self, ws: &mut Workspace, b: usize, q: &[f64], v: &[f64]) {
        ws.kin[b] = self.body_kin(b, q, v);
    }

    /// The kinematics of body `b` at `(q, v)`.
    #[inline(always)]
    fn body_kin(&self, b: usize, q: &[f64], v: &[f64]) -> BodyKin {
        let st = &self.bodies[b];
        let mut p = st.pose0;
        let mut w = [0.0; 3];
        for s in 0..3 {
            let c = st.coord[s];
            if c != NONE {
                p[s] = q[c as usize];
                w[s] = v[c as usize];
            }
        }
        let rot = if st.coord[2] == NONE { st.rot0 } else { Rot::new(p[2]) };
        BodyKin { r: V2::new(p[0], p[1]), phi: p[2], rot, v: V2::new(w[0], w[1]), w: w[2] }
    }

    fn prim_rows(&self, ws: &Workspace, t: f64, prim: PrimRef) -> (Rows, &PrimMap) {
        match prim {
            PrimRef::Point(i) => {
                let (k, m) = &self.points[i as usize];
                (k.rows(&ws.kin[k.a as usize], &ws.kin[k.b as usize]), m)
            }
            PrimRef::Angle(i) => {
                let (k, m) = &self.angles[i as usize];
                (k.rows(&ws.kin[k.a as usize], &ws.kin[k.b as usize]), m)
            }
            PrimRef::Line(i) => {
                let (k, m) = &self.lines[i as usize];
                (k.rows(&ws.kin[k.a as usize], &ws.kin[k.b as usize]), m)
            }
            PrimRef::Driver(i) => {
                let (k, m) = &self.drivers[i as usize];
                (k.rows(&ws.kin[k.a as usize], t), m)
            }
        }
    }

    /// Evaluates `F = Q(t, q, q') - G^T lambda`, `g(q, t)` and the velocity
    /// constraint `G(q) q' + g_t(t)` into the workspace ([`Workspace::forces`],
    /// [`Workspace::constraints`], [`Workspace::velocity_constraints`]).
    pub fn residual(&self, ws: &mut Workspace, t: f64, q: &[f64], v: &[f64], lam: &[f64]) {
        crate::isa::run(
            #[inline(always)]
            || self.residual_impl(ws, t, q, v, lam),
        )
    }

    /// [`Self::residual`], compiled into each version of [`crate::isa::run`].
    #[inline(always)]
    fn residual_impl(&self, ws: &mut Workspace, t: f64, q: &[f64], v: &[f64], lam: &[f64]) {
        self.load_kin(ws, q, v);
        ws.f.iter_mut().for_each(|x| *x = 0.0);
        self.applied_forces(ws, t);
        self.constraint_rows(ws, t, v, Some(lam));
    }

    /// Evaluates only `g(q, t)` and the velocity constraint `G(q) q' + g_t(t)`
    /// ([`Workspace::constraints`], [`Workspace::velocity_constraints`]);
    /// [`Workspace::forces`] is left as it was.
    pub fn constraint_residuals(&self, ws: &mut Workspace, t: f64, q: &[f64], v: &[f64]) {
        crate::isa::run(
            #[inline(always)]
            || self.constraint_residuals_impl(ws, t, q, v),
        )
    }

    /// [`Self::constraint_residuals`], compiled into each version of [`crate::isa::run`].
    #[inline(always)]
    fn constraint_residuals_impl(&self, ws: &mut Workspace, t: f64, q: &[f64], v: &[f64]) {
        self.load_kin(ws, q, v);
        self.constraint_rows(ws, t, v, None);
    }

    /// Constraint rows at the loaded kinematics: `g`, `G q' + g_t` and, with
    /// multipliers, `-G^T lambda` added into the forces.
    #[inline(always)]
    fn constraint_rows(&self, ws: &mut Workspace, t: f64, v: &[f64], lam: Option<&[f64]>) {
        let Workspace { kin, f, g, w, vx, .. } = ws;
        // (slices held in registers: through the vectors, every store would
        // make the compiler reload their addresses)
        let (kin, f, g, w, vx) = (&kin[..], &mut f[..], &mut g[..], &mut w[..], &mut vx[..]);
        vx[..v.len()].copy_from_slice(v);
        vx[v.len()] = 0.0;
        for (k, map) in &self.points {
            apply_rows(f, g, w, vx, map, &k.rows(&kin[k.a as usize], &kin[k.b as usize]), lam);
        }
        for (k, map) in &self.angles {
            let rows = k.rows(&kin[k.a as usize], &kin[k.b as usize]);
            apply_rows_in(f, g, w, vx, map, &rows, lam, &ANGLE_SLOTS);
        }
        for (k, map) in &self.lines {
            apply_rows(f, g, w, vx, map, &k.rows(&kin[k.a as usize], &kin[k.b as usize]), lam);
        }
        for (k, map) in &self.drivers {
            apply_rows(f, g, w, vx, map, &k.rows(&kin[k.a as usize], t), lam);
            w[map.eq as usize] += k.time_derivatives(t).0;
        }
    }

    /// `out = G x` with the gradient values of `jac` (`x` over coordinates,
    /// `out` over equations).
    pub(crate) fn gradient_product<T: Scalar>(&self, jac: &JacobianValues, x: &[T], out: &mut [T]) {
        out.iter_mut().for_each(|o| *o = T::ZERO);
        for (e, &gv) in self.g_entries.iter().zip(&jac.g) {
            out[e.eq as usize] += T::from_real(gv) * x[e.coord as usize];
        }
    }

    /// Generalised applied forces `Q(t, q, q')` added into `ws.f` (kinematics loaded).
    #[inline(always)]
    fn applied_forces(&self, ws: &mut Workspace, t: f64) {
        let Workspace { kin, f, closed, v0, .. } = ws;
        // (slices: see `constraint_rows`)
        let (kin, f, closed, v0) = (&kin[..], &mut f[..], &closed[..], &v0[..]);
        for (i, (k, map)) in self.contacts.iter().enumerate() {
            if closed[i] {
                scatter6(f, &map.f, &k.force(&kin[k.a as usize], &kin[k.b as usize], v0[i]));
            }
        }
        for (k, map) in &self.bushings {
            scatter6(f, &map.f, &k.force(&kin[k.a as usize], &kin[k.b as usize]));
        }
        for (k, map) in &self.frictions {
            scatter6(f, &map.f, &k.force(&kin[k.a as usize], &kin[k.b as usize]));
        }
        for (k, map) in &self.springs {
            scatter6(f, &map.f, &k.force(&kin[k.a as usize], &kin[k.b as usize]));
        }
        for (k, fi, _) in &self.coord_springs {
            f[*fi as usize] += k.force(&kin[k.body as usize]);
        }
        for (k, map) in &self.loads {
            scatter6(f, &map.f, &k.force(&kin[k.a as usize], t));
        }
        for (k, map) in &self.customs {
            scatter6(f, &map.f, &k.force(&kin[k.a as usize], &kin[k.b as usize], t));
        }
        for dir in 0..2 {
            let ag = self.ground[dir].as_ref().map_or(0.0, |a| a.value(t));
            let gacc = if dir == 0 { self.gravity.x } else { self.gravity.y };
            let acc = gacc - ag;
            if acc != 0.0 {
                for &(c, mass) in &self.translational[dir] {
                    f[c as usize] += mass * acc;
                }
            }
        }
    }

    /// Evaluates the Jacobian arrays at a state (the constraint Hessian uses `lam`).
    pub fn jacobian(&self, ws: &mut Workspace, t: f64, q: &[f64], v: &[f64], lam: &[f64], jac: &mut JacobianValues) {
        self.jacobian_impl(ws, t, q, v, lam, jac, None);
    }

    /// The Jacobian arrays for the integrator's iteration matrices: as
    /// [`Assembly::jacobian`], except that each friction element `e` with
    /// `zone[e]` enters with the slope of its regularisation zone (see
    /// [`forces::FrictionK::jacobian`]).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn iteration_jacobian(
        &self,
        ws: &mut Workspace,
        t: f64,
        q: &[f64],
        v: &[f64],
        lam: &[f64],
        zone: &[bool],
        jac: &mut JacobianValues,
    ) {
        self.jacobian_impl(ws, t, q, v, lam, jac, Some(zone));
    }

    #[allow(clippy::too_many_arguments)]
    fn jacobian_impl(
        &self,
        ws: &mut Workspace,
        t: f64,
        q: &[f64],
        v: &[f64],
        lam: &[f64],
        jac: &mut JacobianValues,
        zone: Option<&[bool]>,
    ) {
        self.load_kin(ws, q, v);
        jac.k.iter_mut().for_each(|x| *x = 0.0);
        jac.d.iter_mut().for_each(|x| *x = 0.0);
        let Workspace { kin, km, dm, closed, v0, .. } = ws;
        for (k, map) in &self.bushings {
            zero6(km);
            zero6(dm);
            k.jacobian(&kin[k.a as usize], &kin[k.b as usize], km, dm);
            scatter36(&mut jac.k, &map.jac, km);
            scatter36(&mut jac.d, &map.jac, dm);
        }
        for (i, (k, map)) in self.contacts.iter().enumerate() {
            if closed[i] {
                zero6(km);
                zero6(dm);
                k.jacobian(&kin[k.a as usize], &kin[k.b as usize], v0[i], km, dm);
                scatter36(&mut jac.k, &map.jac, km);
                scatter36(&mut jac.d, &map.jac, dm);
            }
        }
        for (i, (k, map)) in self.frictions.iter().enumerate() {
            zero6(km);
            zero6(dm);
            let zone_slope = zone.is_some_and(|z| z[i]);
            k.jacobian(&kin[k.a as usize], &kin[k.b as usize], km, dm, zone_slope);
            scatter36(&mut jac.k, &map.jac, km);
            scatter36(&mut jac.d, &map.jac, dm);
        }
        for (k, map) in &self.springs {
            zero6(km);
            zero6(dm);
            k.jacobian(&kin[k.a as usize], &kin[k.b as usize], km, dm);
            scatter36(&mut jac.k, &map.jac, km);
            scatter36(&mut jac.d, &map.jac, dm);
        }
        for (k, _, pos) in &self.coord_springs {
            jac.k[*pos as usize] += k.k;
            jac.d[*pos as usize] += k.c;
        }
        for (k, map) in &self.loads {
            zero6(km);
            k.jacobian(&kin[k.a as usize], t, km);
            scatter36(&mut jac.k, &map.jac, km);
        }
        for (k, map) in &self.customs {
            zero6(km);
            zero6(dm);
            k.jacobian(&kin[k.a as usize], &kin[k.b as usize], t, km, dm);
            scatter36(&mut jac.k, &map.jac, km);
            scatter36(&mut jac.d, &map.jac, dm);
        }
        for (k, map) in &self.points {
            let r = k.rows(&kin[k.a as usize], &kin[k.b as usize]);
            store_grad(&mut jac.g, &self.g_entries, map, &r);
            zero6(km);
            let e = map.eq as usize;
            k.hessian(&kin[k.a as usize], &kin[k.b as usize], &lam[e..e + 2], km);
            scatter36(&mut jac.k, &map.h, km);
        }
        for (k, map) in &self.angles {
            let r = k.rows(&kin[k.a as usize], &kin[k.b as usize]);
            store_grad(&mut jac.g, &self.g_entries, map, &r);
        }
        for (k, map) in &self.lines {
            let r = k.rows(&kin[k.a as usize], &kin[k.b as usize]);
            store_grad(&mut jac.g, &self.g_entries, map, &r);
            zero6(km);
            k.hessian(&kin[k.a as usize], &kin[k.b as usize], lam[map.eq as usize], km);
            scatter36(&mut jac.k, &map.h, km);
        }
        for (k, map) in &self.drivers {
            let r = k.rows(&kin[k.a as usize], t);
            store_grad(&mut jac.g, &self.g_entries, map, &r);
        }
    }

    /// Number of friction elements.
    pub(crate) fn friction_count(&self) -> usize {
        self.frictions.len()
    }

    /// The friction elements whose slider runs on a line of its base (of a
    /// prismatic joint or a point-on-line constraint) and moves freely in x
    /// and y: those the integrator solves locally.
    pub(crate) fn line_sliders(&self) -> Vec<SliderInfo> {
        let n = self.coordinates() as u32;
        self.frictions
            .iter()
            .enumerate()
            .filter_map(|(e, (k, map))| {
                let line = self.lines.iter().position(|(l, _)| l.a == k.a && l.b == k.b)?;
                let coords = [map.f[0], map.f[1]];
                (coords[0] < n && coords[1] < n).then(|| SliderInfo {
                    friction: e as u32,
                    line: line as u32,
                    coords,
                    jac: [map.jac[0], map.jac[1], map.jac[6], map.jac[7]],
                    force: k.force,
                    v_eps: k.v_eps,
                    kernel: k.clone(),
                })
            })
            .collect()
    }

    /// A slider's relative sliding velocity and the unit direction of its
    /// line, from the kinematics loaded by the last evaluation (e.g.
    /// [`Assembly::residual`]).
    pub(crate) fn slider_state(&self, ws: &Workspace, s: &SliderInfo) -> (V2, V2) {
        let k = &s.kernel;
        let (ka, kb) = (&ws.kin[k.a as usize], &ws.kin[k.b as usize]);
        (k.rel_velocity(ka, kb), kb.rot.apply(self.lines[s.line as usize].0.ub))
    }

    /// The acceleration-free part of `d^2 g/dt^2` (for consistent accelerations),
    /// into [`Workspace::constraints`].
    pub fn constraint_gamma(&self, ws: &mut Workspace, t: f64, q: &[f64], v: &[f64]) {
        self.load_kin(ws, q, v);
        let Workspace { kin, g, .. } = ws;
        for (k, m) in &self.points {
            let gm = k.gamma(&kin[k.a as usize], &kin[k.b as usize]);
            g[m.eq as usize] = gm[0];
            g[m.eq as usize + 1] = gm[1];
        }
        for (_, m) in &self.angles {
            g[m.eq as usize] = 0.0;
        }
        for (k, m) in &self.lines {
            g[m.eq as usize] = k.gamma(&kin[k.a as usize], &kin[k.b as usize]);
        }
        for (k, m) in &self.drivers {
            g[m.eq as usize] = k.time_derivatives(t).1;
        }
    }

    /// Kinetic energy `1/2 q'^T M q'` [J].
    pub fn kinetic_energy(&self, v: &[f64]) -> f64 {
        0.5 * self.coord_mass.iter().zip(v).map(|(m, v)| m * v * v).sum::<f64>()
    }

    /// Energy stored in springs, bushings and the gravity field [J].
    pub fn potential_energy(&self, ws: &mut Workspace, q: &[f64]) -> f64 {
        // velocities do not enter stored energy; q stands in for them
        self.load_kin(ws, q, q);
        self.loaded_potential_energy(ws, q)
    }

    /// [`Assembly::potential_energy`] at the positions `q` whose kinematics
    /// the last evaluation loaded into `ws` (a residual at `q`, say), which
    /// saves loading them again.
    pub(crate) fn loaded_potential_energy(&self, ws: &Workspace, q: &[f64]) -> f64 {
        let kin = &ws.kin;
        let mut e = 0.0;
        for (k, _) in &self.bushings {
            e += k.potential(&kin[k.a as usize], &kin[k.b as usize]);
        }
        for (k, _) in &self.springs {
            e += k.potential(&kin[k.a as usize], &kin[k.b as usize]);
        }
        for (k, _, _) in &self.coord_springs {
            e += k.potential(&kin[k.body as usize]);
        }
        for (i, (k, _)) in self.contacts.iter().enumerate() {
            if ws.closed[i] {
                e += k.law.energy(k.gap(&kin[k.a as usize], &kin[k.b as usize]).delta);
            }
        }
        for dir in 0..2 {
            let gacc = if dir == 0 { self.gravity.x } else { self.gravity.y };
            if gacc != 0.0 {
                for &(c, mass) in &self.translational[dir] {
                    e -= mass * gacc * q[c as usize];
                }
            }
        }
        e
    }

    /// Power flows at a state.
    pub fn powers(&self, ws: &mut Workspace, t: f64, q: &[f64], v: &[f64], lam: &[f64]) -> Powers {
        crate::isa::run(
            #[inline(always)]
            || self.powers_impl(ws, t, q, v, lam),
        )
    }

    /// [`Self::powers`], compiled into each version of [`crate::isa::run`].
    #[inline(always)]
    fn powers_impl(&self, ws: &mut Workspace, t: f64, q: &[f64], v: &[f64], lam: &[f64]) -> Powers {
        self.load_kin(ws, q, v);
        let kin = &ws.kin[..];
        let mut p = Powers::default();
        for (k, _) in &self.bushings {
            p.damping += k.dissipation(&kin[k.a as usize], &kin[k.b as usize]);
        }
        for (k, _) in &self.springs {
            p.damping += k.dissipation(&kin[k.a as usize], &kin[k.b as usize]);
        }
        for (k, _, _) in &self.coord_springs {
            p.damping += k.dissipation(&kin[k.body as usize]);
        }
        for (k, _) in &self.frictions {
            p.friction += k.dissipation(&kin[k.a as usize], &kin[k.b as usize]);
        }
        for (i, (k, _)) in self.contacts.iter().enumerate() {
            if ws.closed[i] {
                let g = k.gap(&kin[k.a as usize], &kin[k.b as usize]);
                p.contact += k.law.dissipation(g.delta, g.rate, ws.v0[i]);
            }
        }
        for (k, _) in &self.loads {
            p.applied += k.power(&kin[k.a as usize], t);
        }
        for (k, map) in &self.customs {
            let qf = k.force(&kin[k.a as usize], &kin[k.b as usize], t);
            for s in 0..6 {
                let c = map.f[s] as usize;
                if c < self.layout.n {
                    p.applied += qf[s] * v[c];
                }
            }
        }
        for dir in 0..2 {
            if let Some(a) = &self.ground[dir] {
                let ag = a.value(t);
                if ag != 0.0 {
                    // (the momentum in four partial sums: one sum's chain of
                    // additions would take longer than the products)
                    let mut momentum = [0.0; 4];
                    for (i, &(c, mass)) in self.translational[dir].iter().enumerate() {
                        momentum[i % 4] += mass * v[c as usize];
                    }
                    p.base -= ag * ((momentum[0] + momentum[1]) + (momentum[2] + momentum[3]));
                }
            }
        }
        for (k, m) in &self.drivers {
            p.constraints += lam[m.eq as usize] * k.time_derivatives(t).0;
        }
        p
    }

    /// Number of contacts.
    pub fn contact_count(&self) -> usize {
        self.contacts.len()
    }

    /// The state of every contact at `(q, v)` into `out` (one per contact,
    /// in the order the system added them), with the modes of `ws`.
    pub fn contacts(&self, ws: &mut Workspace, q: &[f64], v: &[f64], out: &mut [ContactValue]) {
        // the integrator asks at every step: load only the bodies involved
        for &b in &self.contact_bodies {
            self.load_body(ws, b, q, v);
        }
        for (i, ((k, _), o)) in self.contacts.iter().zip(out.iter_mut()).enumerate() {
            let g = k.gap(&ws.kin[k.a as usize], &ws.kin[k.b as usize]);
            let force = if ws.closed[i] || g.delta > 0.0 { k.law.eval(g.delta, g.rate, ws.v0[i]).0 } else { 0.0 };
            *o = ContactValue { closed: ws.closed[i], penetration: g.delta, rate: g.rate, force };
        }
    }

    /// Stored elastic energy of contact `i` at penetration `d` [J].
    pub(crate) fn contact_energy(&self, i: usize, d: f64) -> f64 {
        self.contacts[i].0.law.energy(d)
    }

    /// The coordinates (up to 6, `n` for locked ones) contact `i` depends on.
    pub(crate) fn contact_coords(&self, i: usize) -> [u32; 6] {
        self.contacts[i].1.f
    }

    /// Largest bushing and friction force magnitudes at a state.
    pub fn force_extremes(&self, ws: &mut Workspace, q: &[f64], v: &[f64]) -> ForceExtremes {
        crate::isa::run(
            #[inline(always)]
            || self.force_extremes_impl(ws, q, v),
        )
    }

    /// [`Self::force_extremes`], compiled into each version of [`crate::isa::run`].
    #[inline(always)]
    fn force_extremes_impl(&self, ws: &mut Workspace, q: &[f64], v: &[f64]) -> ForceExtremes {
        self.load_kin(ws, q, v);
        let kin = &ws.kin[..];
        // (the largest square, then one root: the same number as the
        // largest root, since the root is monotonic and correctly rounded)
        let (mut bushing, mut friction) = (0.0f64, 0.0f64);
        for (k, _) in &self.bushings {
            bushing = bushing.max(k.force_magnitude_squared(&kin[k.a as usize], &kin[k.b as usize]));
        }
        for (k, _) in &self.frictions {
            friction = friction.max(k.force_magnitude_squared(&kin[k.a as usize], &kin[k.b as usize]));
        }
        ForceExtremes { bushing: bushing.sqrt(), friction: friction.sqrt() }
    }

    /// Reaction of a constraint on one body, `-G^T lambda` restricted to the
    /// body: (fx [N], fy [N], torque about the centre of mass [N m]). Locked
    /// coordinates of the body report zero.
    pub fn constraint_reaction(
        &self,
        ws: &mut Workspace,
        t: f64,
        q: &[f64],
        lam: &[f64],
        constraint: ConstraintId,
        body: BodyId,
    ) -> [f64; 3] {
        self.reaction_sum(ws, t, q, lam, &[constraint], body)
    }

    /// Sum of the reactions of several constraints on one body (see
    /// [`Assembly::constraint_reaction`]); only the bodies involved are
    /// evaluated, so this is cheap enough to call at every output time.
    pub fn reaction_sum(
        &self,
        ws: &mut Workspace,
        t: f64,
        q: &[f64],
        lam: &[f64],
        constraints: &[ConstraintId],
        body: BodyId,
    ) -> [f64; 3] {
        let mut out = [0.0; 3];
        let coords = self.bodies[body.index()].coord;
        for id in constraints {
            let Some(prims) = self.constraint_prims.get(id.index()) else {
                continue;
            };
            for &prim in prims {
                let (a, b) = self.prim_bodies(prim);
                // velocities do not enter the reaction; q stands in for them
                self.load_body(ws, a as usize, q, q);
                if b != 0 {
                    self.load_body(ws, b as usize, q, q);
                }
                let (rows, map) = self.prim_rows(ws, t, prim);
                for r in 0..map.rows as usize {
                    let l = lam[map.eq as usize + r];
                    for slot in 0..6 {
                        let fi = map.f[slot];
                        if let Some(s) = coords.iter().position(|&c| c == fi && c != NONE) {
                            out[s] -= rows.grad[r][slot] * l;
                        }
                    }
                }
            }
        }
        out
    }

    fn prim_bodies(&self, prim: PrimRef) -> (u32, u32) {
        match prim {
            PrimRef::Point(i) => (self.points[i as usize].0.a, self.points[i as usize].0.b),
            PrimRef::Angle(i) => (self.angles[i as usize].0.a, self.angles[i as usize].0.b),
            PrimRef::Line(i) => (self.lines[i as usize].0.a, self.lines[i as usize].0.b),
            PrimRef::Driver(i) => (self.drivers[i as usize].0.a, 0),
        }
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
        for (k, _) in &self.loads {
            consider(k.next_breakpoint(t));
        }
        for (k, _) in &self.drivers {
            consider(k.motion.next_breakpoint(t));
        }
        best
    }

    /// Writes the iteration matrix `c2 M + c1 D + K` with the constraint blocks
    /// scaled by `gscale * m_ref` into `out` (block layout). Returns nothing;
    /// `out` must have [`BlockSymbolic::nnz`] entries.
    pub(crate) fn form<T: Scalar>(&self, c2: T, c1: T, kcoef: f64, gscale: f64, jac: &JacobianValues, out: &mut [T]) {
        let nnz = out.len();
        for ((o, &k), &d) in out.iter_mut().zip(&jac.k[..nnz]).zip(&jac.d[..nnz]) {
            *o = T::from_real(kcoef * k) + c1.mul_real(d);
        }
        for (&p, &m) in self.mass_pos.iter().zip(&self.coord_mass) {
            out[p as usize] += c2.mul_real(m);
        }
        for (e, &g) in self.g_entries.iter().zip(&jac.g) {
            let v = T::from_real(gscale * self.eq_mref[e.eq as usize] * g);
            out[e.pos as usize] = v;
            out[e.pos_t as usize] = v;
        }
    }

    /// The real Radau iteration matrix `[c^2 M + c D + K, G^T S; S G, 0]`
    /// (`S = c^2 m_ref` per equation) in block layout; `out` has
    /// [`BlockSymbolic::nnz`] entries.
    pub fn form_real(&self, c: f64, jac: &JacobianValues, out: &mut [f64]) {
        self.form(c * c, c, 1.0, c * c, jac, out);
    }

    /// The complex Radau iteration matrix for a complex `c`, scaled with `|c|^2`.
    pub fn form_complex(&self, c: Complex64, jac: &JacobianValues, out: &mut [Complex64]) {
        self.form(c * c, c, 1.0, c.norm_sqr(), jac, out);
    }

    /// `(c M + D) x` for a coordinate vector `x` (used by the error estimate).
    pub(crate) fn mass_damping_product(&self, c: f64, jac: &JacobianValues, x: &[f64], out: &mut [f64]) {
        crate::isa::run(
            #[inline(always)]
            || self.mass_damping_product_impl(c, jac, x, out),
        )
    }

    /// [`Self::mass_damping_product`], compiled into each version of [`crate::isa::run`].
    #[inline(always)]
    fn mass_damping_product_impl(&self, c: f64, jac: &JacobianValues, x: &[f64], out: &mut [f64]) {
        // (by row, the sum in a register: the same additions in the same
        // order as entry by entry, without each waiting on the last one's
        // store to its row)
        for (r, o) in out.iter_mut().enumerate() {
            let mut s = c * self.coord_mass[r] * x[r];
            for &(col, p) in &self.d_cols[self.d_row_ptr[r] as usize..self.d_row_ptr[r + 1] as usize] {
                s += jac.d[p as usize] * x[col as usize];
            }
            *o = s;
        }
    }
}

/// Writes `g` and `G v` values and subtracts `G^T lambda` from `F` for one
/// primitive (`vx` is `v` with a zero sink entry).
#[inline]
fn apply_rows(
    f: &mut [f64],
    g: &mut [f64],
    w: &mut [f64],
    vx: &[f64],
    map: &PrimMap,
    rows: &Rows,
    lam: Option<&[f64]>,
) {
    apply_rows_in(f, g, w, vx, map, rows, lam, &ALL_SLOTS);
}

/// All six slots (x, y, phi of body a, then of body b) of a constraint row.
const ALL_SLOTS: [usize; 6] = [0, 1, 2, 3, 4, 5];
/// The slots an angle constraint's row depends on (the two angles).
const ANGLE_SLOTS: [usize; 2] = [2, 5];

/// [`apply_rows`] over the given slots only (the others are zero).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn apply_rows_in(
    f: &mut [f64],
    g: &mut [f64],
    w: &mut [f64],
    vx: &[f64],
    map: &PrimMap,
    rows: &Rows,
    lam: Option<&[f64]>,
    slots: &[usize],
) {
    let e0 = map.eq as usize;
    for r in 0..map.rows as usize {
        g[e0 + r] = rows.g[r];
        let grad = &rows.grad[r];
        let mut gv = 0.0;
        for &s in slots {
            gv += grad[s] * vx[map.f[s] as usize];
        }
        w[e0 + r] = gv;
        let l = lam.map_or(0.0, |lam| lam[e0 + r]);
        if l != 0.0 {
            for &s in slots {
                f[map.f[s] as usize] -= grad[s] * l;
            }
        }
    }
}

#[inline]
fn store_grad(g: &mut [f64], entries: &[GEntry], map: &PrimMap, rows: &Rows) {
    let start = map.g_start as usize;
    for (i, e) in entries[start..start + map.g_count as usize].iter().enumerate() {
        g[start + i] = rows.grad[e.row as usize][e.slot as usize];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
