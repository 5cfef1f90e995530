//! Local solve of sliding friction inside the Radau IIA Newton iteration.
//!
//! Regularised Coulomb friction (`F = -F_c v / max(|v|, v_eps)`) makes the
//! stage equations of a slider piecewise smooth with slopes from 0 (sliding,
//! along the motion) to `F_c / v_eps` (inside the regularisation zone). One
//! iteration matrix cannot match both: with the sliding slope, Newton jumps
//! across the zone and cycles; with the zone slope, it contracts at
//! `~F_c/v_eps / (F_c/v_eps + m gamma/h)` on a sliding slider; and a step in
//! which a slider sticks at one stage and slides at another defeats any
//! single slope unless `h < ~m gamma v_eps / F_c`. So, for every friction
//! element whose slider runs on a line of its base (a prismatic joint or a
//! point-on-line constraint):
//! - the iteration matrix holds the zone slope `F_c / v_eps` (the regime of
//!   a reversal), whatever the state, so it no longer changes with the
//!   sliding direction and is kept over many steps
//!   ([`crate::Assembly`]'s iteration Jacobian);
//! - at every Newton iteration, before the global correction, the three
//!   stage values of the slider's velocity along its line are solved locally
//!   with everything else held at the iterate: the slider's stage equations
//!   along the line with the exact law, linear inertia, stiffness and damping
//!   (3 unknowns, damped semismooth Newton with a residual monotonicity
//!   test). This is nonlinear elimination (P. J. Lanzkron, D. J. Rose and
//!   J. T. Wilkes, "An analysis of approximate nonlinear elimination", SIAM
//!   J. Sci. Comput. 17 (1996) 538-559): the stiff non-smooth unknowns are
//!   eliminated by a local solve, and the simplified Newton iteration sees a
//!   system whose coupling to the slider hardly depends on its regime (the
//!   bushing to a slider of mass `m` differs from a bushing to a fixed point
//!   by `k / (m (gamma/h)^2)`).
//!
//! The zone slope also enters the filter `(gamma/h M + D + K/(gamma/h))^-1`
//! of the error estimate, which damps the sliders' own velocity errors; the
//! joint's results (peak deck acceleration, friction energy, peak joint force,
//! sub-gaps) were checked against runs at 100 times tighter tolerances on the
//! small, medium and reference expansion-joint models (docs/performance.md).

use super::radau5::A;
use crate::assembly::friction::FrictionK;
use crate::assembly::kin::V2;
use crate::assembly::{Assembly, JacobianValues, Workspace};
use crate::linalg::small::solve3_adjugate;
use crate::model::force::FrictionLaw;

/// `A^-1` of the Butcher matrix of Radau IIA (s = 3).
pub(super) const AINV: [[f64; 3]; 3] = [
    [3.224_744_871_391_589, 1.167_840_084_690_405_5, -0.253_197_264_742_180_9],
    [-3.567_840_084_690_405_5, 0.775_255_128_608_411, 1.053_197_264_742_181],
    [5.531_972_647_421_808, -7.531_972_647_421_808, 5.0],
];

/// Relative residual at which a local solve stops.
const LOCAL_TOL: f64 = 1e-10;
/// Iterations of one local solve.
const LOCAL_ITERATIONS: usize = 40;

/// A friction element whose slider runs on a line of its base, solved
/// locally ([`sliders`]).
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
    /// velocity with components `a` along the direction and `b` across it
    /// [m/s].
    #[inline]
    pub fn law_along(&self, a: f64, b: f64) -> (f64, f64) {
        self.kernel.law_along(a, b)
    }

    /// Whether the law is linear inside the zone `|v| < v_eps` and, along a
    /// line crossed by no velocity, constant outside it (the linear law).
    pub fn is_linear_law(&self) -> bool {
        self.kernel.law == FrictionLaw::Linear
    }

    /// The slider's relative sliding velocity [m/s] and the unit direction
    /// of its line, from the kinematics loaded into `ws` by the last
    /// evaluation (e.g. [`Assembly::residual`]).
    fn state(&self, asm: &Assembly, ws: &Workspace) -> (V2, V2) {
        let k = &self.kernel;
        let (ka, kb) = (&ws.kin[k.a as usize], &ws.kin[k.b as usize]);
        (k.rel_velocity(ka, kb), kb.rot.apply(asm.prims.lines[self.line as usize].0.ub))
    }
}

