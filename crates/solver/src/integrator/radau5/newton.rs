//! The simplified Newton iteration on the transformed stage equations, its
//! starting values and error scales, and the local friction solve inside it.

use super::coefficients::*;
use super::*;

impl Radau5 {
    /// Error scales of a step of size `h` from the current state: positions
    /// and velocities (error test and Newton norm) and multipliers (Newton
    /// norm only): `(rtol (|lambda_e| + max |lambda|) + m_ref s_v) / h` (`s_v` the
    /// velocity scale of the equation's coordinate),
    /// relative to the largest multiplier so that a component passing through
    /// zero is not held to an absolute tolerance; the velocity-equivalent
    /// floor only matters while every multiplier is near zero.
    pub(super) fn set_scales(&mut self, h: f64) {
        // (stored as reciprocals: the Newton norm multiplies, once per
        // iteration and unknown, instead of dividing; on slices: through the
        // vectors, every store would make the compiler reload their addresses)
        let (n, rtol) = (self.n, self.rtol);
        let (rscal_q, rscal_v) = (&mut self.rscal_q[..n], &mut self.rscal_v[..n]);
        let (q, v, q_ref, atol_q, atol_v) =
            (&self.q[..n], &self.v[..n], &self.q_ref[..n], &self.atol_q[..n], &self.atol_v[..n]);
        for c in 0..n {
            rscal_q[c] = 1.0 / (atol_q[c] + rtol * (q[c] - q_ref[c]).abs());
            rscal_v[c] = 1.0 / (atol_v[c] + rtol * v[c].abs());
        }
        let lam_max = self.lam.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let per_eq = self.asm.layout.eq_coord.iter().zip(&self.asm.eq_mref).zip(&self.lam);
        for (r, ((&c, &mref), &lam)) in self.rscal_l.iter_mut().zip(per_eq) {
            let floor = mref * (atol_v[c as usize] + rtol * v[c as usize].abs());
            *r = h / (rtol * (lam.abs() + lam_max) + floor);
        }
    }

    /// Extrapolates the last collocation polynomial to the new stages (or
    /// starts from zero), and derives the position stages.
    pub(super) fn starting_values(&mut self, h: f64) {
        if self.first || !self.have_cont {
            for i in 0..3 {
                self.zv[i].iter_mut().for_each(|x| *x = 0.0);
                self.zl[i].iter_mut().for_each(|x| *x = 0.0);
            }
        } else {
            let c3q = h / self.h_cont;
            let cq = [C[0] * c3q, C[1] * c3q, c3q];
            let extrapolate = |[c0, c1, c2]: &Stages, [z0, z1, z2]: &mut Stages| {
                // (on slices: through the vectors, every store would make the
                // compiler reload their addresses)
                let len = c0.len();
                let (c0, c1, c2) = (&c0[..len], &c1[..len], &c2[..len]);
                let z = [&mut z0[..len], &mut z1[..len], &mut z2[..len]];
                for j in 0..len {
                    let (a1, a2, a3) = (c0[j], c1[j], c2[j]);
                    for i in 0..3 {
                        z[i][j] = cq[i] * (a1 + (cq[i] - C2M1) * (a2 + (cq[i] - C1M1) * a3));
                    }
                }
            };
            extrapolate(&self.cont_v, &mut self.zv);
            extrapolate(&self.cont_l, &mut self.zl);
        }
        transform(&TI, &self.zv, &mut self.wv);
        transform(&TI, &self.zl, &mut self.wl);
        self.derive_zq(h);
    }

    /// `Zq_i = h sum_j a_ij (v_n + Zv_j)`.
    pub(super) fn derive_zq(&mut self, h: f64) {
        let n = self.n;
        let [q0, q1, q2] = &mut self.zq;
        let (q0, q1, q2) = (&mut q0[..n], &mut q1[..n], &mut q2[..n]);
        let (v, v0, v1, v2) = (&self.v[..n], &self.zv[0][..n], &self.zv[1][..n], &self.zv[2][..n]);
        for j in 0..n {
            let (z0, z1, z2) = (v[j] + v0[j], v[j] + v1[j], v[j] + v2[j]);
            q0[j] = h * (A[0][0] * z0 + A[0][1] * z1 + A[0][2] * z2);
            q1[j] = h * (A[1][0] * z0 + A[1][1] * z1 + A[1][2] * z2);
            q2[j] = h * (A[2][0] * z0 + A[2][1] * z1 + A[2][2] * z2);
        }
    }

    /// Time of stage `i` (the last stage is exactly the step's end).
    pub(super) fn stage_time(&self, i: usize, h: f64) -> f64 {
        if i == 2 {
            self.t_new
        } else {
            self.t + C[i] * h
        }
    }

