//! The embedded error estimate of RADAU5, filtered through the real system.

use super::coefficients::*;
use super::*;

impl Radau5 {
    /// Embedded error estimate of RADAU5 (filtered through the real system).
    pub(super) fn error_estimate(&mut self, h: f64) -> Result<f64, LinalgError> {
        crate::isa::run(
            #[inline(always)]
            || self.error_estimate_impl(h),
        )
    }

    /// [`Self::error_estimate`], compiled into each version of [`crate::isa::run`].
    #[inline(always)]
    fn error_estimate_impl(&mut self, h: f64) -> Result<f64, LinalgError> {
        let n = self.n;
        let hee = [DD[0] / h, DD[1] / h, DD[2] / h];
        // F1 = M_big (hee . Z); cont = F1 + F(t_n, y_n)
        // (on slices taken once: through `self`, every store would make the
        // compiler reload every vector's address)
        let ([zq0, zq1, zq2], [zv0, zv1, zv2]) = (&self.zq, &self.zv);
        let (zq0, zq1, zq2, zv0, zv1, zv2) = (&zq0[..n], &zq1[..n], &zq2[..n], &zv0[..n], &zv1[..n], &zv2[..n]);
        let (e1q, e1v, ecq, ecv) = (&mut self.e1q[..n], &mut self.e1v[..n], &mut self.ecq[..n], &mut self.ecv[..n]);
        let (mass, v, y0f) = (&self.mass[..n], &self.v[..n], &self.y0f[..n]);
        for c in 0..n {
            e1q[c] = hee[0] * zq0[c] + hee[1] * zq1[c] + hee[2] * zq2[c];
            e1v[c] = mass[c] * (hee[0] * zv0[c] + hee[1] * zv1[c] + hee[2] * zv2[c]);
            ecq[c] = e1q[c] + v[c];
            ecv[c] = e1v[c] + y0f[c];
        }
        self.ecg.copy_from_slice(&self.y0g);
        let mut err = self.filtered_error(h)?;
        if err >= 1.0 && (self.first || self.reject) {
            // second estimate: f(y_n + err) + F1 (RADAU5); the estimate is in bq, bv, bl
            for c in 0..n {
                self.bq[c] += self.q[c];
                self.bv[c] += self.v[c];
            }
            for e in 0..self.m {
                self.bl[e] += self.lam[e];
            }
            self.asm.residual(&mut self.ws, self.t, &self.bq, &self.bv, &self.bl);
            self.stats.residual_evaluations += 1;
            for c in 0..n {
                self.ecq[c] = self.bv[c] + self.e1q[c];
                self.ecv[c] = self.ws.forces()[c] + self.e1v[c];
            }
            self.ecg.copy_from_slice(self.ws.velocity_constraints());
            err = self.filtered_error(h)?;
        }
        Ok(err)
    }

    /// Solves `E1 e = cont` (condensed; cont in `ecq`, `ecv`, `ecg`) and returns
    /// the weighted RMS norm of the position and velocity parts.
    /// Leaves `e` in `bq`, `bv`, `bl`.
    pub(super) fn filtered_error(&mut self, h: f64) -> Result<f64, LinalgError> {
        let n = self.n;
        let g_r = GAMMA / h;
        super::matrices::mass_damping_product(&self.asm, g_r, &self.jac, &self.ecq, &mut self.emd);
        super::newton::add_into(&mut self.bv[..n], &self.ecv[..n], &self.emd[..n]);
        // velocity constraint rows: G e_q = (G R_q - R_w) / c
        super::matrices::gradient_product(&self.asm, &self.jac, &self.ecq, &mut self.bl);
        for (b, &g) in self.bl.iter_mut().zip(&self.ecg) {
            *b = (*b - g) / g_r;
        }
        self.solve_real_into_bq()?;
        let mut sum = 0.0;
        let rtol = self.rtol;
        let (bq, bv, ecq) = (&self.bq[..n], &mut self.bv[..n], &self.ecq[..n]);
        let (q, v, zq2, zv2) = (&self.q[..n], &self.v[..n], &self.zq[2][..n], &self.zv[2][..n]);
        let (atol_q, atol_v, q_ref) = (&self.atol_q[..n], &self.atol_v[..n], &self.q_ref[..n]);
        for c in 0..n {
            let eq = bq[c];
            let ev = g_r * eq - ecq[c];
            bv[c] = ev;
            let q1 = q[c] + zq2[c];
            let v1 = v[c] + zv2[c];
            let sq = atol_q[c] + rtol * (q[c] - q_ref[c]).abs().max((q1 - q_ref[c]).abs());
            let sv = atol_v[c] + rtol * v[c].abs().max(v1.abs());
            sum += (eq / sq).powi(2) + (ev / sv).powi(2);
        }
        Ok((sum / (2 * n) as f64).sqrt().max(1e-10))
    }
}
