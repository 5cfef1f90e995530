//! The evaluations the integrator iterates on: the residual
//! `F = Q - G^T lambda`, `g` and `G q' + g_t`, the Jacobian arrays `K`, `D`
//! and `G`, and `gamma`, each one walk over the element and primitive lists
//! through [`ForceKernel`] and [`Primitive`].

use super::constraints::{PrimVisitor, Primitive, Rows};
use super::element::{At, ForceKernel, JacobianOrder, KindVisitor, ResidualOrder};
use super::kin::{BodyKin, Rot, V2};
use super::layout::NONE;
use super::maps::{add_block, GEntry, PrimMap, Scatter};
use super::{Assembly, JacobianValues, Workspace};

impl Assembly {
    /// Loads the kinematics of every body at `(q, v)` into `ws`.
    #[inline(always)]
    pub(crate) fn load_kin(&self, ws: &mut Workspace, q: &[f64], v: &[f64]) {
        // (into a slice: see `constraint_rows`)
        let kin = &mut ws.kin[..];
        for b in 1..self.bodies.len() {
            kin[b] = self.body_kin(b, q, v);
        }
    }

    /// Loads the kinematics of body `b` only.
    #[inline(always)]
    pub(crate) fn load_body(&self, ws: &mut Workspace, b: usize, q: &[f64], v: &[f64]) {
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
        self.prims.visit(&mut ConstraintRows { kin, t, f, g, w, vx, lam });
        for k in &self.linear {
            k.apply(kin, vx, f, g, w, lam);
        }
    }

    /// Generalised applied forces `Q(t, q, q')` added into `ws.f` (kinematics loaded).
    #[inline(always)]
    fn applied_forces(&self, ws: &mut Workspace, t: f64) {
        let Workspace { kin, f, closed, v0, .. } = ws;
        // (slices: see `constraint_rows`)
        let (kin, f, closed, v0) = (&kin[..], &mut f[..], &closed[..], &v0[..]);
        self.elements.visit::<ResidualOrder, _>(&mut AddForces { at: At::new(kin, t, closed, v0), f });
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
    /// [`ForceKernel::derivatives`] of [`super::friction::FrictionK`]).
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
        let Workspace { kin, closed, v0, .. } = ws;
        let (kin, closed, v0) = (&kin[..], &closed[..], &v0[..]);
        let JacobianValues { k, d, g } = jac;
        let at = At { zone, ..At::new(kin, t, closed, v0) };
        self.elements.visit::<JacobianOrder, _>(&mut AddDerivatives { at, k, d });
        self.prims.visit(&mut Gradients { kin, t, lam, entries: &self.g_entries, g, k });
        for k in &self.linear {
            k.store_gradient(g);
        }
    }

    /// The acceleration-free part of `d^2 g/dt^2` (for consistent accelerations),
    /// into [`Workspace::constraints`].
    pub fn constraint_gamma(&self, ws: &mut Workspace, t: f64, q: &[f64], v: &[f64]) {
        self.load_kin(ws, q, v);
        let Workspace { kin, g, .. } = ws;
        self.prims.visit(&mut Gamma { kin: &kin[..], t, g });
        for k in &self.linear {
            g[k.eq as usize] = 0.0;
        }
    }
}

/// Adds each element's forces into `F`.
struct AddForces<'a> {
    at: At<'a>,
    f: &'a mut [f64],
}

impl KindVisitor for AddForces<'_> {
    #[inline(always)]
    fn visit<K: ForceKernel>(&mut self, elements: &[(K, K::Map)]) {
        let (at, f) = (self.at, &mut *self.f);
        for (i, (e, map)) in elements.iter().enumerate() {
            if e.acts(&at, i) {
                map.add_vector(f, &e.force(&at, i));
            }
        }
    }
}

/// Adds each element's stiffness and damping blocks into `K` and `D`.
struct AddDerivatives<'a> {
    at: At<'a>,
    k: &'a mut [f64],
    d: &'a mut [f64],
}

impl KindVisitor for AddDerivatives<'_> {
    #[inline(always)]
    fn visit<K: ForceKernel>(&mut self, elements: &[(K, K::Map)]) {
        let (at, kv, dv) = (&self.at, &mut *self.k, &mut *self.d);
        for (i, (e, map)) in elements.iter().enumerate() {
            if e.acts(at, i) {
                let mut km = <K::Map as Scatter>::Matrix::default();
                let mut dm = <K::Map as Scatter>::Matrix::default();
                e.derivatives(at, i, &mut km, &mut dm);
                map.add_matrix(kv, &km);
                if K::DAMPING {
                    map.add_matrix(dv, &dm);
                }
            }
        }
    }
}

/// Writes `g` and `G q' + g_t` and subtracts `G^T lambda` from `F`.
struct ConstraintRows<'a> {
    kin: &'a [BodyKin],
    t: f64,
    f: &'a mut [f64],
    g: &'a mut [f64],
    w: &'a mut [f64],
    /// `q'` with a zero sink entry.
    vx: &'a [f64],
    lam: Option<&'a [f64]>,
}

impl PrimVisitor for ConstraintRows<'_> {
    #[inline(always)]
    fn visit<P: Primitive>(&mut self, prims: &[(P, PrimMap)]) {
        let (kin, t, vx, lam) = (self.kin, self.t, self.vx, self.lam);
        let (f, g, w) = (&mut *self.f, &mut *self.g, &mut *self.w);
        for (k, map) in prims {
            apply_rows(f, g, w, vx, map, &k.rows(kin, t), lam, P::SLOTS);
            if P::RHEONOMIC {
                w[map.eq as usize] += k.rate(t);
            }
        }
    }
}

/// Stores the gradient values `G` and adds the constraint Hessians into `K`.
struct Gradients<'a> {
    kin: &'a [BodyKin],
    t: f64,
    lam: &'a [f64],
    entries: &'a [GEntry],
    g: &'a mut [f64],
    k: &'a mut [f64],
}

impl PrimVisitor for Gradients<'_> {
    fn visit<P: Primitive>(&mut self, prims: &[(P, PrimMap)]) {
        let (kin, t, lam, entries) = (self.kin, self.t, self.lam, self.entries);
        for (k, map) in prims {
            store_grad(self.g, entries, map, &k.rows(kin, t));
            if P::HESSIAN {
                let mut h = [[0.0; 6]; 6];
                k.hessian(kin, lam, map.eq as usize, &mut h);
                add_block(self.k, &map.h, &h);
            }
        }
    }
}

/// Writes each primitive's `gamma`.
struct Gamma<'a> {
    kin: &'a [BodyKin],
    t: f64,
    g: &'a mut [f64],
}

impl PrimVisitor for Gamma<'_> {
    fn visit<P: Primitive>(&mut self, prims: &[(P, PrimMap)]) {
        for (k, map) in prims {
            let gm = k.gamma(self.kin, self.t);
            for r in 0..map.rows as usize {
                self.g[map.eq as usize + r] = gm[r];
            }
        }
    }
}

/// Writes one primitive's `g` and `G v` values and subtracts `G^T lambda`
/// from `F`, over the given slots only (the others are zero; `vx` is `v`
/// with a zero sink entry).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn apply_rows(
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

/// Stores one primitive's gradient entries.
#[inline]
fn store_grad(g: &mut [f64], entries: &[GEntry], map: &PrimMap, rows: &Rows) {
    let start = map.g_start as usize;
    for (i, e) in entries[start..start + map.g_count as usize].iter().enumerate() {
        g[start + i] = rows.grad[e.row as usize][e.slot as usize];
    }
}