    /// Evaluates the residual at the three stages.
    pub(super) fn stage_residuals(&mut self, h: f64, record_sliders: bool) -> bool {
        let mut finite = true;
        for i in 0..3 {
            add_into(&mut self.bq, &self.q, &self.zq[i]);
            add_into(&mut self.bv, &self.v, &self.zv[i]);
            add_into(&mut self.bl, &self.lam, &self.zl[i]);
            let ti = self.stage_time(i, h);
            self.asm.residual(&mut self.ws, ti, &self.bq, &self.bv, &self.bl);
            if record_sliders {
                self.local.record_stage(&self.asm, &self.ws, i);
            }
            // (swapped, not copied: the next evaluation overwrites them)
            self.ws.swap_results(&mut self.fv[i], &mut self.fg[i]);
            // (no early exit, so that the test vectorises)
            finite &= self.fv[i][..self.n].iter().chain(&self.fg[i]).fold(true, |ok, x| ok & x.is_finite());
        }
        self.stats.residual_evaluations += 3;
        finite
    }

    /// Simplified Newton iteration on the transformed stage equations.
    pub(super) fn newton(&mut self, h: f64) -> Result<Newton, LinalgError> {
        crate::isa::run(
            #[inline(always)]
            || self.newton_impl(h),
        )
    }

    /// [`Self::newton`], compiled into each version of [`crate::isa::run`]
    /// (its loops over the unknowns).
    #[inline(always)]
    fn newton_impl(&mut self, h: f64) -> Result<Newton, LinalgError> {
        let (n, m) = (self.n, self.m);
        let nit = self.opt.max_newton;
        let g_r = GAMMA / h;
        let c_c = Complex64::new(ALPHA / h, BETA / h);
        self.faccon = self.faccon.max(UROUND).powf(0.8);
        self.theta = self.opt.jacobian_reuse.abs();
        let mut dynold = 0.0f64;
        let mut thqold = 0.0f64;
        let mut newt = 0u32;
        loop {
            if newt >= nit {
                return Ok(Newton::Retry { factor: 0.5, cause: StepFailure::Newton { rate: self.theta } });
            }
            let record = !self.local.is_empty();
            if !self.stage_residuals(h, record) || (self.solve_frictions_locally(h) && !self.stage_residuals(h, false))
            {
                return Ok(Newton::Retry { factor: 0.5, cause: StepFailure::NonFinite });
            }
            // transformed right-hand sides: force rows, then the velocity
            // constraint rows, `G dq = -R_w / c`
            let lay = &self.asm.layout;
            // (the loops work on slices taken once: through `self`, every
            // store would make the compiler reload every vector's address)
            let ([fv0, fv1, fv2], [wv0, wv1, wv2]) = (&self.fv, &self.wv);
            let (fv0, fv1, fv2, wv0, wv1, wv2) = (&fv0[..n], &fv1[..n], &fv2[..n], &wv0[..n], &wv1[..n], &wv2[..n]);
            let (mass, unknown) = (&self.mass[..n], &lay.unknown_of_coord[..n]);
            let (rhs_r, rhs_c) = (&mut self.rhs_r[..], &mut self.rhs_c[..]);
            for c in 0..n {
                let r = tmul(&TI, [fv0[c], fv1[c], fv2[c]]);
                let (w, mc, u) = ([wv0[c], wv1[c], wv2[c]], mass[c], unknown[c] as usize);
                rhs_r[u] = r[0] - g_r * mc * w[0];
                rhs_c[u] = Complex64::new(
                    r[1] - mc * (c_c.re * w[1] - c_c.im * w[2]),
                    r[2] - mc * (c_c.im * w[1] + c_c.re * w[2]),
                );
            }
            let inv_c = c_c.inv();
            let [fg0, fg1, fg2] = &self.fg;
            let (gscale_r, gscale_c) = (self.gscale_r, self.gscale_c);
            let eqs = fg0[..m].iter().zip(&fg1[..m]).zip(&fg2[..m]);
            for (((&g0, &g1), &g2), (&u, &s)) in eqs.zip(lay.unknown_of_eq[..m].iter().zip(&self.asm.eq_mref[..m])) {
                let r = tmul(&TI, [g0, g1, g2]);
                let u = u as usize;
                rhs_r[u] = -gscale_r * s * r[0] / g_r;
                rhs_c[u] = -Complex64::new(r[1], r[2]) * inv_c * (gscale_c * s);
            }
            let sym = self.asm.block_structure();
            self.real.solve(sym, &mut self.faer, &mut self.rhs_r)?;
            self.cplx.solve(sym, &mut self.faer, &mut self.rhs_c)?;
            self.stats.linear_solves += 2;
            newt += 1;
            self.stats.newton_iterations += 1;
            // increments of W and the Newton norm
            let mut sum = 0.0;
            let (rhs_r, rhs_c) = (&self.rhs_r[..], &self.rhs_c[..]);
            let [wv0, wv1, wv2] = &mut self.wv;
            let coords = wv0[..n].iter_mut().zip(&mut wv1[..n]).zip(&mut wv2[..n]);
            let scales = self.rscal_q[..n].iter().zip(&self.rscal_v[..n]);
            for (((w0, w1), w2), ((&rq, &rv), &u)) in coords.zip(scales.zip(&lay.unknown_of_coord[..n])) {
                let u = u as usize;
                let d1 = rhs_r[u];
                let d23 = rhs_c[u];
                let dv23 = c_c * d23;
                let dv1 = g_r * d1;
                sum += (d1 * rq).powi(2) + (d23.re * rq).powi(2) + (d23.im * rq).powi(2);
                sum += (dv1 * rv).powi(2) + (dv23.re * rv).powi(2) + (dv23.im * rv).powi(2);
                *w0 += dv1;
                *w1 += dv23.re;
                *w2 += dv23.im;
            }
            // multipliers (index-2 variables, whose errors are O(1/h) larger;
            // Hairer and Wanner IV.8 and VII.4) with the scales of `set_scales`
            let [wl0, wl1, wl2] = &mut self.wl;
            let eqs = wl0[..m].iter_mut().zip(&mut wl1[..m]).zip(&mut wl2[..m]);
            let per_eq = lay.unknown_of_eq[..m].iter().zip(&self.asm.eq_mref[..m]).zip(&self.rscal_l[..m]);
            for (((w0, w1), w2), ((&u, &s), &rl)) in eqs.zip(per_eq) {
                let u = u as usize;
                let d1 = gscale_r * s * rhs_r[u];
                let d23 = rhs_c[u] * (gscale_c * s);
                *w0 += d1;
                *w1 += d23.re;
                *w2 += d23.im;
                sum += (d1 * rl).powi(2) + (d23.re * rl).powi(2) + (d23.im * rl).powi(2);
            }
            let dyno = (sum / (6 * n + 3 * m) as f64).sqrt();
            if newt > 1 && newt < nit {
                let thq = dyno / dynold;
                self.theta = if newt == 2 { thq } else { (thq * thqold).sqrt() };
                thqold = thq;
                if self.theta < 0.99 {
                    self.faccon = self.theta / (1.0 - self.theta);
                    let dyth = self.faccon * dyno * self.theta.powi((nit - 1 - newt) as i32) / self.fnewt;
                    if dyth >= 1.0 {
                        let qnewt = dyth.clamp(1e-4, 20.0);
                        let factor = 0.8 * qnewt.powf(-1.0 / (4.0 + nit as f64 - 1.0 - newt as f64));
                        return Ok(Newton::Retry { factor, cause: StepFailure::Newton { rate: self.theta } });
                    }
                } else {
                    return Ok(Newton::Retry { factor: 0.5, cause: StepFailure::Newton { rate: self.theta } });
                }
            }
            dynold = dyno.max(UROUND);
            transform(&T, &self.wv, &mut self.zv);
            transform(&T, &self.wl, &mut self.zl);
            self.derive_zq(h);
            if self.faccon * dyno <= self.fnewt {
                return Ok(Newton::Converged { iterations: newt });
            }
        }
    }