/// The friction elements of `asm` whose slider runs on a line of its base
/// (of a prismatic joint or a point-on-line constraint) and moves freely in
/// x and y: those the integrator solves locally.
pub(crate) fn sliders(asm: &Assembly) -> Vec<SliderInfo> {
    let n = asm.coordinates() as u32;
    let lines = &asm.prims.lines;
    asm.elements
        .frictions
        .iter()
        .enumerate()
        .filter_map(|(e, (k, map))| {
            let line = lines.iter().position(|(l, _)| l.a == k.a && l.b == k.b)?;
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

/// The sliders solved locally and their state at the three stages.
#[derive(Debug, Clone, Default)]
pub(super) struct LocalFriction {
    sliders: Vec<SliderInfo>,
    /// Per stage and slider: relative sliding velocity and the unit
    /// direction of the line, at the last residual evaluation.
    stage: [Vec<(V2, V2)>; 3],
}

/// One slider's local problem at one Newton iteration.
struct Local<'a> {
    info: &'a SliderInfo,
    /// Stage velocities along the line (`v_i . t_i`) and across it.
    along: [f64; 3],
    across: [f64; 3],
    /// `L = m/h A^-1 + h k_t A + c_t I`.
    lmat: [[f64; 3]; 3],
    /// Stage residuals along the line at `d = 0`.
    r0: [f64; 3],
    /// `t_i . phi(v_i)`.
    phi0: [f64; 3],
}

impl Local<'_> {
    /// `t . phi(v + d t)` at stage `i` and its slope along `t` times the
    /// force scale.
    #[inline(always)]
    fn law(&self, i: usize, d: f64) -> (f64, f64) {
        let (phi, slope) = self.info.law_along(self.along[i] + d, self.across[i]);
        (phi, self.info.force * slope)
    }

    /// Residual and slopes at `d`.
    #[inline(always)]
    fn eval(&self, d: &[f64; 3]) -> ([f64; 3], [f64; 3]) {
        let mut r = [0.0; 3];
        let mut slope = [0.0; 3];
        for i in 0..3 {
            let (phi, s) = self.law(i, d[i]);
            let ld = self.lmat[i][0] * d[0] + self.lmat[i][1] * d[1] + self.lmat[i][2] * d[2];
            r[i] = self.r0[i] - ld - self.info.force * (phi - self.phi0[i]);
            slope[i] = s;
        }
        (r, slope)
    }

    /// Whether `d + step` keeps every stage on the piece of the linear law
    /// it has at `d`, and the Newton step from `d` (with the slopes there)
    /// then solves the local equations to `LOCAL_TOL` of the friction force,
    /// so that no trial evaluation is needed. Inside the zone the law is
    /// linear and the step exact. Outside it the law along the line is
    /// `a / |v|` with the slope `b^2 / |v|^3` (`b` across the line); with `a`
    /// keeping its sign, the step's linearisation error is at most
    /// `2 F b^2 |step| / min(|a_0|, |a_1|)^3`, zero when nothing crosses the
    /// line.
    #[inline(always)]
    fn same_linear_piece(&self, d: &[f64; 3], step: &[f64; 3]) -> bool {
        if !self.info.is_linear_law() {
            return false;
        }
        let v_eps = self.info.v_eps;
        let e2 = v_eps * v_eps;
        // `law_along`'s test of the zone, `sqrt(s) < v_eps`, without the root
        // where `s` is clearly on one side
        let inside_at = |s: f64| if (s - e2).abs() > 1e-12 * e2 { s < e2 } else { s.sqrt() < v_eps };
        (0..3).all(|i| {
            let b2 = self.across[i] * self.across[i];
            // (the speeds as `law_along` forms them)
            let (a0, a1) = (self.along[i] + d[i], self.along[i] + (d[i] + step[i]));
            let inside = inside_at(a0 * a0 + b2);
            if inside != inside_at(a1 * a1 + b2) {
                return false;
            }
            let m = a0.abs().min(a1.abs());
            inside || (a0 * a1 > 0.0 && 2.0 * b2 * step[i].abs() <= LOCAL_TOL * m * m * m)
        })
    }

    /// Damped semismooth Newton from `d = 0` with the slopes there.
    #[inline(always)]
    fn solve(&self, slope0: [f64; 3]) -> [f64; 3] {
        let tol = LOCAL_TOL * (self.info.force + norm3(&self.r0));
        let mut d = [0.0; 3];
        let (mut r, mut slope) = (self.r0, slope0);
        let mut rn = norm3(&r);
        for _ in 0..LOCAL_ITERATIONS {
            if rn <= tol {
                break;
            }
            let mut jm = self.lmat;
            for i in 0..3 {
                jm[i][i] += slope[i];
            }
            let Some(step) = solve3_adjugate(jm, r) else { break };
            if self.same_linear_piece(&d, &step) {
                // the step solves the local equations: no trial evaluation
                return [d[0] + step[0], d[1] + step[1], d[2] + step[2]];
            }
            // damped: the residual must fall (a full step can jump across the zone)
            let mut lambda = 1.0;
            loop {
                let trial = [d[0] + lambda * step[0], d[1] + lambda * step[1], d[2] + lambda * step[2]];
                let (rt, st) = self.eval(&trial);
                let rtn = norm3(&rt);
                if rtn <= (1.0 - 0.25 * lambda) * rn || lambda < 1e-6 {
                    (d, r, slope, rn) = (trial, rt, st, rtn);
                    break;
                }
                lambda *= 0.5;
            }
        }
        d
    }
}

impl LocalFriction {
    /// The friction elements of `asm` whose slider runs on a line of its
    /// base (none when `enabled` is false).
    pub(super) fn new(asm: &Assembly, enabled: bool) -> Self {
        let sliders = if enabled { sliders(asm) } else { Vec::new() };
        let n = sliders.len();
        Self { sliders, stage: [Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n)] }
    }

    /// Whether no slider is solved locally.
    pub(super) fn is_empty(&self) -> bool {
        self.sliders.is_empty()
    }

    /// Per friction element of `asm`, whether it is solved locally (it then
    /// enters the iteration matrix with its zone slope).
    pub(super) fn zone_mask(&self, asm: &Assembly) -> Vec<bool> {
        let mut mask = vec![false; asm.elements.frictions.len()];
        for s in &self.sliders {
            mask[s.friction as usize] = true;
        }
        mask
    }

    /// Records the sliders' state at stage `i` from the kinematics just
    /// loaded into `ws` by the stage's residual evaluation.
    pub(super) fn record_stage(&mut self, asm: &Assembly, ws: &Workspace, i: usize) {
        let out = &mut self.stage[i];
        out.clear();
        out.extend(self.sliders.iter().map(|s| s.state(asm, ws)));
    }

    /// Solves every slider locally (see the module documentation): the stage
    /// values `d_i` added to the slider's velocity along its line `t_i` solve
    /// `r_i(d) = r_i(0) - sum_j L_ij d_j - F_c (t_i . phi(v_i + d_i t_i) - t_i . phi(v_i)) = 0`
    /// with `r_i(0)` the stage residual along the line at the iterate (`fv`
    /// the stage forces, `zv` the stage velocity increments) and
    /// `L = m/h A^-1 + h k_t A + c_t I` (`k_t`, `c_t`: the slider's other
    /// stiffness and damping along the line, from the Jacobian `jac`).
    /// Everything else is held at the iterate. Adds the solutions to `zv`
    /// and returns whether anything changed (the stage residuals must then
    /// be evaluated again).
    pub(super) fn solve(
        &self,
        h: f64,
        mass: &[f64],
        jac: &JacobianValues,
        fv: &[Vec<f64>; 3],
        zv: &mut [Vec<f64>; 3],
    ) -> bool {
        crate::isa::run(
            #[inline(always)]
            || self.solve_impl(h, mass, jac, fv, zv),
        )
    }

    /// [`Self::solve`], compiled into each version of [`crate::isa::run`].
    #[inline(always)]
    fn solve_impl(
        &self,
        h: f64,
        mass: &[f64],
        jac: &JacobianValues,
        fv: &[Vec<f64>; 3],
        zv: &mut [Vec<f64>; 3],
    ) -> bool {
        let mut changed = false;
        // (slices held in registers: through the vectors, every store into
        // `zv` would make the compiler reload their addresses)
        let stage = [&self.stage[0][..], &self.stage[1][..], &self.stage[2][..]];
        let fv = [&fv[0][..], &fv[1][..], &fv[2][..]];
        let [zv0, zv1, zv2] = zv;
        let zv = [&mut zv0[..], &mut zv1[..], &mut zv2[..]];
        let (kvals, dvals) = (&jac.k[..], &jac.d[..]);
        for (k, info) in self.sliders.iter().enumerate() {
            let (cx, cy) = (info.coords[0] as usize, info.coords[1] as usize);
            let st = [stage[0][k], stage[1][k], stage[2][k]];
            let m = mass[cx];
            // the slider's stiffness and damping along the line, less the
            // friction element's own zone slope (its stiffness part is skew)
            let block = |vals: &[f64]| {
                let [xx, xy, yx, yy] = info.jac.map(|p| vals[p as usize]);
                [[xx, xy], [yx, yy]]
            };
            let t3 = st[2].1;
            let kt = along(t3, block(kvals));
            let ct = along(t3, block(dvals)) - info.force / info.v_eps;
            let along_line = st.map(|(v, t)| v.dot(t));
            let across_line = st.map(|(v, t)| v.cross(t));
            let mut local = Local {
                info,
                along: along_line,
                across: across_line,
                lmat: [[0.0; 3]; 3],
                r0: [0.0; 3],
                phi0: [0.0; 3],
            };
            let mut slope0 = [0.0; 3];
            for i in 0..3 {
                for j in 0..3 {
                    local.lmat[i][j] = m / h * AINV[i][j] + h * kt * A[i][j];
                }
                local.lmat[i][i] += ct;
                let t = st[i].1;
                let res = |c: usize| {
                    fv[i][c] - m / h * (AINV[i][0] * zv[0][c] + AINV[i][1] * zv[1][c] + AINV[i][2] * zv[2][c])
                };
                local.r0[i] = t.x * res(cx) + t.y * res(cy);
                (local.phi0[i], slope0[i]) = local.law(i, 0.0);
            }
            let d = local.solve(slope0);
            if d.iter().all(|x| x.is_finite()) && d.iter().any(|x| *x != 0.0) {
                for i in 0..3 {
                    let t = st[i].1;
                    zv[i][cx] += d[i] * t.x;
                    zv[i][cy] += d[i] * t.y;
                }
                changed = true;
            }
        }
        changed
    }
}

