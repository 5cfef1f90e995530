//! The contact kernel: penetration, force, stiffness and damping of a point
//! against an edge ([`crate::model::force::Contact`]).
//!
//! With `z = (x_a, y_a, phi_a, x_b, y_b, phi_b)`, body `a` carrying the
//! point `p = r_a + A_a s_a` and body `b` the edge through `e = r_b + A_b s_b`
//! with normal `n = A_b n_b`, the penetration is `delta = -n . (p - e)` and
//! `J = -d delta / dz = (n, rho_a x n, -n, -(p - r_b) x n)` (`rho_a = A_a s_a`).
//! A closed contact applies the generalised force `Q = F J` with
//! `F = F(delta, delta')`, `delta' = -J . z'`, so that
//! - `K = -dQ/dz = F_d J J^T - F_v J (H z')^T + F H`,
//! - `D = -dQ/dz' = F_v J J^T`,
//!
//! where `F_d`, `F_v` are the law's partial derivatives and `H` the Hessian
//! of `delta` (non-zero only in the rows and columns of `phi_a` and `phi_b`):
//! `H[r_a][phi_b] = -perp(n)`, `H[r_b][phi_b] = perp(n)`,
//! `H[phi_a][phi_a] = n . rho_a`, `H[phi_a][phi_b] = -n . rho_a`,
//! `H[phi_b][phi_b] = n . (p - r_b)`. The tests of [`crate::fd`] check the
//! kernel against central differences.
//!
//! Inside a closed contact the law is used as written for every sign of
//! `delta` (`sign(delta) |delta|^1.5` for Hertz): the mode changes only at
//! the integrator's events, so within a step the force is smooth.

use super::element::{At, ForceKernel, PeakForce, PowerFlow};
use super::kin::{BodyKin, Mat6, V2};
use super::maps::PairMap;
use crate::model::force::{ContactLaw, HertzDamping, MIN_APPROACH_SPEED};

/// The compiled law.
#[derive(Debug, Clone, Copy)]
pub(crate) enum LawK {
    Linear { k: f64, c: f64 },
    Hertz { k: f64, factor: f64 },
}

/// A contact between a point of `a` and an edge of `b`.
#[derive(Debug, Clone)]
pub(crate) struct ContactK {
    pub a: u32,
    pub b: u32,
    pub sa: V2,
    pub sb: V2,
    pub nb: V2,
    pub law: LawK,
}

/// Geometry and rates of one evaluation.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Gap {
    /// Penetration [m] (positive when overlapping).
    pub delta: f64,
    /// Its rate [m/s].
    pub rate: f64,
    n: V2,
    rho_a: V2,
    d_b: V2,
}

impl LawK {
    /// The law of a [`ContactLaw`] between bodies of reduced mass `mass` [kg].
    pub fn new(law: &ContactLaw, mass: f64) -> Self {
        match *law {
            ContactLaw::Linear { stiffness, restitution } => {
                let l = restitution.ln();
                let zeta = -l / (std::f64::consts::PI.powi(2) + l * l).sqrt();
                LawK::Linear { k: stiffness, c: 2.0 * zeta * (stiffness * mass).sqrt() }
            }
            ContactLaw::Hertz { stiffness, restitution, damping } => {
                LawK::Hertz { k: stiffness, factor: HertzDamping::factor(damping, restitution) }
            }
        }
    }

    /// Force `F` and its derivatives `F_d`, `F_v` at penetration `d`, rate
    /// `v`, approach speed at onset `v0`.
    #[inline]
    pub fn eval(&self, d: f64, v: f64, v0: f64) -> (f64, f64, f64) {
        match *self {
            LawK::Linear { k, c } => (k * d + c * v, k, c),
            LawK::Hertz { k, factor } => {
                let damp = factor / v0.max(MIN_APPROACH_SPEED);
                let a = d.abs();
                let root = a.sqrt();
                let spring = k * d * root; // sign(d) |d|^1.5
                (spring * (1.0 + damp * v), 1.5 * k * root * (1.0 + damp * v), spring * damp)
            }
        }
    }

