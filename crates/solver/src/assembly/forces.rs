//! Force laws with their analytic derivatives.
//!
//! Every two-body element works on the generalised coordinates
//! `z = (x_a, y_a, phi_a, x_b, y_b, phi_b)` and returns
//! - the generalised forces `Q(z, z')` (6 values),
//! - the stiffness `K = -dQ/dz` and damping `D = -dQ/dz'` (6x6 each),
//! - its stored energy and dissipated power for the energy balance,
//! - the force it transmits (bushings and friction, for the peak forces),
//!
//! each through its implementation of [`ForceKernel`]. The derivations are
//! in `docs/solver.md`; every kernel's derivatives are checked against
//! central differences of its own force (the tests of
//! [`super::element`]) and, inside a whole system, against the coloured
//! differences of [`crate::fd`] (`tests/jacobian_fd.rs`).

use super::element::{At, ForceKernel, PeakForce, PowerFlow};
use super::kin::{add_btcb, add_btcp, BodyKin, Mat6, Rot, V2};
use super::maps::{CoordMap, PairMap};
use crate::model::force::{BodyState, CustomElement};
use crate::timefn::TimeFunction;

/// Generalised force of a point force `f` at world offset `rho` from the
/// centre of mass: (fx, fy, rho x f).
#[inline]
pub(super) fn point_force(f: V2, rho: V2) -> [f64; 3] {
    [f.x, f.y, rho.cross(f)]
}

#[inline]
pub(super) fn put(q: &mut [f64; 6], at: usize, g: [f64; 3]) {
    q[at] += g[0];
    q[at + 1] += g[1];
    q[at + 2] += g[2];
}

/// Bushing (see [`crate::model::force::Bushing`]); body `a` is the frame body.
#[derive(Debug, Clone)]
pub(crate) struct BushingK {
    pub a: u32,
    pub b: u32,
    pub pa: V2,
    pub pb: V2,
    pub k: [f64; 2],
    pub c: [f64; 2],
    pub rest: V2,
}

/// Intermediate quantities of a bushing evaluation.
struct BushingEval {
    rot_a: Rot,
    rho_a: V2,
    rho_b: V2,
    rho_b_l: V2,
    e_l: V2,
    d_l: V2,
    f_l: V2,
    dd_l: V2,
    c_l: V2,
}

impl BushingK {
    #[inline(always)]
    fn eval(&self, ka: &BodyKin, kb: &BodyKin) -> BushingEval {
        if self.pb == V2::default() {
            self.eval_at::<true>(ka, kb)
        } else {
            self.eval_at::<false>(ka, kb)
        }
    }

    /// The evaluation; with `CENTRED` (`pb` is zero, as a bearing's) the
    /// terms of `b`'s offset are left out rather than computed as zeros.
    #[inline(always)]
    fn eval_at<const CENTRED: bool>(&self, ka: &BodyKin, kb: &BodyKin) -> BushingEval {
        let rot_a = ka.rot;
        let rho_a = rot_a.apply(self.pa);
        let rho_b = if CENTRED { V2::default() } else { kb.rot.apply(self.pb) };
        let delta = if CENTRED { kb.r - (ka.r + rho_a) } else { (kb.r + rho_b) - (ka.r + rho_a) };
        let e_l = rot_a.apply_t(delta);
        let d_l = e_l - self.rest;
        let f_l = V2::new(self.k[0] * d_l.x, self.k[1] * d_l.y);
        let vb = if CENTRED { kb.v } else { kb.v + kb.w * rho_b.perp() };
        let w = vb - (ka.v + ka.w * rho_a.perp());
        let dd_l = rot_a.apply_t(w);
        let c_l = V2::new(self.c[0] * dd_l.x, self.c[1] * dd_l.y);
        let rho_b_l = if CENTRED { V2::default() } else { rot_a.apply_t(rho_b) };
        BushingEval { rot_a, rho_a, rho_b, rho_b_l, e_l, d_l, f_l, dd_l, c_l }
    }

    #[inline(always)]
    fn force_at<const CENTRED: bool>(&self, ka: &BodyKin, kb: &BodyKin) -> [f64; 6] {
        let e = self.eval_at::<CENTRED>(ka, kb);
        // total force on b, world frame
        let f = -e.rot_a.apply(e.f_l + e.c_l);
        let mut q = [0.0; 6];
        put(&mut q, 3, if CENTRED { [f.x, f.y, 0.0] } else { point_force(f, e.rho_b) });
        put(&mut q, 0, point_force(-f, e.rho_a));
        // frame torque of the elastic part: e_l x f_l
        q[2] += e.e_l.cross(e.f_l);
        q
    }
}