/// `t^T a t` for a 2x2 matrix.
#[inline]
fn along(t: V2, a: [[f64; 2]; 2]) -> f64 {
    t.x * (a[0][0] * t.x + a[0][1] * t.y) + t.y * (a[1][0] * t.x + a[1][1] * t.y)
}

fn norm3(r: &[f64; 3]) -> f64 {
    (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The local solve returns a root of the slider's three stage equations
    /// whether the first Newton step stays on one linear piece of the law
    /// (inside the zone, or sliding along the line; returned without a trial
    /// evaluation) or crosses the zone (damped iteration): a 20 kg slider,
    /// 2 kN of friction, v_eps = 1 mm/s, h = 5 ms.
    #[test]
    fn local_solve_finds_the_root_on_every_piece_of_the_law() {
        use crate::model::force::FrictionLaw;
        use crate::reference::FrictionOscillator;
        use crate::AssemblyOptions;
        for law in [FrictionLaw::Linear, FrictionLaw::Smooth] {
            let osc = FrictionOscillator { mass: 20.0, stiffness: 1e7, friction_force: 2e3, v_eps: 1e-3, law, x0: 0.0 };
            let (sys, _) = osc.on_prismatic();
            let asm = Assembly::new(&sys, &AssemblyOptions::default()).unwrap();
            let sliders = sliders(&asm);
            let info = &sliders[0];
            let (m, h, kt, ct) = (20.0, 5e-3, 1e7, 2e3);
            let mut lmat = [[0.0; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    lmat[i][j] = m / h * AINV[i][j] + h * kt * A[i][j];
                }
                lmat[i][i] += ct;
            }
            // (stage velocities along, across, residuals at d = 0)
            let cases = [
                ([2e-4, -3e-4, 1e-4], [0.0; 3], [5.0, -20.0, 8.0]),
                ([0.3, 0.31, 0.32], [0.0; 3], [150.0, -90.0, 40.0]),
                ([-0.2, -0.21, -0.19], [1e-6, -1e-6, 0.0], [-30.0, 60.0, 10.0]),
                ([0.01, 0.002, -0.004], [0.0; 3], [4e3, -6e3, 9e3]),
                ([5e-4, 0.0, -5e-4], [2e-4, 0.0, 1e-4], [-2e4, 3e4, 1e4]),
                // sliding with a little velocity across the line, the speed
                // growing 100-fold: the slope b^2/|v|^3 changes too much
                ([2e-3, 2e-3, 2e-3], [1e-7, 1e-7, 1e-7], [5.3e3, 5.5e3, 1.28e4]),
            ];
            for (k, (along, across, r0)) in cases.into_iter().enumerate() {
                let mut local = Local { info, along, across, lmat, r0, phi0: [0.0; 3] };
                let mut slope0 = [0.0; 3];
                for i in 0..3 {
                    (local.phi0[i], slope0[i]) = local.law(i, 0.0);
                }
                local.r0 = r0;
                let mut jm = lmat;
                (0..3).for_each(|i| jm[i][i] += slope0[i]);
                let first = solve3_adjugate(jm, r0).unwrap();
                // the first three stay on one piece of the linear law
                let expect = law == FrictionLaw::Linear && k < 3;
                assert_eq!(local.same_linear_piece(&[0.0; 3], &first), expect, "{law:?} {along:?}");
                let d = local.solve(slope0);
                let (r, _) = local.eval(&d);
                let scale = info.force + norm3(&r0);
                assert!(norm3(&r) <= 1e-9 * scale, "{law:?} {along:?}: residual {r:?} at d = {d:?}");
            }
        }
    }

    /// The adjugate solve agrees with the pivoted elimination on matrices
    /// shaped like the local friction ones, falls back to it on nearly
    /// dependent rows, and refuses singular or non-finite systems.
    #[test]
    fn solve3_adjugate_matches_the_pivoted_solve() {
        use crate::linalg::small::solve3;
        for (m_h, kh, c, slope) in
            [(4e3, 5e4, 1e3, 0.0), (4e3, 5e4, 1e3, 2e6), (1.0, 1e9, 0.0, 0.0), (1e6, 0.0, 0.0, 1.0)]
        {
            let mut a = [[0.0; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    a[i][j] = m_h * AINV[i][j] + kh * A[i][j];
                }
                a[i][i] += c + slope * [1.0, 0.5, 0.0][i];
            }
            let b = [1.0, -2.0, 0.5];
            let (x, y) = (solve3_adjugate(a, b).unwrap(), solve3(a, b).unwrap());
            for i in 0..3 {
                assert!((x[i] - y[i]).abs() <= 1e-13 * y.iter().fold(0.0f64, |m, v| m.max(v.abs())), "{x:?} {y:?}");
            }
        }
        // nearly dependent rows: the pivoted solve's answer exactly
        let a = [[1.0, 2.0, 3.0], [2.0, 4.0, 6.0 + 1e-9], [0.0, 1.0, 1.0]];
        assert_eq!(solve3_adjugate(a, [1.0, 2.0, 3.0]), solve3(a, [1.0, 2.0, 3.0]));
        assert!(solve3_adjugate([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]], [1.0, 2.0, 3.0]).is_none());
        assert!(solve3_adjugate([[f64::NAN, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], [1.0; 3]).is_none());
        assert!(solve3_adjugate([[1e200, 0.0, 0.0], [0.0, 1e200, 0.0], [0.0, 0.0, 1e200]], [1.0; 3]).is_some());
    }

    #[test]
    fn stored_inverse_of_the_butcher_matrix() {
        for i in 0..3 {
            for j in 0..3 {
                let p: f64 = (0..3).map(|k| AINV[i][k] * A[k][j]).sum();
                let expect = if i == j { 1.0 } else { 0.0 };
                assert!((p - expect).abs() < 1e-13, "A^-1 A [{i}][{j}] = {p}");
            }
        }
    }
}