    /// Elastic energy stored at penetration `d` [J].
    pub fn energy(&self, d: f64) -> f64 {
        match *self {
            LawK::Linear { k, .. } => 0.5 * k * d * d,
            LawK::Hertz { k, .. } => 0.4 * k * d.abs().powf(2.5),
        }
    }

    /// Power dissipated by the damping part at penetration `d`, rate `v` [W].
    pub fn dissipation(&self, d: f64, v: f64, v0: f64) -> f64 {
        match *self {
            LawK::Linear { c, .. } => c * v * v,
            LawK::Hertz { k, factor } => k * d * d.abs().sqrt() * factor / v0.max(MIN_APPROACH_SPEED) * v * v,
        }
    }
}

impl ContactK {
    /// Penetration, its rate and the geometry for the derivatives.
    #[inline]
    pub fn gap(&self, ka: &BodyKin, kb: &BodyKin) -> Gap {
        let rho_a = ka.rot.apply(self.sa);
        let p = ka.r + rho_a;
        let n = kb.rot.apply(self.nb);
        let e = kb.r + kb.rot.apply(self.sb);
        let d_b = p - kb.r;
        let delta = -n.dot(p - e);
        // delta' = -J . z'
        let rate = -(n.dot(ka.v) + ka.w * rho_a.cross(n) - n.dot(kb.v) - kb.w * d_b.cross(n));
        Gap { delta, rate, n, rho_a, d_b }
    }

    /// `J = -d delta / dz`.
    #[inline]
    fn j(g: &Gap) -> [f64; 6] {
        let n = g.n;
        [n.x, n.y, g.rho_a.cross(n), -n.x, -n.y, -g.d_b.cross(n)]
    }
}

impl ForceKernel for ContactK {
    type Map = PairMap;
    const DAMPING: bool = true;
    const STORES_ENERGY: bool = true;
    const POWER: Option<PowerFlow> = Some(PowerFlow::Contact);
    const PEAK: Option<PeakForce> = None;

    /// Only while closed (the integrator's mode of the step).
    #[inline(always)]
    fn acts(&self, at: &At, i: usize) -> bool {
        at.closed[i]
    }

    /// Generalised forces of the closed contact.
    fn force(&self, at: &At, i: usize) -> [f64; 6] {
        let (ka, kb) = at.pair(self.a, self.b);
        let g = self.gap(ka, kb);
        let (f, _, _) = self.law.eval(g.delta, g.rate, at.v0[i]);
        Self::j(&g).map(|x| f * x)
    }

    /// Stiffness and damping of the closed contact.
    fn derivatives(&self, at: &At, i: usize, km: &mut Mat6, dm: &mut Mat6) {
        let (ka, kb) = at.pair(self.a, self.b);
        let v0 = at.v0[i];
        let g = self.gap(ka, kb);
        let (f, fd, fv) = self.law.eval(g.delta, g.rate, v0);
        let j = Self::j(&g);
        // Hessian of delta
        let np = g.n.perp();
        let mut h = [[0.0; 6]; 6];
        for (i, v) in [(0, -np.x), (1, -np.y), (3, np.x), (4, np.y)] {
            h[i][5] = v;
            h[5][i] = v;
        }
        let na = g.n.dot(g.rho_a);
        h[2][2] = na;
        h[2][5] = -na;
        h[5][2] = -na;
        h[5][5] = g.n.dot(g.d_b);
        let zdot = [ka.v.x, ka.v.y, ka.w, kb.v.x, kb.v.y, kb.w];
        let hz: [f64; 6] = std::array::from_fn(|i| (0..6).map(|k| h[i][k] * zdot[k]).sum());
        for r in 0..6 {
            for c in 0..6 {
                km[r][c] += fd * j[r] * j[c] - fv * j[r] * hz[c] + f * h[r][c];
                dm[r][c] += fv * j[r] * j[c];
            }
        }
    }

    /// Elastic energy stored at the penetration [J].
    fn potential(&self, at: &At, _i: usize) -> f64 {
        let (ka, kb) = at.pair(self.a, self.b);
        self.law.energy(self.gap(ka, kb).delta)
    }

