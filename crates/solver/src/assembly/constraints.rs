//! Constraint primitives with their derivatives.
//!
//! Each user constraint is made of primitives: a revolute is a point
//! coincidence, a weld a point coincidence plus an angle, a prismatic joint
//! an angle plus a line, a point-on-line a line, a driver a coordinate
//! equation. A primitive with `k` equations provides, over the coordinates
//! `z = (x_a, y_a, phi_a, x_b, y_b, phi_b)`,
//! - `g(z, t)` (k values) and the rows of `G = dg/dz`,
//! - the Hessian contraction `H = sum_i lambda_i d^2 g_i / dz^2` (6x6),
//! - the velocity constraint `G z' + dg/dt`,
//! - `gamma`, the part of `d^2 g / dt^2` free of accelerations (for the
//!   consistent initial accelerations),
//!
//! through its implementation of [`Primitive`]; the assembly keeps one list
//! per kind ([`Primitives`]) and walks them through a [`PrimVisitor`], as
//! it does the force elements.

use super::kin::{BodyKin, Mat6, V2};
use super::maps::PrimMap;
use crate::timefn::TimeFunction;

/// All six slots (x, y, phi of body a, then of body b) of a constraint row.
const ALL_SLOTS: [usize; 6] = [0, 1, 2, 3, 4, 5];

/// One constraint primitive, as the assembly's loops see it: its equations
/// over the slots `z = (x_a, y_a, phi_a, x_b, y_b, phi_b)` of its two bodies
/// at the kinematics `kin` (every body's) and time `t` [s].
pub(crate) trait Primitive {
    /// The slots its gradient rows can be non-zero in (the others are left
    /// out of the products with them).
    const SLOTS: &'static [usize];
    /// Whether its equations have second derivatives (a Hessian).
    const HESSIAN: bool;
    /// Whether its equations depend on time (`g_t`, [`Self::rate`]).
    const RHEONOMIC: bool;

    /// Its two bodies (the ground, 0, for a driver's second).
    fn bodies(&self) -> (u32, u32);

    /// `g` [m or rad] and the rows of `G = dg/dz`.
    fn rows(&self, kin: &[BodyKin], t: f64) -> Rows;

    /// Adds `sum_i lambda_i d^2 g_i / dz^2` into `h`, with the multipliers
    /// of its equations at `lam[eq..]` [N or N m].
    #[inline(always)]
    fn hessian(&self, _kin: &[BodyKin], _lam: &[f64], _eq: usize, _h: &mut Mat6) {}

    /// `gamma`, the part of `d^2 g / dt^2` free of accelerations, per
    /// equation [m/s^2 or rad/s^2].
    fn gamma(&self, kin: &[BodyKin], t: f64) -> [f64; 2];

    /// `dg/dt` of its (one) equation [m/s or rad/s] (read only if
    /// [`Self::RHEONOMIC`]).
    #[inline(always)]
    fn rate(&self, _t: f64) -> f64 {
        0.0
    }
}

/// One operation over the constraint primitives, run on each kind's list
/// in turn ([`Primitives::visit`]).
pub(crate) trait PrimVisitor {
    /// Runs the operation on the primitives of one kind, in their order.
    fn visit<P: Primitive>(&mut self, prims: &[(P, PrimMap)]);
}

/// The compiled constraint primitives, one list per kind, each with its
/// scatter map.
#[derive(Debug, Clone, Default)]
pub(crate) struct Primitives {
    pub points: Vec<(PointK, PrimMap)>,
    pub angles: Vec<(AngleK, PrimMap)>,
    pub lines: Vec<(LineK, PrimMap)>,
    pub drivers: Vec<(DriverK, PrimMap)>,
}

impl Primitives {
    /// Runs `visitor` on the points, angles, lines and drivers, in that
    /// order (the order of every sum over them).
    #[inline(always)]
    pub fn visit<V: PrimVisitor>(&self, visitor: &mut V) {
        visitor.visit(&self.points);
        visitor.visit(&self.angles);
        visitor.visit(&self.lines);
        visitor.visit(&self.drivers);
    }

