//! Accepting a step: energy quadrature, dense output, the new state and its
//! projection onto the constraints.

use super::coefficients::*;
use super::newton::add_into;
use super::*;

impl Radau5 {
    /// Accepts the step: new state, dense output, projection, energy.
    pub(super) fn accept(&mut self, h: f64) -> Result<(), SolverError> {
        crate::isa::run(
            #[inline(always)]
            || self.accept_impl(h),
        )
    }

    /// [`Self::accept`], compiled into each version of [`crate::isa::run`].
    #[inline(always)]
    fn accept_impl(&mut self, h: f64) -> Result<(), SolverError> {
        let (n, m) = (self.n, self.m);
        // energy quadrature over the stages (weights b = last row of A)
        let mut pw = [crate::assembly::Powers::default(); 3];
        for (i, p) in pw.iter_mut().enumerate() {
            add_into(&mut self.bq, &self.q, &self.zq[i]);
            add_into(&mut self.bv, &self.v, &self.zv[i]);
            add_into(&mut self.bl, &self.lam, &self.zl[i]);
            let ti = self.stage_time(i, h);
            *p = self.asm.powers(&mut self.ws, ti, &self.bq, &self.bv, &self.bl);
            if !self.group_friction.is_empty() {
                self.group_power.iter_mut().for_each(|x| *x = 0.0);
                self.asm.friction_powers_by_group(&mut self.ws, ti, &self.bq, &self.bv, &mut self.group_power);
                let w = h * A[2][i];
                for (e, p) in self.group_friction.iter_mut().zip(&self.group_power) {
                    *e += w * p;
                }
            }
        }
        for (i, p) in pw.iter().enumerate() {
            let w = h * A[2][i];
            self.energy.damping += w * p.damping;
            self.energy.friction += w * p.friction;
            self.energy.applied += w * p.applied;
            self.energy.base += w * p.base;
            self.energy.constraints += w * p.constraints;
            self.energy.contact += w * p.contact;
        }
        // dense output coefficients
        for (z, cont, len) in
            [(&self.zq, &mut self.cont_q, n), (&self.zv, &mut self.cont_v, n), (&self.zl, &mut self.cont_l, m)]
        {
            // (reciprocals: a division costs several multiplications)
            const R_C2M1: f64 = 1.0 / C2M1;
            const R_C1MC2: f64 = 1.0 / C1MC2;
            const R_C1: f64 = 1.0 / C[0];
            const R_C2: f64 = 1.0 / C[1];
            const R_C1M1: f64 = 1.0 / C1M1;
            for j in 0..len {
                let (z1, z2, z3) = (z[0][j], z[1][j], z[2][j]);
                let c1 = (z2 - z3) * R_C2M1;
                let ak = (z1 - z2) * R_C1MC2;
                let acont3 = (ak - z1 * R_C1) * R_C2;
                let c2 = (ak - c1) * R_C1M1;
                cont[0][j] = c1;
                cont[1][j] = c2;
                cont[2][j] = c2 - acont3;
            }
        }
        for (x, z) in [(&mut self.q, &self.zq[2]), (&mut self.v, &self.zv[2]), (&mut self.lam, &self.zl[2])] {
            x.iter_mut().zip(z).for_each(|(x, z)| *x += z);
        }
        self.t_prev = self.t;
        self.t = self.t_new;
        self.h_cont = h;
        self.have_cont = true;
        self.project().map_err(|e| SolverError::StepFailed {
            time: self.t,
            h,
            attempts: 1,
            cause: StepFailure::Linalg(e),
        })?;
        self.stats.steps += 1;
        self.update_y0();
        self.energy.kinetic = self.asm.kinetic_energy(&self.v);
        self.energy.record(self.potential0);
        let asm = Arc::clone(&self.asm);
        self.events.record_start(&asm, &mut self.ws, &self.q, &self.v);
        Ok(())
    }

    /// Projects the accepted state onto `g = 0` and `G v + g_t = 0` with the
    /// current real factorisation (stale gradients are iterated out), and
    /// records the residuals left.
    pub(super) fn project(&mut self) -> Result<(), LinalgError> {
        let tol = self.opt.constraint_tolerance;
        // whether the workspace holds the constraint residuals at (q, v)
        let mut current = false;
        for velocity in [false, true] {
            let mut last = f64::INFINITY;
            for _ in 0..12 {
                // (one evaluation gives both kinds: the velocity pass starts
                // from the position pass's last one when nothing moved since)
                if !current {
                    self.asm.constraint_residuals(&mut self.ws, self.t, &self.q, &self.v);
                    current = true;
                }
                let r = if velocity { self.ws.velocity_constraints() } else { self.ws.constraints() };
                let worst = worst_equation(r).1;
                // converged, or the stale gradients no longer help
                if worst <= tol || worst > 0.5 * last {
                    break;
                }
                last = worst;
                self.bl.copy_from_slice(r);
                self.bl.iter_mut().for_each(|x| *x = -*x);
                self.bv.iter_mut().for_each(|x| *x = 0.0);
                self.solve_real_into_bq()?;
                let target = if velocity { &mut self.v } else { &mut self.q };
                for (x, d) in target.iter_mut().zip(&self.bq) {
                    *x += d;
                }
                current = false;
                self.stats.projections += 1;
            }
        }
        if current {
            self.record_constraint_residuals();
        } else {
            self.track_constraint_residuals();
        }
        Ok(())
    }
}
