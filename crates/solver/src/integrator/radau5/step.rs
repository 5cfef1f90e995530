//! One accepted step: fitting the step to breakpoints and events, the
//! step-size control of RADAU5 and the handling of failures and contact
//! changes.

use super::coefficients::*;
use super::*;

impl Radau5 {
    /// Step size and end time: the step lands exactly on the next breakpoint
    /// or end time, splitting the remaining interval into equal steps.
    pub(super) fn fit_step(&self, t_end: f64) -> (f64, f64) {
        let h = self.h.min(self.opt.h_max);
        let tiny = 4.0 * f64::EPSILON * self.t.abs().max(1.0);
        let bp = self.asm.next_breakpoint(self.t + tiny).map_or(t_end, |b| b.min(t_end));
        let bp = self.events.pending_time().map_or(bp, |e| e.min(bp));
        let dist = bp - self.t;
        let k = (dist / h * (1.0 - 1e-9)).ceil().max(1.0);
        if k <= 1.0 {
            (dist, bp)
        } else {
            let hs = dist / k;
            (hs, self.t + hs)
        }
    }

    pub(super) fn fail(&mut self, cause: StepFailure, failures: &mut u32, factor: f64) -> Result<(), SolverError> {
        *failures += 1;
        self.stats.failed_attempts += 1;
        self.h *= factor;
        self.reject = true;
        if !self.jac_fresh {
            self.need_jac = true;
        }
        if *failures >= self.opt.max_failures || self.h < self.opt.h_min {
            // report what went wrong, not that the step size ran out
            return Err(SolverError::StepFailed { time: self.t, h: self.h, attempts: *failures, cause });
        }
        Ok(())
    }

    /// Advances by one accepted step.
    pub(super) fn step(&mut self, t_end: f64) -> Result<(), SolverError> {
        let mut failures = 0u32;
        loop {
            let (h, t_new) = self.fit_step(t_end);
            self.t_new = t_new;
            if self.need_jac {
                self.evaluate_jacobian();
            }
            // (NaN after a new Jacobian: always refactorise)
            let same_h = (h - self.fact_h).abs() <= FACT_RTOL * h;
            if !same_h {
                if let Err(e) = self.factorize(h) {
                    if self.jac_fresh {
                        self.fail(StepFailure::Linalg(e), &mut failures, 0.5)?;
                    } else {
                        self.need_jac = true;
                        failures += 1;
                    }
                    continue;
                }
            }
            self.set_scales(h);
            self.starting_values(h);
            let iterations = match self.newton(h) {
                Ok(Newton::Converged { iterations }) => iterations,
                Ok(Newton::Retry { factor, cause }) => {
                    self.fail(cause, &mut failures, factor)?;
                    continue;
                }
                Err(e) => {
                    self.fail(StepFailure::Linalg(e), &mut failures, 0.5)?;
                    continue;
                }
            };
            let err = match self.error_estimate(h) {
                Ok(e) => e,
                Err(e) => {
                    self.fail(StepFailure::Linalg(e), &mut failures, 0.5)?;
                    continue;
                }
            };
            // step-size proposal (RADAU5)
            let nit = self.opt.max_newton as f64;
            let fac = SAFE.min(SAFE * (1.0 + 2.0 * nit) / (iterations as f64 + 2.0 * nit));
            let quot = FACR.max(FACL.min(err.powf(0.25) / fac));
            let h_new = h / quot;
            if err < 1.0 && !self.events.is_empty() && self.locate_event(h)? {
                continue;
            }
            if err < 1.0 {
                return self.accept_step(h, Proposal { quot, h_new, err });
            }
            self.reject_step(h, h_new, err, &mut failures)?;
        }
    }