    /// Runs `visitor` on one primitive.
    pub fn visit_one<V: PrimVisitor>(&self, prim: PrimRef, visitor: &mut V) {
        match prim {
            PrimRef::Point(i) => visitor.visit(std::slice::from_ref(&self.points[i as usize])),
            PrimRef::Angle(i) => visitor.visit(std::slice::from_ref(&self.angles[i as usize])),
            PrimRef::Line(i) => visitor.visit(std::slice::from_ref(&self.lines[i as usize])),
            PrimRef::Driver(i) => visitor.visit(std::slice::from_ref(&self.drivers[i as usize])),
            // (not a primitive: the callers handle it, see `super::linear`)
            PrimRef::Linear(_) => {}
        }
    }
}

/// Which primitive of [`Primitives`] (or linear equation) a part of a user
/// constraint is.
#[derive(Debug, Clone, Copy)]
pub(crate) enum PrimRef {
    Point(u32),
    Angle(u32),
    Line(u32),
    Driver(u32),
    /// A linear constraint's equation, in [`super::Assembly::linear`].
    Linear(u32),
}

/// Point of body `a` coincides with point of body `b` (2 equations).
#[derive(Debug, Clone)]
pub(crate) struct PointK {
    pub a: u32,
    pub b: u32,
    pub pa: V2,
    pub pb: V2,
}

/// Relative angle `phi_a - phi_b - phi0 = 0` (1 equation).
#[derive(Debug, Clone)]
pub(crate) struct AngleK {
    pub a: u32,
    pub b: u32,
    pub phi0: f64,
}

/// Point `pa` of body `a` lies on the line through `lb` along unit `ub` of body `b` (1 equation).
#[derive(Debug, Clone)]
pub(crate) struct LineK {
    pub a: u32,
    pub b: u32,
    pub pa: V2,
    pub lb: V2,
    pub ub: V2,
}

/// Coordinate `slot` of body `a` equals `f(t)` (1 equation).
#[derive(Debug, Clone)]
pub(crate) struct DriverK {
    pub a: u32,
    pub slot: u8,
    pub motion: TimeFunction,
}

/// Equation values and gradient rows of one primitive (up to 2 equations).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Rows {
    pub g: [f64; 2],
    pub grad: [[f64; 6]; 2],
}

impl PointK {
    fn parts(&self, ka: &BodyKin, kb: &BodyKin) -> (V2, V2) {
        (ka.rot.apply(self.pa), kb.rot.apply(self.pb))
    }
}

impl Primitive for PointK {
    const SLOTS: &'static [usize] = &ALL_SLOTS;
    const HESSIAN: bool = true;
    const RHEONOMIC: bool = false;

    fn bodies(&self) -> (u32, u32) {
        (self.a, self.b)
    }

    #[inline(always)]
    fn rows(&self, kin: &[BodyKin], _t: f64) -> Rows {
        let (ka, kb) = (&kin[self.a as usize], &kin[self.b as usize]);
        let (ra, rb) = self.parts(ka, kb);
        let g = (ka.r + ra) - (kb.r + rb);
        let (sa, sb) = (ra.perp(), rb.perp());
        Rows { g: [g.x, g.y], grad: [[1.0, 0.0, sa.x, -1.0, 0.0, -sb.x], [0.0, 1.0, sa.y, 0.0, -1.0, -sb.y]] }
    }

    fn hessian(&self, kin: &[BodyKin], lam: &[f64], eq: usize, h: &mut Mat6) {
        let (ka, kb) = (&kin[self.a as usize], &kin[self.b as usize]);
        let lam = &lam[eq..eq + 2];
        let (ra, rb) = self.parts(ka, kb);
        let l = V2::new(lam[0], lam[1]);
        h[2][2] += -l.dot(ra);
        h[5][5] += l.dot(rb);
    }

