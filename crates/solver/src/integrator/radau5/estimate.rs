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
        for c in 0..n {
            self.e1q[c] = hee[0] * self.zq[0][c] + hee[1] * self.zq[1][c] + hee[2] * self.zq[2][c];
            self.e1v[c] = self.mass[c] * (hee[0] * self.zv[0][c] + hee[1] * self.zv[1][c] + hee[2] * self.zv[2][c]);
            self.ecq[c] = self.e1q[c] + self.v[c];
            self.ecv[c] = self.e1v[c] + self.y0f[c];
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
        self.asm.mass_damping_product(g_r, &self.jac, &self.ecq, &mut self.emd);
        for c in 0..n {
            self.bv[c] = self.ecv[c] + self.emd[c];
        }
        // velocity constraint rows: G e_q = (G R_q - R_w) / c
        self.asm.gradient_product(&self.jac, &self.ecq, &mut self.bl);
        for e in 0..self.m {
            self.bl[e] = (self.bl[e] - self.ecg[e]) / g_r;
        }
        self.solve_real_into_bq()?;
        let mut sum = 0.0;
        for c in 0..n {
            let eq = self.bq[c];
            let ev = g_r * eq - self.ecq[c];
            self.bv[c] = ev;
            let q1 = self.q[c] + self.zq[2][c];
            let v1 = self.v[c] + self.zv[2][c];
            let sq = self.atol_q[c] + self.rtol * (self.q[c] - self.q_ref[c]).abs().max((q1 - self.q_ref[c]).abs());
            let sv = self.atol_v[c] + self.rtol * self.v[c].abs().max(v1.abs());
            sum += (eq / sq).powi(2) + (ev / sv).powi(2);
        }
        Ok((sum / (2 * n) as f64).sqrt().max(1e-10))
    }
}
