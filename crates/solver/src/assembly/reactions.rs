//! What the constraints and elements transmit at a state: the reactions of
//! constraints on a body, the largest element forces, and the contacts'
//! states.

use super::constraints::{PrimRef, PrimVisitor, Primitive};
use super::element::{At, EnergyOrder, ForceKernel, KindVisitor, PeakForce};
use super::layout::NONE;
use super::linear::LinearK;
use super::maps::PrimMap;
use super::{Assembly, ContactValue, ForceExtremes, Workspace};
use crate::model::body::BodyId;
use crate::model::constraint::ConstraintId;

impl Assembly {
    /// Reaction of a constraint on one body, `-G^T lambda` restricted to the
    /// body: (fx \[N\], fy \[N\], torque about the centre of mass [N m]). Locked
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
        let mut reaction =
            Reaction { asm: self, ws, t, q, lam, coords: self.bodies[body.index()].coord, out: [0.0; 3] };
        for id in constraints {
            let Some(prims) = self.constraint_prims.get(id.index()) else {
                continue;
            };
            for &prim in prims {
                match prim {
                    PrimRef::Linear(i) => reaction.linear(&self.linear[i as usize]),
                    _ => self.prims.visit_one(prim, &mut reaction),
                }
            }
        }
        reaction.out
    }

    /// Largest bushing and friction force magnitudes at a state.
    pub fn force_extremes(&self, ws: &mut Workspace, q: &[f64], v: &[f64]) -> ForceExtremes {
        crate::isa::run(
            #[inline(always)]
            || self.force_extremes_impl(ws, q, v),
        )
    }

    /// [`Self::force_extremes`] per group of bodies
    /// ([`crate::System::set_group`]): each group's largest bushing and
    /// friction force at `(q, v)`, raised into `out` (one entry per group).
    pub fn force_extremes_by_group(&self, ws: &mut Workspace, q: &[f64], v: &[f64], out: &mut [ForceExtremes]) {
        self.load_kin(ws, q, v);
        let at = At::new(&ws.kin, 0.0, &ws.closed, &ws.v0);
        for (i, (k, _)) in self.elements.bushings.iter().enumerate() {
            if let Some(x) = out.get_mut(self.group_of(k.a, k.b)) {
                if k.acts(&at, i) {
                    x.bushing = x.bushing.max(k.reaction_squared(&at, i).sqrt());
                }
            }
        }
        for (i, (k, _)) in self.elements.frictions.iter().enumerate() {
            if let Some(x) = out.get_mut(self.group_of(k.a, k.b)) {
                if k.acts(&at, i) {
                    x.friction = x.friction.max(k.reaction_squared(&at, i).sqrt());
                }
            }
        }
    }

    /// [`Self::force_extremes`], compiled into each version of [`crate::isa::run`].
    #[inline(always)]
    fn force_extremes_impl(&self, ws: &mut Workspace, q: &[f64], v: &[f64]) -> ForceExtremes {
        self.load_kin(ws, q, v);
        // (the largest square, then one root: the same number as the
        // largest root, since the root is monotonic and correctly rounded)
        let mut peaks = PeakSquares { at: At::new(&ws.kin, 0.0, &ws.closed, &ws.v0), bushing: 0.0, friction: 0.0 };
        self.elements.visit::<EnergyOrder, _>(&mut peaks);
        ForceExtremes { bushing: peaks.bushing.sqrt(), friction: peaks.friction.sqrt() }
    }

    /// The state of every contact at `(q, v)` into `out` (one per contact,
    /// in the order the system added them), with the modes of `ws`.
    pub fn contacts(&self, ws: &mut Workspace, q: &[f64], v: &[f64], out: &mut [ContactValue]) {
        // the integrator asks at every step: load only the bodies involved
        for &b in &self.contact_bodies {
            self.load_body(ws, b, q, v);
        }
        for (i, ((k, _), o)) in self.elements.contacts.iter().zip(out.iter_mut()).enumerate() {
            let g = k.gap(&ws.kin[k.a as usize], &ws.kin[k.b as usize]);
            let force = if ws.closed[i] || g.delta > 0.0 { k.law.eval(g.delta, g.rate, ws.v0[i]).0 } else { 0.0 };
            *o = ContactValue { closed: ws.closed[i], penetration: g.delta, rate: g.rate, force };
        }
    }

    /// Stored elastic energy of contact `i` at penetration `d` [m], in J.
    pub(crate) fn contact_energy(&self, i: usize, d: f64) -> f64 {
        self.elements.contacts[i].0.law.energy(d)
    }

    /// The coordinates (up to 6, `n` for locked ones) contact `i` depends on.
    pub(crate) fn contact_coords(&self, i: usize) -> [u32; 6] {
        self.elements.contacts[i].1.f
    }
}

/// Sums `-G^T lambda` of the primitives it visits over one body's
/// coordinates.
struct Reaction<'a> {
    asm: &'a Assembly,
    ws: &'a mut Workspace,
    t: f64,
    q: &'a [f64],
    lam: &'a [f64],
    /// The body's coordinates.
    coords: [u32; 3],
    /// (fx [N], fy [N], torque [N m]).
    out: [f64; 3],
}

impl PrimVisitor for Reaction<'_> {
    fn visit<P: Primitive>(&mut self, prims: &[(P, PrimMap)]) {
        for (k, map) in prims {
            let (a, b) = k.bodies();
            // velocities do not enter the reaction; q stands in for them
            self.asm.load_body(self.ws, a as usize, self.q, self.q);
            if b != 0 {
                self.asm.load_body(self.ws, b as usize, self.q, self.q);
            }
            let rows = k.rows(&self.ws.kin, self.t);
            for r in 0..map.rows as usize {
                let l = self.lam[map.eq as usize + r];
                for slot in 0..6 {
                    let fi = map.f[slot];
                    if let Some(s) = self.coords.iter().position(|&c| c == fi && c != NONE) {
                        self.out[s] -= rows.grad[r][slot] * l;
                    }
                }
            }
        }
    }
}

impl Reaction<'_> {
    /// Adds `-c_k lambda` of the terms of a linear equation on the body's
    /// coordinates.
    fn linear(&mut self, k: &LinearK) {
        let l = self.lam[k.eq as usize];
        for &(_, _, c, coef) in &k.terms {
            if let Some(s) = self.coords.iter().position(|&x| x == c) {
                self.out[s] -= coef * l;
            }
        }
    }
}

/// The largest squared reaction of each kind of [`PeakForce`].
struct PeakSquares<'a> {
    at: At<'a>,
    /// [N^2]
    bushing: f64,
    /// [N^2]
    friction: f64,
}

impl KindVisitor for PeakSquares<'_> {
    #[inline(always)]
    fn visit<K: ForceKernel>(&mut self, elements: &[(K, K::Map)]) {
        let Some(peak) = K::PEAK else { return };
        let largest = match peak {
            PeakForce::Bushing => &mut self.bushing,
            PeakForce::Friction => &mut self.friction,
        };
        let (at, mut x) = (self.at, *largest);
        for (i, (k, _)) in elements.iter().enumerate() {
            if k.acts(&at, i) {
                x = x.max(k.reaction_squared(&at, i));
            }
        }
        *largest = x;
    }
}
