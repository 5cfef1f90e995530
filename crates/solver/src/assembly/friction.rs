//! Regularised Coulomb friction: the force law with its derivatives
//! ([`ForceKernel`]), and the law along a line that the integrator's local
//! friction solve uses (`crate::integrator::local_friction`).

use super::element::{At, ForceKernel, PeakForce, PowerFlow};
use super::forces::{point_force, put};
use super::kin::{add_btcb, add_btcp, BodyKin, Mat6, V2};
use super::maps::PairMap;
use crate::model::force::FrictionLaw;

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
}

impl ForceKernel for FrictionK {
    type Map = PairMap;
    const DAMPING: bool = true;
    const STORES_ENERGY: bool = false;
    const POWER: Option<PowerFlow> = Some(PowerFlow::Friction);
    const PEAK: Option<PeakForce> = Some(PeakForce::Friction);

    #[inline(always)]
    fn force(&self, at: &At, _i: usize) -> [f64; 6] {
        let (ka, kb) = at.pair(self.a, self.b);
        if self.pa == V2::default() {
            self.force_at::<true>(ka, kb)
        } else {
            self.force_at::<false>(ka, kb)
        }
    }

    /// Derivatives of the friction force. In the integrator's iteration
    /// Jacobian (`at.zone` marks element `i`), `d phi / dv` is replaced by
    /// the slope of the law inside its regularisation zone, `I / v_eps`,
    /// whatever the state (see [`crate::integrator::radau5`]).
    fn derivatives(&self, at: &At, i: usize, km: &mut Mat6, dm: &mut Mat6) {
        let zone_slope = at.zone.is_some_and(|z| z[i]);
        let (ka, kb) = at.pair(self.a, self.b);
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
    /// first value of [`FrictionK::law`] bit for bit.)
    #[inline(always)]
    fn add_power(&self, at: &At, _i: usize, _map: &PairMap, acc: &mut f64) {
        let (ka, kb) = at.pair(self.a, self.b);
        let (_, _, v) = self.kinematics(ka, kb);
        let f = -(self.force * self.phi(v));
        *acc += -f.dot(v);
    }

    /// Square of the friction force's magnitude [N^2].
    #[inline(always)]
    fn reaction_squared(&self, at: &At, _i: usize) -> f64 {
        let (ka, kb) = at.pair(self.a, self.b);
        let (_, _, v) = self.kinematics(ka, kb);
        (-(self.force * self.phi(v))).norm_squared()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assembly::forces::tests::{kin_at, BEARING_STATES};

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

    /// The centred form (the slider's offset of zero left out rather than
    /// computed) gives what the general form gives, bit for bit: a bearing's
    /// friction, both laws, sliding and sticking, the bearing translating
    /// only or turning.
    #[test]
    fn centred_friction_gives_the_general_results() {
        let base = kin_at(-0.5, 0.4, -0.13, -0.2, 0.3, -0.4);
        for (vx, vy, w) in BEARING_STATES {
            let bearing = kin_at(0.1, 0.6, 0.26, vx, vy, w);
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