    /// Local solve of the sliders ([`LocalFriction::solve`]); returns
    /// whether the iterate changed.
    pub(super) fn solve_frictions_locally(&mut self, h: f64) -> bool {
        if self.local.is_empty() || !self.local.solve(h, &self.mass, &self.jac, &self.fv, &mut self.zv) {
            return false;
        }
        transform(&TI, &self.zv, &mut self.wv);
        self.derive_zq(h);
        true
    }
}

/// `out = a + b` elementwise.
#[inline]
pub(super) fn add_into(out: &mut [f64], a: &[f64], b: &[f64]) {
    for ((o, &x), &y) in out.iter_mut().zip(a).zip(b) {
        *o = x + y;
    }
}

/// `y = M x` for a 3x3 matrix and a 3-vector.
#[inline]
pub(super) fn tmul(mat: &[[f64; 3]; 3], x: [f64; 3]) -> [f64; 3] {
    [
        mat[0][0] * x[0] + mat[0][1] * x[1] + mat[0][2] * x[2],
        mat[1][0] * x[0] + mat[1][1] * x[1] + mat[1][2] * x[2],
        mat[2][0] * x[0] + mat[2][1] * x[1] + mat[2][2] * x[2],
    ]
}

/// Applies a 3x3 matrix across three stage vectors.
pub(super) fn transform(mat: &[[f64; 3]; 3], src: &Stages, dst: &mut Stages) {
    let n = src[0].len();
    let (s0, s1, s2) = (&src[0][..n], &src[1][..n], &src[2][..n]);
    let [d0, d1, d2] = dst;
    let (d0, d1, d2) = (&mut d0[..n], &mut d1[..n], &mut d2[..n]);
    for j in 0..n {
        let y = tmul(mat, [s0[j], s1[j], s2[j]]);
        d0[j] = y[0];
        d1[j] = y[1];
        d2[j] = y[2];
    }
}