    /// Locates a contact's change of mode inside the trial step of size
    /// `h`: changes one due now at the start (then the step is tried again)
    /// or makes it the step's end; whether one was found.
    fn locate_event(&mut self, h: f64) -> Result<bool, SolverError> {
        let asm = Arc::clone(&self.asm);
        let start = State { t: self.t, q: &self.q, v: &self.v };
        let trial = Trial { start, h, zq: &self.zq, zv: &self.zv };
        let located = self.events.locate(&asm, &mut self.ws, &trial);
        if let Some((te, contacts)) = located {
            self.stats.event_retries += 1;
            if te - self.t <= 1e-9 * h {
                // the change is due now: at the start of the step
                let at = State { t: self.t, q: &self.q, v: &self.v };
                let (n, so_far) = self.events.change_now(&asm, &mut self.ws, at, contacts, &mut self.energy);
                self.after_contact_change(n);
                // each contact changes at most twice at one time
                if so_far > 2 * asm.contact_count() {
                    return Err(SolverError::StepFailed {
                        time: self.t,
                        h,
                        attempts: so_far as u32,
                        cause: StepFailure::Chattering,
                    });
                }
            } else {
                self.events.set_pending(te, contacts);
            }
            return Ok(true);
        }
        Ok(false)
    }

    /// Accepts the step of size `h` that passed the error test, with the
    /// step-size proposal, and proposes the next.
    fn accept_step(&mut self, h: f64, proposal: Proposal) -> Result<(), SolverError> {
        let Proposal { mut quot, mut h_new, err } = proposal;
        if !self.first {
            let facgus = (self.h_acc / h) * (err * err / self.err_acc).powf(0.25) / SAFE;
            let facgus = FACR.max(FACL.min(facgus));
            quot = quot.max(facgus);
            h_new = h / quot;
        }
        self.h_acc = h;
        self.err_acc = err.max(1e-2);
        self.accept(h)?;
        let asm = Arc::clone(&self.asm);
        let changed = if self.events.is_empty() {
            0
        } else {
            let at = State { t: self.t, q: &self.q, v: &self.v };
            self.events.apply_pending(&asm, &mut self.ws, at, &mut self.energy)
        };
        if changed > 0 {
            self.after_contact_change(changed);
            self.jac_fresh = false;
            return Ok(());
        }
        let h_new = h_new.min(self.opt.h_max);
        let h_new = if self.reject { h_new.min(h) } else { h_new };
        self.first = false;
        self.reject = false;
        let qt = h_new / h;
        if self.theta <= self.opt.jacobian_reuse && (QUOT1..=QUOT2).contains(&qt) {
            // keep h and the factorisation
            self.h = h.max(self.h);
        } else {
            self.h = h_new;
            if self.theta > self.opt.jacobian_reuse {
                self.need_jac = true;
            }
        }
        self.jac_fresh = false;
        Ok(())
    }

    /// A step of size `h` rejected by the error test `err`: the next try
    /// at `h_new` (a tenth of `h` at the first step), or the failure.
    fn reject_step(&mut self, h: f64, h_new: f64, err: f64, failures: &mut u32) -> Result<(), SolverError> {
        self.stats.rejected += 1;
        *failures += 1;
        if *failures >= self.opt.max_failures {
            return Err(SolverError::StepFailed {
                time: self.t,
                h,
                attempts: *failures,
                cause: StepFailure::ErrorTest { error: err },
            });
        }
        self.h = if self.first { h * 0.1 } else { h_new };
        self.reject = true;
        if !self.jac_fresh {
            self.need_jac = true;
        }
        if self.h < self.opt.h_min {
            return Err(SolverError::StepFailed {
                time: self.t,
                h: self.h,
                attempts: *failures,
                cause: StepFailure::StepTooSmall { h: self.h, h_min: self.opt.h_min },
            });
        }
        Ok(())
    }

    /// After contacts changed mode at the current state: the start-of-step
    /// residual, the stored energy and the contacts' states are recomputed,
    /// and the next step starts afresh (new Jacobian, no extrapolation across
    /// the change, a step short against a contact's duration).
    pub(super) fn after_contact_change(&mut self, changed: usize) {
        self.stats.contact_events += changed as u64;
        self.update_y0();
        self.energy.record(self.potential0);
        let asm = Arc::clone(&self.asm);
        self.events.record_start(&asm, &mut self.ws, &self.q, &self.v);
        self.need_jac = true;
        self.first = true;
        self.reject = false;
        self.have_cont = false;
        self.h = self.h.min(CONTACT_STEP);
    }
}

/// The step-size controller's proposal after a step's error test: the
/// quotient `h / h_new`, the new size and the scaled error.
#[derive(Clone, Copy)]
struct Proposal {
    quot: f64,
    h_new: f64,
    err: f64,
}
