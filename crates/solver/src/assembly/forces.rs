//! Force laws with their analytic derivatives.
//!
//! Every two-body element works on the generalised coordinates
//! `z = (x_a, y_a, phi_a, x_b, y_b, phi_b)` and returns
//! - the generalised forces `Q(z, z')` (6 values),
//! - the stiffness `K = -dQ/dz` and damping `D = -dQ/dz'` (6x6 each),
//! - its stored energy and dissipated power for the energy balance.
//!
//! The derivations are in `docs/solver.md`; every kernel is checked against
//! central finite differences in the tests of [`crate::fd`].

use super::kin::{add_btcb, add_btcp, BodyKin, Mat6, Rot, V2};
use crate::model::force::{BodyState, CustomElement, FrictionLaw};
use crate::timefn::TimeFunction;

/// Generalised force of a point force `f` at world offset `rho` from the
/// centre of mass: (fx, fy, rho x f).
#[inline]
fn point_force(f: V2, rho: V2) -> [f64; 3] {
    [f.x, f.y, rho.cross(f)]
}

#[inline]
fn put(q: &mut [f64; 6], at: usize, g: [f64; 3]) {
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
    pub fn force(&self, ka: &BodyKin, kb: &BodyKin) -> [f64; 6] {
        if self.pb == V2::default() {
            self.force_at::<true>(ka, kb)
        } else {
            self.force_at::<false>(ka, kb)
        }
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

    pub fn jacobian(&self, ka: &BodyKin, kb: &BodyKin, km: &mut Mat6, dm: &mut Mat6) {
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

    pub fn potential(&self, ka: &BodyKin, kb: &BodyKin) -> f64 {
        let e = self.eval(ka, kb);
        0.5 * (self.k[0] * e.d_l.x * e.d_l.x + self.k[1] * e.d_l.y * e.d_l.y)
    }

    #[inline(always)]
    pub fn dissipation(&self, ka: &BodyKin, kb: &BodyKin) -> f64 {
        let e = self.eval(ka, kb);
        e.c_l.dot(e.dd_l)
    }

    /// Square of the bushing force's magnitude [N^2] (the largest of
    /// several magnitudes is the root of the largest square, bit for bit).
    #[inline(always)]
    pub fn force_magnitude_squared(&self, ka: &BodyKin, kb: &BodyKin) -> f64 {
        let e = self.eval(ka, kb);
        (e.f_l + e.c_l).norm_squared()
    }
}

/// Regularised Coulomb friction; body `a` is the slider, `b` the base.
#[derive(Debug, Clone)]
pub(crate) struct FrictionK {
    pub a: u32,
    pub b: u32,
    pub pa: V2,
    /// mu * surfaces * normal force [N].
    pub force: f64,
    pub v_eps: f64,
    pub law: FrictionLaw,
}

struct FrictionEval {
    rho: V2,
    e: V2,
    f: V2,
}

impl FrictionK {
    /// phi(v) of the regularised law (the force is `-force phi`).
    #[inline(always)]
    pub(crate) fn phi(&self, v: V2) -> V2 {
        let speed = v.norm();
        match self.law {
            FrictionLaw::Linear => v.scale(1.0 / speed.max(self.v_eps)),
            FrictionLaw::Smooth => v.scale(1.0 / (speed * speed + self.v_eps * self.v_eps).sqrt()),
        }
    }

    /// For a relative velocity with components `a` along a unit direction
    /// and `b` across it: the component of `phi` along the direction and
    /// its derivative with respect to `a`.
    #[inline]
    pub(crate) fn law_along(&self, a: f64, b: f64) -> (f64, f64) {
        let speed2 = a * a + b * b;
        match self.law {
            FrictionLaw::Linear => {
                let speed = speed2.sqrt();
                if speed < self.v_eps {
                    (a / self.v_eps, 1.0 / self.v_eps)
                } else {
                    let s = 1.0 / speed;
                    (a * s, b * b * s * s * s)
                }
            }
            FrictionLaw::Smooth => {
                let e2 = self.v_eps * self.v_eps;
                let s = 1.0 / (speed2 + e2).sqrt();
                (a * s, (b * b + e2) * s * s * s)
            }
        }
    }

    /// phi(v) and d phi / dv for the regularised law.
    pub(crate) fn law(&self, v: V2) -> (V2, [[f64; 2]; 2]) {
        let speed = v.norm();
        match self.law {
            FrictionLaw::Linear if speed < self.v_eps => {
                let s = 1.0 / self.v_eps;
                (v.scale(s), [[s, 0.0], [0.0, s]])
            }
            FrictionLaw::Linear => {
                let s = 1.0 / speed;
                let (ux, uy) = (v.x * s, v.y * s);
                (V2::new(ux, uy), [[s * (1.0 - ux * ux), -s * ux * uy], [-s * ux * uy, s * (1.0 - uy * uy)]])
            }
            FrictionLaw::Smooth => {
                let r = (speed * speed + self.v_eps * self.v_eps).sqrt();
                let s = 1.0 / r;
                let s3 = s * s * s;
                (v.scale(s), [[s - v.x * v.x * s3, -v.x * v.y * s3], [-v.x * v.y * s3, s - v.y * v.y * s3]])
            }
        }
    }

    /// Contact point, relative velocity and force, without the law's slope.
    #[inline(always)]
    fn kinematics(&self, ka: &BodyKin, kb: &BodyKin) -> (V2, V2, V2) {
        if self.pa == V2::default() {
            self.kinematics_at::<true>(ka, kb)
        } else {
            self.kinematics_at::<false>(ka, kb)
        }
    }

    /// [`Self::kinematics`]; with `CENTRED` (`pa` is zero, as a bearing's)
    /// the terms of the offset are left out rather than computed as zeros.
    #[inline(always)]
    fn kinematics_at<const CENTRED: bool>(&self, ka: &BodyKin, kb: &BodyKin) -> (V2, V2, V2) {
        let rho = if CENTRED { V2::default() } else { ka.rot.apply(self.pa) };
        let e = if CENTRED { ka.r - kb.r } else { ka.r + rho - kb.r };
        let va = if CENTRED { ka.v } else { ka.v + ka.w * rho.perp() };
        let v = va - (kb.v + kb.w * e.perp());
        (rho, e, v)
    }

    fn eval(&self, ka: &BodyKin, kb: &BodyKin) -> (FrictionEval, [[f64; 2]; 2]) {
        let (rho, e, v) = self.kinematics(ka, kb);
        let (phi, dphi) = self.law(v);
        (FrictionEval { rho, e, f: -(self.force * phi) }, dphi)
    }

    #[inline(always)]
    pub fn force(&self, ka: &BodyKin, kb: &BodyKin) -> [f64; 6] {
        if self.pa == V2::default() {
            self.force_at::<true>(ka, kb)
        } else {
            self.force_at::<false>(ka, kb)
        }
    }

    #[inline(always)]
    fn force_at<const CENTRED: bool>(&self, ka: &BodyKin, kb: &BodyKin) -> [f64; 6] {
        let (rho, e, v) = self.kinematics_at::<CENTRED>(ka, kb);
        let e = FrictionEval { rho, e, f: -(self.force * self.phi(v)) };
        let mut q = [0.0; 6];
        put(&mut q, 0, if CENTRED { [e.f.x, e.f.y, 0.0] } else { point_force(e.f, e.rho) });
        put(&mut q, 3, point_force(-e.f, e.e));
        q
    }

    /// Relative sliding velocity (slider contact point minus base).
    pub(crate) fn rel_velocity(&self, ka: &BodyKin, kb: &BodyKin) -> V2 {
        self.kinematics(ka, kb).2
    }

    /// Derivatives of the friction force. With `zone_slope`, `d phi / dv` is
    /// replaced by the slope of the law inside its regularisation zone,
    /// `I / v_eps`, whatever the state (the iteration matrix of the
    /// integrator; see [`crate::integrator::radau5`]).
    pub fn jacobian(&self, ka: &BodyKin, kb: &BodyKin, km: &mut Mat6, dm: &mut Mat6, zone_slope: bool) {
        let (e, dphi) = self.eval(ka, kb);
        let dphi = if zone_slope { [[1.0 / self.v_eps, 0.0], [0.0, 1.0 / self.v_eps]] } else { dphi };
        let cf =
            [[self.force * dphi[0][0], self.force * dphi[0][1]], [self.force * dphi[1][0], self.force * dphi[1][1]]];
        let ex = V2::new(1.0, 0.0);
        let ey = V2::new(0.0, 1.0);
        let b = [ex, ey, e.rho.perp(), -ex, -ey, -e.e.perp()];
        add_btcb(dm, &b, cf);
        // -(dB^T/dz) F
        let f = e.f;
        let fp = f.perp();
        km[2][2] -= -e.rho.dot(f);
        km[5][0] -= fp.x;
        km[5][1] -= fp.y;
        km[5][2] -= e.rho.dot(f);
        km[5][3] -= -fp.x;
        km[5][4] -= -fp.y;
        // + B^T Cf P with P = d v_rel / dz
        let ws = kb.w;
        let p =
            [-(ws * ex.perp()), -(ws * ey.perp()), (ws - ka.w) * e.rho, ws * ex.perp(), ws * ey.perp(), V2::default()];
        add_btcp(km, &b, cf, &p);
    }

    /// Dissipated power `-F . v_rel` [W] (never negative).
    /// (`phi` alone: the law's slope is not needed, and `phi` equals the
    /// first value of [`Self::law`] bit for bit.)
    #[inline(always)]
    pub fn dissipation(&self, ka: &BodyKin, kb: &BodyKin) -> f64 {
        let (_, _, v) = self.kinematics(ka, kb);
        let f = -(self.force * self.phi(v));
        -f.dot(v)
    }

    /// Square of the friction force's magnitude [N^2].
    #[inline(always)]
    pub fn force_magnitude_squared(&self, ka: &BodyKin, kb: &BodyKin) -> f64 {
        let (_, _, v) = self.kinematics(ka, kb);
        (-(self.force * self.phi(v))).norm_squared()
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

    pub fn force(&self, ka: &BodyKin, kb: &BodyKin) -> [f64; 6] {
        let e = self.eval(ka, kb);
        let fb = -(e.f * e.n);
        let mut q = [0.0; 6];
        put(&mut q, 3, point_force(fb, e.rho_b));
        put(&mut q, 0, point_force(-fb, e.rho_a));
        q
    }

    pub fn jacobian(&self, ka: &BodyKin, kb: &BodyKin, km: &mut Mat6, dm: &mut Mat6) {
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

    pub fn potential(&self, ka: &BodyKin, kb: &BodyKin) -> f64 {
        let e = self.eval(ka, kb);
        0.5 * self.k * (e.l - self.l0) * (e.l - self.l0)
    }

    pub fn dissipation(&self, ka: &BodyKin, kb: &BodyKin) -> f64 {
        let e = self.eval(ka, kb);
        self.c * e.ldot * e.ldot
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

    pub fn force(&self, kin: &BodyKin) -> f64 {
        let (q, v) = self.q_v(kin);
        -self.k * (q - self.rest) - self.c * v
    }

    pub fn potential(&self, kin: &BodyKin) -> f64 {
        let (q, _) = self.q_v(kin);
        0.5 * self.k * (q - self.rest) * (q - self.rest)
    }

    pub fn dissipation(&self, kin: &BodyKin) -> f64 {
        let (_, v) = self.q_v(kin);
        self.c * v * v
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

    pub fn force(&self, ka: &BodyKin, t: f64) -> [f64; 6] {
        let (f, tau) = self.at(t);
        let rho = ka.rot.apply(self.pa);
        let mut q = [0.0; 6];
        put(&mut q, 0, point_force(f, rho));
        q[2] += tau;
        q
    }

    pub fn jacobian(&self, ka: &BodyKin, t: f64, km: &mut Mat6) {
        let (f, _) = self.at(t);
        let rho = ka.rot.apply(self.pa);
        km[2][2] += rho.dot(f);
    }

    pub fn power(&self, ka: &BodyKin, t: f64) -> f64 {
        let (f, tau) = self.at(t);
        let rho = ka.rot.apply(self.pa);
        f.dot(ka.v + ka.w * rho.perp()) + tau * ka.w
    }

    pub fn next_breakpoint(&self, t: f64) -> Option<f64> {
        [&self.fx, &self.fy, &self.torque].iter().filter_map(|f| f.next_breakpoint(t)).reduce(f64::min)
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

    pub fn force(&self, ka: &BodyKin, kb: &BodyKin, t: f64) -> [f64; 6] {
        self.eval_states(t, &body_state(ka), &body_state(kb))
    }

    /// Central differences over the 12 inputs of the element.
    pub fn jacobian(&self, ka: &BodyKin, kb: &BodyKin, t: f64, km: &mut Mat6, dm: &mut Mat6) {
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
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The scalar law along a direction (the local friction solve) agrees
    /// with the vector law: `t . phi(v)` and `t^T (d phi/dv) t`.
    #[test]
    fn law_along_a_direction_matches_the_vector_law() {
        for law in [FrictionLaw::Linear, FrictionLaw::Smooth] {
            let k = FrictionK { a: 1, b: 0, pa: V2::default(), force: 1.0, v_eps: 1e-3, law };
            let t = V2::new(0.8, -0.6);
            let n = t.perp();
            for (a, b) in [(0.0, 0.0), (2e-4, 1e-5), (-5e-4, 3e-4), (0.3, 1e-4), (-0.02, -1e-3), (1e-3, 0.0)] {
                let v = t.scale(a) + n.scale(b);
                let (phi, dphi) = k.law(v);
                let expect_slope =
                    t.x * (dphi[0][0] * t.x + dphi[0][1] * t.y) + t.y * (dphi[1][0] * t.x + dphi[1][1] * t.y);
                // across = v x t (only its square enters)
                let (p, s) = k.law_along(v.dot(t), v.cross(t));
                assert!((p - phi.dot(t)).abs() < 1e-12, "{law:?} {a} {b}: phi {p} vs {}", phi.dot(t));
                assert!(
                    (s - expect_slope).abs() <= 1e-9 * expect_slope.abs().max(1.0),
                    "{law:?} {a} {b}: slope {s} vs {expect_slope}"
                );
            }
        }
    }

    /// A body's kinematics from a pose and velocity.
    pub(crate) fn kin_at(x: f64, y: f64, phi: f64, vx: f64, vy: f64, w: f64) -> BodyKin {
        BodyKin { r: V2::new(x, y), phi, rot: Rot::new(phi), v: V2::new(vx, vy), w }
    }

    /// The centred forms (an offset of zero left out rather than computed)
    /// give what the general forms give, bit for bit (the general forms are
    /// checked against finite differences in `tests/jacobian_fd.rs`): a
    /// bushing to a bearing's centre and a bearing's friction, both laws,
    /// sliding and sticking, the bearing translating only or turning (the
    /// spec's prismatic form, whose bearing has an angle coordinate).
    #[test]
    fn centred_forms_give_the_general_forms_results() {
        let frame = kin_at(0.3, -0.2, 0.21, 0.4, -0.1, 0.7);
        let base = kin_at(-0.5, 0.4, -0.13, -0.2, 0.3, -0.4);
        for (vx, vy, w) in
            [(0.35, -0.2, 0.0), (2e-4, -1e-4, 0.0), (0.0, 0.0, 0.0), (0.35, -0.2, -0.9), (2e-4, 0.0, 0.3)]
        {
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
            for law in [FrictionLaw::Linear, FrictionLaw::Smooth] {
                let friction = FrictionK { a: 2, b: 3, pa: V2::default(), force: 10.0, v_eps: 1e-3, law };
                assert_eq!(friction.force_at::<true>(&bearing, &base), friction.force_at::<false>(&bearing, &base));
                assert_eq!(
                    friction.kinematics_at::<true>(&bearing, &base),
                    friction.kinematics_at::<false>(&bearing, &base)
                );
            }
        }
    }
}