impl ForceKernel for BushingK {
    type Map = PairMap;
    const DAMPING: bool = true;
    const STORES_ENERGY: bool = true;
    const POWER: Option<PowerFlow> = Some(PowerFlow::Damping);
    const PEAK: Option<PeakForce> = Some(PeakForce::Bushing);

    #[inline(always)]
    fn force(&self, at: &At, _i: usize) -> [f64; 6] {
        let (ka, kb) = at.pair(self.a, self.b);
        if self.pb == V2::default() {
            self.force_at::<true>(ka, kb)
        } else {
            self.force_at::<false>(ka, kb)
        }
    }

    fn derivatives(&self, at: &At, _i: usize, km: &mut Mat6, dm: &mut Mat6) {
        let (ka, kb) = at.pair(self.a, self.b);
        let e = self.eval(ka, kb);
        let ra = e.rot_a;
        let pa = self.pa;
        // Columns of J_d (= d d_l / dz) and J_v (= d d'_l / dz'), in a's frame.
        let ex = ra.apply_t(V2::new(1.0, 0.0));
        let ey = ra.apply_t(V2::new(0.0, 1.0));
        let jd = [-ex, -ey, -(e.e_l + pa).perp(), ex, ey, e.rho_b_l.perp()];
        let jv = [-ex, -ey, -pa.perp(), ex, ey, e.rho_b_l.perp()];
        let kd = [[self.k[0], 0.0], [0.0, self.k[1]]];
        let cd = [[self.c[0], 0.0], [0.0, self.c[1]]];
        // elastic: J_d^T K J_d + geometric terms
        add_btcb(km, &jd, kd);
        let f = e.f_l;
        let g = ra.apply(f.perp());
        km[2][2] += -f.dot(e.e_l + pa);
        for (i, gi) in [(0usize, -g.x), (1, -g.y), (3, g.x), (4, g.y)] {
            km[2][i] += gi;
            km[i][2] += gi;
        }
        km[2][5] += f.dot(e.rho_b_l);
        km[5][2] += f.dot(e.rho_b_l);
        km[5][5] += -f.dot(e.rho_b_l);
        // damping: D = J_v^T C J_v
        add_btcb(dm, &jv, cd);
        // position derivative of the damping force: E + J_v^T C P
        let c = e.c_l;
        let h = ra.apply(c.perp());
        km[0][2] += -h.x;
        km[1][2] += -h.y;
        km[3][2] += h.x;
        km[4][2] += h.y;
        km[5][2] += e.rho_b_l.dot(c);
        km[5][5] += -e.rho_b_l.dot(c);
        let zero = V2::default();
        let p = [zero, zero, -e.dd_l.perp() + ka.w * pa, zero, zero, -(kb.w * e.rho_b_l)];
        add_btcp(km, &jv, cd, &p);
        let _ = (e.rho_a, e.rho_b);
    }

    /// `1/2 d_l^T diag(kx, ky) d_l` [J].
    #[inline]
    fn potential(&self, at: &At, _i: usize) -> f64 {
        let (ka, kb) = at.pair(self.a, self.b);
        let e = self.eval(ka, kb);
        0.5 * (self.k[0] * e.d_l.x * e.d_l.x + self.k[1] * e.d_l.y * e.d_l.y)
    }

    /// Dissipated by the dampers [W] (never negative).
    #[inline(always)]
    fn add_power(&self, at: &At, _i: usize, _map: &PairMap, acc: &mut f64) {
        let (ka, kb) = at.pair(self.a, self.b);
        let e = self.eval(ka, kb);
        *acc += e.c_l.dot(e.dd_l);
    }

    /// Square of the bushing force's magnitude, elastic and damping [N^2].
    #[inline(always)]
    fn reaction_squared(&self, at: &At, _i: usize) -> f64 {
        let (ka, kb) = at.pair(self.a, self.b);
        let e = self.eval(ka, kb);
        (e.f_l + e.c_l).norm_squared()
    }
}

/// Point-to-point spring and damper.
#[derive(Debug, Clone)]
pub(crate) struct SpringK {
    pub a: u32,
    pub b: u32,
    pub pa: V2,
    pub pb: V2,
    pub k: f64,
    pub c: f64,
    pub l0: f64,
}