    fn gamma(&self, kin: &[BodyKin], _t: f64) -> [f64; 2] {
        let (ka, kb) = (&kin[self.a as usize], &kin[self.b as usize]);
        let (ra, rb) = self.parts(ka, kb);
        let g = -(ka.w * ka.w * ra) + kb.w * kb.w * rb;
        [g.x, g.y]
    }
}

/// The slots an angle constraint's row depends on (the two angles).
const ANGLE_SLOTS: [usize; 2] = [2, 5];

impl Primitive for AngleK {
    const SLOTS: &'static [usize] = &ANGLE_SLOTS;
    const HESSIAN: bool = false;
    const RHEONOMIC: bool = false;

    fn bodies(&self) -> (u32, u32) {
        (self.a, self.b)
    }

    fn rows(&self, kin: &[BodyKin], _t: f64) -> Rows {
        let (ka, kb) = (&kin[self.a as usize], &kin[self.b as usize]);
        let mut r = Rows { g: [ka.phi - kb.phi - self.phi0, 0.0], ..Rows::default() };
        r.grad[0][2] = 1.0;
        r.grad[0][5] = -1.0;
        r
    }

    fn gamma(&self, _kin: &[BodyKin], _t: f64) -> [f64; 2] {
        [0.0; 2]
    }
}

struct LineEval {
    rho_a: V2,
    lam_b: V2,
    n: V2,
    w: V2,
}

impl LineK {
    #[inline(always)]
    fn eval(&self, ka: &BodyKin, kb: &BodyKin) -> LineEval {
        if self.pa == V2::default() && self.lb == V2::default() {
            self.eval_at::<true>(ka, kb)
        } else {
            self.eval_at::<false>(ka, kb)
        }
    }

    /// The evaluation; with `CENTRED` (`pa` and `lb` zero: a bearing's
    /// centre on its beam's axis) the terms of the offsets are left out
    /// rather than computed as zeros.
    #[inline(always)]
    fn eval_at<const CENTRED: bool>(&self, ka: &BodyKin, kb: &BodyKin) -> LineEval {
        let rho_a = if CENTRED { V2::default() } else { ka.rot.apply(self.pa) };
        let lam_b = if CENTRED { V2::default() } else { kb.rot.apply(self.lb) };
        let n = kb.rot.apply(self.ub.perp());
        let w = if CENTRED { ka.r - kb.r } else { (ka.r + rho_a) - (kb.r + lam_b) };
        LineEval { rho_a, lam_b, n, w }
    }

    #[inline(always)]
    fn rows_at<const CENTRED: bool>(&self, ka: &BodyKin, kb: &BodyKin) -> Rows {
        let e = self.eval_at::<CENTRED>(ka, kb);
        let n = e.n;
        let gphib = if CENTRED { n.perp().dot(e.w) } else { n.perp().dot(e.w) - n.dot(e.lam_b.perp()) };
        let grad_phia = if CENTRED { 0.0 } else { n.dot(e.rho_a.perp()) };
        let mut r = Rows { g: [n.dot(e.w), 0.0], ..Rows::default() };
        r.grad[0] = [n.x, n.y, grad_phia, -n.x, -n.y, gphib];
        r
    }
}

impl Primitive for LineK {
    const SLOTS: &'static [usize] = &ALL_SLOTS;
    const HESSIAN: bool = true;
    const RHEONOMIC: bool = false;

    fn bodies(&self) -> (u32, u32) {
        (self.a, self.b)
    }

    #[inline(always)]
    fn rows(&self, kin: &[BodyKin], _t: f64) -> Rows {
        let (ka, kb) = (&kin[self.a as usize], &kin[self.b as usize]);
        if self.pa == V2::default() && self.lb == V2::default() {
            self.rows_at::<true>(ka, kb)
        } else {
            self.rows_at::<false>(ka, kb)
        }
    }