    /// Dissipated by the law's damping [W].
    fn add_power(&self, at: &At, i: usize, _map: &PairMap, acc: &mut f64) {
        let (ka, kb) = at.pair(self.a, self.b);
        let g = self.gap(ka, kb);
        *acc += self.law.dissipation(g.delta, g.rate, at.v0[i]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assembly::kin::Rot;

    /// The kinematics of the ground, body 1 (`z[0..3]`) and body 2 (`z[3..6]`).
    fn kin(z: &[f64], zd: &[f64]) -> [BodyKin; 3] {
        let body = |o: usize| BodyKin {
            r: V2::new(z[o], z[o + 1]),
            phi: z[o + 2],
            rot: Rot::new(z[o + 2]),
            v: V2::new(zd[o], zd[o + 1]),
            w: zd[o + 2],
        };
        [BodyKin::default(), body(0), body(3)]
    }

    /// The kernel's stiffness and damping against central differences of
    /// its own force.
    #[test]
    fn kernel_derivatives() {
        let law = LawK::Hertz { k: 3e6, factor: 0.6 };
        let c = ContactK { a: 1, b: 2, sa: V2::new(0.2, 0.1), sb: V2::new(-0.1, 0.05), nb: V2::new(-0.8, 0.6), law };
        let z = [0.31, 0.18, 0.27, 0.62, -0.09, -0.21];
        let zd = [0.4, -0.3, 0.7, -0.2, 0.5, -0.6];
        let force = |z: &[f64], zd: &[f64]| c.force(&At::new(&kin(z, zd), 0.0, &[true], &[0.3]), 0);
        let (mut km, mut dm) = ([[0.0; 6]; 6], [[0.0; 6]; 6]);
        c.derivatives(&At::new(&kin(&z, &zd), 0.0, &[true], &[0.3]), 0, &mut km, &mut dm);
        for col in 0..6 {
            let h = 1e-6;
            let (mut zp, mut zm) = (z, z);
            zp[col] += h;
            zm[col] -= h;
            let (fp, fm) = (force(&zp, &zd), force(&zm, &zd));
            let (mut vp, mut vm) = (zd, zd);
            vp[col] += h;
            vm[col] -= h;
            let (gp, gm) = (force(&z, &vp), force(&z, &vm));
            for row in 0..6 {
                let k_fd = -(fp[row] - fm[row]) / (2.0 * h);
                let d_fd = -(gp[row] - gm[row]) / (2.0 * h);
                assert!(
                    (km[row][col] - k_fd).abs() < 1e-5 * k_fd.abs().max(1.0),
                    "K[{row}][{col}]: {} vs {k_fd}",
                    km[row][col]
                );
                assert!(
                    (dm[row][col] - d_fd).abs() < 1e-5 * d_fd.abs().max(1.0),
                    "D[{row}][{col}]: {} vs {d_fd}",
                    dm[row][col]
                );
            }
        }
    }

    /// The Hertz law's derivatives against central differences, on both
    /// sides of zero penetration.
    #[test]
    fn law_derivatives() {
        for law in [LawK::Linear { k: 2e9, c: 3e4 }, LawK::Hertz { k: 1e10, factor: 0.6 }] {
            for (d, v) in [(1e-4, 0.3), (-2e-5, 0.1), (3e-4, -0.2)] {
                let (_, fd, fv) = law.eval(d, v, 0.5);
                let h = 1e-9;
                let nd = (law.eval(d + h, v, 0.5).0 - law.eval(d - h, v, 0.5).0) / (2.0 * h);
                let nv = (law.eval(d, v + 1e-6, 0.5).0 - law.eval(d, v - 1e-6, 0.5).0) / 2e-6;
                assert!((fd - nd).abs() <= 1e-5 * nd.abs().max(1.0), "{law:?} {d} {v}: {fd} vs {nd}");
                assert!((fv - nv).abs() <= 1e-5 * nv.abs().max(1.0), "{law:?} {d} {v}: {fv} vs {nv}");
            }
        }
    }
}