struct SpringEval {
    rho_a: V2,
    rho_b: V2,
    n: V2,
    l: f64,
    w: V2,
    ldot: f64,
    f: f64,
}

impl SpringK {
    fn eval(&self, ka: &BodyKin, kb: &BodyKin) -> SpringEval {
        let rho_a = ka.rot.apply(self.pa);
        let rho_b = kb.rot.apply(self.pb);
        let delta = (kb.r + rho_b) - (ka.r + rho_a);
        let l = delta.norm();
        // A zero-length spring has no direction; take x so that the law stays finite.
        let n = if l > 1e-300 { delta.scale(1.0 / l) } else { V2::new(1.0, 0.0) };
        let w = (kb.v + kb.w * rho_b.perp()) - (ka.v + ka.w * rho_a.perp());
        let ldot = n.dot(w);
        SpringEval { rho_a, rho_b, n, l, w, ldot, f: self.k * (l - self.l0) + self.c * ldot }
    }
}

impl ForceKernel for SpringK {
    type Map = PairMap;
    const DAMPING: bool = true;
    const STORES_ENERGY: bool = true;
    const POWER: Option<PowerFlow> = Some(PowerFlow::Damping);
    const PEAK: Option<PeakForce> = None;

    fn force(&self, at: &At, _i: usize) -> [f64; 6] {
        let (ka, kb) = at.pair(self.a, self.b);
        let e = self.eval(ka, kb);
        let fb = -(e.f * e.n);
        let mut q = [0.0; 6];
        put(&mut q, 3, point_force(fb, e.rho_b));
        put(&mut q, 0, point_force(-fb, e.rho_a));
        q
    }

    fn derivatives(&self, at: &At, _i: usize, km: &mut Mat6, dm: &mut Mat6) {
        let (ka, kb) = at.pair(self.a, self.b);
        let e = self.eval(ka, kb);
        let ex = V2::new(1.0, 0.0);
        let ey = V2::new(0.0, 1.0);
        let b = [-ex, -ey, -e.rho_a.perp(), ex, ey, e.rho_b.perp()];
        let n = e.n;
        let nn = [[n.x * n.x, n.x * n.y], [n.y * n.x, n.y * n.y]];
        let cnn = [[self.c * nn[0][0], self.c * nn[0][1]], [self.c * nn[1][0], self.c * nn[1][1]]];
        add_btcb(dm, &b, cnn);
        // -dF_b/dDelta = n (k n^T + c w^T N / l) + f N / l
        let inv_l = if e.l > 1e-300 { 1.0 / e.l } else { 0.0 };
        let big_n = [[1.0 - nn[0][0], -nn[0][1]], [-nn[1][0], 1.0 - nn[1][1]]];
        let wn = V2::new(e.w.x * big_n[0][0] + e.w.y * big_n[1][0], e.w.x * big_n[0][1] + e.w.y * big_n[1][1]);
        let mut s = [[0.0; 2]; 2];
        let row = [self.k * n.x + self.c * wn.x * inv_l, self.k * n.y + self.c * wn.y * inv_l];
        let nv = [n.x, n.y];
        for i in 0..2 {
            for j in 0..2 {
                s[i][j] = nv[i] * row[j] + e.f * big_n[i][j] * inv_l;
            }
        }
        // K = -(dB^T/dz) F_b - B^T dF_b/dz = -(dB^T/dz) F_b + B^T S B + B^T (c n n^T) P_w
        add_btcp(km, &b, s, &b);
        let zero = V2::default();
        let pw = [zero, zero, ka.w * e.rho_a, zero, zero, -(kb.w * e.rho_b)];
        add_btcp(km, &b, cnn, &pw);
        let fb = -(e.f * n);
        km[2][2] -= e.rho_a.dot(fb);
        km[5][5] -= -e.rho_b.dot(fb);
    }

    /// `1/2 k (l - l0)^2` [J].
    fn potential(&self, at: &At, _i: usize) -> f64 {
        let (ka, kb) = at.pair(self.a, self.b);
        let e = self.eval(ka, kb);
        0.5 * self.k * (e.l - self.l0) * (e.l - self.l0)
    }

    /// Dissipated by the damper, `c l'^2` [W].
    fn add_power(&self, at: &At, _i: usize, _map: &PairMap, acc: &mut f64) {
        let (ka, kb) = at.pair(self.a, self.b);
        let e = self.eval(ka, kb);
        *acc += self.c * e.ldot * e.ldot;
    }
}