    fn hessian(&self, kin: &[BodyKin], lam: &[f64], eq: usize, h: &mut Mat6) {
        let (ka, kb) = (&kin[self.a as usize], &kin[self.b as usize]);
        let lam = lam[eq];
        let e = self.eval(ka, kb);
        let n = e.n;
        let np = n.perp();
        h[2][2] += lam * -n.dot(e.rho_a);
        let x = lam * n.dot(e.rho_a);
        h[2][5] += x;
        h[5][2] += x;
        for (i, v) in [(0usize, np.x), (1, np.y), (3, -np.x), (4, -np.y)] {
            h[5][i] += lam * v;
            h[i][5] += lam * v;
        }
        h[5][5] += lam * (-n.dot(e.w) - n.dot(e.lam_b));
    }

    fn gamma(&self, kin: &[BodyKin], _t: f64) -> [f64; 2] {
        let (ka, kb) = (&kin[self.a as usize], &kin[self.b as usize]);
        let e = self.eval(ka, kb);
        let wdot = (ka.v + ka.w * e.rho_a.perp()) - (kb.v + kb.w * e.lam_b.perp());
        let (wa, wb) = (ka.w, kb.w);
        [
            -wb * wb * e.n.dot(e.w) + 2.0 * wb * e.n.perp().dot(wdot) - wa * wa * e.n.dot(e.rho_a)
                + wb * wb * e.n.dot(e.lam_b),
            0.0,
        ]
    }
}

impl DriverK {
    pub fn coordinate(&self, ka: &BodyKin) -> f64 {
        match self.slot {
            0 => ka.r.x,
            1 => ka.r.y,
            _ => ka.phi,
        }
    }

    /// `dg/dt = -f'(t)` and `-f''(t)`.
    pub fn time_derivatives(&self, t: f64) -> (f64, f64) {
        let e = self.motion.eval(t);
        (-e[1], -e[2])
    }
}

impl Primitive for DriverK {
    const SLOTS: &'static [usize] = &ALL_SLOTS;
    const HESSIAN: bool = false;
    const RHEONOMIC: bool = true;

    fn bodies(&self) -> (u32, u32) {
        (self.a, 0)
    }

    fn rows(&self, kin: &[BodyKin], t: f64) -> Rows {
        let mut r = Rows { g: [self.coordinate(&kin[self.a as usize]) - self.motion.value(t), 0.0], ..Rows::default() };
        r.grad[0][self.slot as usize] = 1.0;
        r
    }

    fn gamma(&self, _kin: &[BodyKin], t: f64) -> [f64; 2] {
        [self.time_derivatives(t).1, 0.0]
    }

    #[inline(always)]
    fn rate(&self, t: f64) -> f64 {
        self.time_derivatives(t).0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assembly::forces::tests::kin_at;

    /// A bearing's centre on its beam's axis: the centred form of the line
    /// (offsets of zero left out rather than computed) gives the general
    /// form's rows bit for bit, and the same Hessian and `gamma`.
    #[test]
    fn centred_line_gives_the_general_rows() {
        let line = LineK { a: 1, b: 2, pa: V2::default(), lb: V2::default(), ub: V2::new(0.6, 0.8) };
        let base = kin_at(-0.5, 0.4, -0.13, -0.2, 0.3, -0.4);
        for w in [0.0, 0.8] {
            let bearing = kin_at(0.1, 0.6, 0.26, 0.35, -0.2, w);
            let (c, g) = (line.rows_at::<true>(&bearing, &base), line.rows_at::<false>(&bearing, &base));
            assert_eq!((c.g, c.grad), (g.g, g.grad));
            let (c, g) = (line.eval_at::<true>(&bearing, &base), line.eval_at::<false>(&bearing, &base));
            assert_eq!((c.rho_a, c.lam_b, c.n, c.w), (g.rho_a, g.lam_b, g.n, g.w));
        }
    }
}