/// Spring and damper on one coordinate to the ground.
#[derive(Debug, Clone)]
pub(crate) struct CoordSpringK {
    pub body: u32,
    pub slot: u8,
    pub k: f64,
    pub c: f64,
    pub rest: f64,
}

impl CoordSpringK {
    fn q_v(&self, kin: &BodyKin) -> (f64, f64) {
        match self.slot {
            0 => (kin.r.x, kin.v.x),
            1 => (kin.r.y, kin.v.y),
            _ => (kin.phi, kin.w),
        }
    }
}

impl ForceKernel for CoordSpringK {
    type Map = CoordMap;
    const DAMPING: bool = true;
    const STORES_ENERGY: bool = true;
    const POWER: Option<PowerFlow> = Some(PowerFlow::Damping);
    const PEAK: Option<PeakForce> = None;

    fn force(&self, at: &At, _i: usize) -> f64 {
        let (q, v) = self.q_v(&at.kin[self.body as usize]);
        -self.k * (q - self.rest) - self.c * v
    }

    fn derivatives(&self, _at: &At, _i: usize, km: &mut f64, dm: &mut f64) {
        *km += self.k;
        *dm += self.c;
    }

    /// `1/2 k (q - rest)^2` [J].
    fn potential(&self, at: &At, _i: usize) -> f64 {
        let (q, _) = self.q_v(&at.kin[self.body as usize]);
        0.5 * self.k * (q - self.rest) * (q - self.rest)
    }

    /// Dissipated by the damper, `c q'^2` [W].
    fn add_power(&self, at: &At, _i: usize, _map: &CoordMap, acc: &mut f64) {
        let (_, v) = self.q_v(&at.kin[self.body as usize]);
        *acc += self.c * v * v;
    }
}

/// Applied force and torque, functions of time; `b` is unused (ground).
#[derive(Debug, Clone)]
pub(crate) struct LoadK {
    pub a: u32,
    pub pa: V2,
    pub fx: TimeFunction,
    pub fy: TimeFunction,
    pub torque: TimeFunction,
}

impl LoadK {
    fn at(&self, t: f64) -> (V2, f64) {
        (V2::new(self.fx.value(t), self.fy.value(t)), self.torque.value(t))
    }

    pub fn next_breakpoint(&self, t: f64) -> Option<f64> {
        [&self.fx, &self.fy, &self.torque].iter().filter_map(|f| f.next_breakpoint(t)).reduce(f64::min)
    }
}

impl ForceKernel for LoadK {
    type Map = PairMap;
    const DAMPING: bool = false;
    const STORES_ENERGY: bool = false;
    const POWER: Option<PowerFlow> = Some(PowerFlow::Applied);
    const PEAK: Option<PeakForce> = None;

    fn force(&self, at: &At, _i: usize) -> [f64; 6] {
        let ka = &at.kin[self.a as usize];
        let (f, tau) = self.at(at.t);
        let rho = ka.rot.apply(self.pa);
        let mut q = [0.0; 6];
        put(&mut q, 0, point_force(f, rho));
        q[2] += tau;
        q
    }

    /// The moment of the force turning with the body (no damping).
    fn derivatives(&self, at: &At, _i: usize, km: &mut Mat6, _dm: &mut Mat6) {
        let ka = &at.kin[self.a as usize];
        let (f, _) = self.at(at.t);
        let rho = ka.rot.apply(self.pa);
        km[2][2] += rho.dot(f);
    }

    /// Delivered power `f . v_p + tau w` [W].
    fn add_power(&self, at: &At, _i: usize, _map: &PairMap, acc: &mut f64) {
        let ka = &at.kin[self.a as usize];
        let (f, tau) = self.at(at.t);
        let rho = ka.rot.apply(self.pa);
        *acc += f.dot(ka.v + ka.w * rho.perp()) + tau * ka.w;
    }
}

/// A user force law differentiated by central finite differences.
#[derive(Debug, Clone)]
pub(crate) struct CustomK {
    pub a: u32,
    pub b: u32,
    pub law: CustomElement,
}

fn body_state(k: &BodyKin) -> BodyState {
    BodyState { pose: [k.r.x, k.r.y, k.phi], velocity: [k.v.x, k.v.y, k.w] }
}

impl CustomK {
    fn eval_states(&self, t: f64, sa: &BodyState, sb: &BodyState) -> [f64; 6] {
        let (fa, fb) = self.law.0.force(t, sa, sb);
        [fa[0], fa[1], fa[2], fb[0], fb[1], fb[2]]
    }
}

impl ForceKernel for CustomK {
    type Map = PairMap;
    const DAMPING: bool = true;
    const STORES_ENERGY: bool = false;
    const POWER: Option<PowerFlow> = Some(PowerFlow::Applied);
    const PEAK: Option<PeakForce> = None;

    fn force(&self, at: &At, _i: usize) -> [f64; 6] {
        let (ka, kb) = at.pair(self.a, self.b);
        self.eval_states(at.t, &body_state(ka), &body_state(kb))
    }

    /// Central differences over the 12 inputs of the element.
    fn derivatives(&self, at: &At, _i: usize, km: &mut Mat6, dm: &mut Mat6) {
        let (ka, kb) = at.pair(self.a, self.b);
        let t = at.t;
        let base = [body_state(ka), body_state(kb)];
        for j in 0..6 {
            for (velocity, out) in [(false, &mut *km), (true, &mut *dm)] {
                let mut plus = base;
                let mut minus = base;
                let (bi, slot) = (j / 3, j % 3);
                let x = if velocity { base[bi].velocity[slot] } else { base[bi].pose[slot] };
                let h = 1e-6 * x.abs().max(1e-3);
                if velocity {
                    plus[bi].velocity[slot] += h;
                    minus[bi].velocity[slot] -= h;
                } else {
                    plus[bi].pose[slot] += h;
                    minus[bi].pose[slot] -= h;
                }
                let fp = self.eval_states(t, &plus[0], &plus[1]);
                let fm = self.eval_states(t, &minus[0], &minus[1]);
                for i in 0..6 {
                    out[i][j] -= (fp[i] - fm[i]) / (2.0 * h);
                }
            }
        }
    }

    /// Delivered power `Q . z'` over the free slots [W].
    fn add_power(&self, at: &At, i: usize, map: &PairMap, acc: &mut f64) {
        let qf = self.force(at, i);
        for s in 0..6 {
            let c = map.f[s] as usize;
            if c < at.v.len() {
                *acc += qf[s] * at.v[c];
            }
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A body's kinematics from a pose and velocity.
    pub(crate) fn kin_at(x: f64, y: f64, phi: f64, vx: f64, vy: f64, w: f64) -> BodyKin {
        BodyKin { r: V2::new(x, y), phi, rot: Rot::new(phi), v: V2::new(vx, vy), w }
    }

    /// The bearing states of the centred-form tests (translating only or
    /// turning, sliding and sticking).
    pub(crate) const BEARING_STATES: [(f64, f64, f64); 5] =
        [(0.35, -0.2, 0.0), (2e-4, -1e-4, 0.0), (0.0, 0.0, 0.0), (0.35, -0.2, -0.9), (2e-4, 0.0, 0.3)];

    /// The centred form (an offset of zero left out rather than computed)
    /// gives what the general form gives, bit for bit (the general forms are
    /// checked against finite differences in `tests/jacobian_fd.rs` and
    /// [`crate::assembly::element`]): a bushing to a bearing's centre, the
    /// bearing translating only or turning (the spec's prismatic form, whose
    /// bearing has an angle coordinate).
    #[test]
    fn centred_bushing_gives_the_general_results() {
        let frame = kin_at(0.3, -0.2, 0.21, 0.4, -0.1, 0.7);
        for (vx, vy, w) in BEARING_STATES {
            let bearing = kin_at(0.1, 0.6, 0.26, vx, vy, w);
            let bushing = BushingK {
                a: 1,
                b: 2,
                pa: V2::new(0.2, -0.4),
                pb: V2::default(),
                k: [2e3, 5e2],
                c: [3.0, 7.0],
                rest: V2::new(0.01, -0.02),
            };
            assert_eq!(bushing.force_at::<true>(&frame, &bearing), bushing.force_at::<false>(&frame, &bearing));
            let (c, g) = (bushing.eval_at::<true>(&frame, &bearing), bushing.eval_at::<false>(&frame, &bearing));
            assert_eq!(
                (c.e_l, c.f_l, c.dd_l, c.c_l, c.rho_b, c.rho_b_l),
                (g.e_l, g.f_l, g.dd_l, g.c_l, g.rho_b, g.rho_b_l)
            );
        }
    }
}
