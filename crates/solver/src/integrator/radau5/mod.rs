//! Radau IIA, three stages, order 5, for constrained mechanical systems.
//!
//! Coefficients, the transformation of the simplified Newton iteration to one
//! real and one complex system, the starting values, the error estimate and
//! the step-size controller are those of RADAU5:
//! E. Hairer and G. Wanner, *Solving Ordinary Differential Equations II:
//! Stiff and Differential-Algebraic Problems*, 2nd ed., Springer 1996,
//! Section IV.8; the transformation matrices `T`, `T^-1` are the ones printed
//! in the RADAU5 code (verified in the tests: `T^-1 A^-1 T` is block diagonal).
//!
//! Formulation: the stages satisfy the constraints at velocity level
//! (`G(q) v + g_t = 0`, an index-2 system in which Radau IIA keeps the full
//! order 5 for positions and velocities), and every accepted state is
//! projected onto `g(q, t) = 0` (and, if needed, back onto `G v + g_t = 0`),
//! so both hold to `constraint_tolerance` at every step. This is the
//! stabilised index-2 formulation of Gear, Gupta and Leimkuhler with its
//! position correction applied as a projection after the step instead of
//! inside it (coordinate projection: E. Eich, "Convergence results for a
//! coordinate projection method applied to mechanical systems with algebraic
//! constraints", SIAM J. Numer. Anal. 30 (1993) 1467-1482; Hairer and Wanner,
//! Section VII.2). Two alternatives were measured on the reference pendulum
//! (`tests/pendulum_period.rs`) and rejected: the index-3 form (`g = 0` at the
//! stages) loses velocity order (order 3, Hairer and Wanner, Section VII.4):
//! energy drift 5e-5 at rtol 1e-6; the acceleration-level form needs
//! `M^-1` in its constraint, and with a point-like bob (inertia 1e-6) Newton
//! forced 1000 times more steps.
//!
//! Adaptations to the mechanical structure:
//! - the stage unknowns are the velocity increments and multipliers; the
//!   position increments follow exactly from `Zq = h A (1 v_n + Zv)`, and each
//!   transformed Newton system reduces to `[c^2 M + c D + K, G^T; G, 0]` with
//!   `c` the real eigenvalue `gamma/h` or the complex one `(alpha + i beta)/h`
//!   (the velocity-constraint row `(c G + d(G v)/dq) dq` is taken as `c G dq`:
//!   the left-out term is of relative size `omega h` for a body turning at
//!   `omega`, so Newton stays robust whatever the masses and inertias);
//! - the constraint rows are scaled by `|c|^2 m_ref` (Bottasso, Bauchau and
//!   Cardona 2007, "Time-step-size-independent conditioning ... of index three
//!   differential algebraic equations", SIAM J. Sci. Comput. 29);
//! - positions and velocities enter the error test, multipliers do not;
//! - no step crosses a breakpoint of an excitation or driver.
//!
//! Sliding friction on a line is solved locally at every Newton iteration,
//! with the regularisation zone's slope in the iteration matrix
//! (`super::local_friction`).
//!
//! The factorisation is reused while the step size is unchanged to within
//! `FACT_RTOL` (steps fitted between breakpoints differ in the last bits),
//! and a new Jacobian is always factorised.
//!
//! Parts: [`coefficients`] (the method's constants), `newton` (starting
//! values, error scales, the simplified Newton iteration and the local
//! friction solve), `estimate` (the embedded error estimate), `accept` (energy
//! quadrature, dense output, new state and projection) and `step` (step-size
//! control, failures, contact events), `matrices` (the iteration matrices
//! formed from the assembly's `K`, `D` and `G`, and the error estimate's
//! products with them); this file holds the state, its set-up and the linear
//! algebra.

use std::sync::Arc;
use std::time::Instant;

use super::events::{Events, State, Trial};
use super::local_friction::LocalFriction;
use super::{EnergyBalance, IntegratorOptions, JacobianMode, Observer, Stats, StepView};
use crate::assembly::{Assembly, JacobianValues, Workspace};
use crate::error::{BuildError, LinalgError, SolverError, StepFailure};
use crate::fd;
use crate::linalg::scalar::Complex64;
use crate::linalg::{FaerCache, KktSolver};

mod accept;
pub mod coefficients;
mod estimate;
mod matrices;
mod newton;
mod resume;
mod step;

use coefficients::*;
pub use coefficients::{A, ALPHA, BETA, C, GAMMA, T, TI};
pub use matrices::{form_complex, form_real};

/// Dense output of the last step: `y(t) = c0 + s (c1 + (s - c2m1)(c2 + (s - c1m1) c3))`
/// with `s = (t - t1)/h`.
pub(crate) struct DenseRef<'a> {
    t1: f64,
    h: f64,
    q: [&'a [f64]; 4],
    v: [&'a [f64]; 4],
    l: [&'a [f64]; 4],
}

impl DenseRef<'_> {
    pub(crate) fn eval(&self, t: f64, q: &mut [f64], v: &mut [f64], l: &mut [f64]) {
        let s = if self.h > 0.0 { (t - self.t1) / self.h } else { 0.0 };
        let poly = |c: &[&[f64]; 4], out: &mut [f64]| {
            for (i, o) in out.iter_mut().enumerate() {
                *o = c[0][i] + s * (c[1][i] + (s - C2M1) * (c[2][i] + (s - C1M1) * c[3][i]));
            }
        };
        poly(&self.q, q);
        poly(&self.v, v);
        poly(&self.l, l);
    }
}

/// Three stage vectors.
type Stages = [Vec<f64>; 3];

fn stages(len: usize) -> Stages {
    [vec![0.0; len], vec![0.0; len], vec![0.0; len]]
}

/// Outcome of one Newton solve.
enum Newton {
    Converged {
        iterations: u32,
    },
    /// Reject the attempt; retry with `h * factor`.
    Retry {
        factor: f64,
        cause: StepFailure,
    },
}

/// The integrator and the state it advances.
pub struct Radau5 {
    asm: Arc<Assembly>,
    opt: IntegratorOptions,
    ws: Workspace,
    n: usize,
    m: usize,
    // accepted state
    t: f64,
    q: Vec<f64>,
    v: Vec<f64>,
    lam: Vec<f64>,
    q_ref: Vec<f64>,
    /// F(t_n, y_n) and the velocity constraints `G v + g_t` at `(q_n, v_n, t_n)`: the
    /// start-of-step residual of the error estimate (swapped in from the
    /// workspace, so `y0f` has the workspace's length `n + 1`; its last
    /// entry, the sink of locked coordinates, is not used).
    y0f: Vec<f64>,
    y0g: Vec<f64>,
    // stages
    zq: Stages,
    zv: Stages,
    zl: Stages,
    wv: Stages,
    wl: Stages,
    /// Stage forces and velocity constraints of the last stage residuals
    /// (swapped in from the workspace: each `fv[i]` has its length `n + 1`,
    /// the last entry unused).
    fv: Stages,
    fg: Stages,
    // dense output (c1..c3; c0 is the state)
    cont_q: Stages,
    cont_v: Stages,
    cont_l: Stages,
    h_cont: f64,
    t_prev: f64,
    have_cont: bool,
    // Jacobian and factorisations
    jac: JacobianValues,
    need_jac: bool,
    jac_fresh: bool,
    real: KktSolver<f64>,
    cplx: KktSolver<Complex64>,
    faer: FaerCache,
    fact_h: f64,
    gscale_r: f64,
    gscale_c: f64,
    /// The factorisation before the current one, of the same Jacobian
    /// (`spare.h` NaN once the Jacobian changes).
    spare: Option<Box<Spare>>,
    // scratch
    bq: Vec<f64>,
    bv: Vec<f64>,
    bl: Vec<f64>,
    rhs_r: Vec<f64>,
    rhs_c: Vec<Complex64>,
    /// scratch for the error estimate: F1 (q, v parts), cont (q, v, g), (cM + D) cont_q
    e1q: Vec<f64>,
    e1v: Vec<f64>,
    ecq: Vec<f64>,
    ecv: Vec<f64>,
    ecg: Vec<f64>,
    emd: Vec<f64>,
    mass: Vec<f64>,
    colouring: Option<fd::Colouring>,
    /// end of the step being attempted (exactly the breakpoint when it lands on one)
    t_new: f64,
    /// Reciprocal error scales of the Newton norm ([`Self::set_scales`]).
    rscal_q: Vec<f64>,
    rscal_v: Vec<f64>,
    rscal_l: Vec<f64>,
    atol_q: Vec<f64>,
    atol_v: Vec<f64>,
    rtol: f64,
    fnewt: f64,
    // control
    h: f64,
    h_acc: f64,
    err_acc: f64,
    theta: f64,
    faccon: f64,
    first: bool,
    reject: bool,
    stats: Stats,
    energy: EnergyBalance,
    /// The energy friction dissipated so far in each group of bodies
    /// ([`crate::System::set_group`]) \[J\], and scratch for one stage's
    /// powers.
    group_friction: Vec<f64>,
    group_power: Vec<f64>,
    potential0: f64,
    /// Largest residuals over the run by kind (position and angle,
    /// velocity and angular velocity).
    max_residual: ConstraintResiduals,
    /// The sliders solved locally at every Newton iteration.
    local: LocalFriction,
    /// Per friction element, whether it is solved locally (and enters the
    /// iteration matrix with its zone slope).
    zone: Vec<bool>,
    /// Contact onsets and releases ([`super::events`]).
    events: Events,
    /// When the wall-clock limit's count started: the start of
    /// [`Radau5::run`], or the first [`Radau5::advance`].
    started: Option<Instant>,
}

impl Radau5 {
    /// Prepares a run from the system's initial state: projects it onto the
    /// constraints (refusing positions off by more than
    /// `initial_tolerance`) and computes consistent multipliers.
    pub fn new(asm: Arc<Assembly>, opt: IntegratorOptions) -> Result<Self, SolverError> {
        opt.validate()?;
        let (n, m) = (asm.coordinates(), asm.equations());
        let (q0, v0) = asm.initial_state();
        let sym = asm.block_structure();
        let ws = asm.workspace();
        let jac = asm.jacobian_values();
        // RADAU5's conversion of the user tolerances (Hairer & Wanner, IV.8).
        let rtol = 0.1 * opt.rtol.powf(2.0 / 3.0);
        let conv = rtol / opt.rtol;
        let mut atol_q = vec![0.0; n];
        let mut atol_v = vec![0.0; n];
        for c in 0..n {
            let rotational = asm.layout.coord_body[c].1 == 2;
            let scale = conv * asm.coord_tolerance_scale[c];
            atol_q[c] = scale * if rotational { opt.atol_rotation } else { opt.atol_translation };
            atol_v[c] = scale * if rotational { opt.atol_angular_velocity } else { opt.atol_velocity };
        }
        let fnewt = (10.0 * UROUND / rtol)
            .max(opt.newton_tolerance.unwrap_or_else(|| 0.03f64.min(rtol.powf(1.0 / (2.0 / 3.0) - 1.0))));
        let local = LocalFriction::new(&asm, opt.local_friction && opt.jacobian == JacobianMode::Analytic);
        let zone = local.zone_mask(&asm);
        let mut s = Self {
            real: KktSolver::new(sym, opt.linear_solver),
            cplx: KktSolver::new(sym, opt.linear_solver),
            faer: FaerCache::default(),
            t: 0.0,
            q_ref: q0.clone(),
            q: q0,
            v: v0,
            lam: vec![0.0; m],
            // (as long as the workspace's forces, which are swapped in)
            y0f: vec![0.0; asm.workspace_forces_len()],
            y0g: vec![0.0; m],
            zq: stages(n),
            zv: stages(n),
            zl: stages(m),
            wv: stages(n),
            wl: stages(m),
            // (as long as the workspace's forces, which are swapped in)
            fv: stages(asm.workspace_forces_len()),
            fg: stages(m),
            cont_q: stages(n),
            cont_v: stages(n),
            cont_l: stages(m),
            h_cont: 0.0,
            t_prev: 0.0,
            have_cont: false,
            jac,
            need_jac: true,
            jac_fresh: false,
            fact_h: f64::NAN,
            spare: None,
            gscale_r: 0.0,
            gscale_c: 0.0,
            bq: vec![0.0; n],
            bv: vec![0.0; n],
            bl: vec![0.0; m],
            rhs_r: vec![0.0; n + m],
            rhs_c: vec![Complex64::new(0.0, 0.0); n + m],
            e1q: vec![0.0; n],
            e1v: vec![0.0; n],
            ecq: vec![0.0; n],
            ecv: vec![0.0; n],
            ecg: vec![0.0; m],
            emd: vec![0.0; n],
            mass: asm.coordinate_masses().to_vec(),

            colouring: None,
            t_new: 0.0,
            rscal_q: vec![1.0; n],
            rscal_v: vec![1.0; n],
            rscal_l: vec![1.0; m],
            atol_q,
            atol_v,
            rtol,
            fnewt,
            h: opt.h_initial,
            h_acc: 0.0,
            err_acc: 0.0,
            theta: 0.0,
            faccon: 1.0,
            first: true,
            reject: false,
            stats: Stats::default(),
            energy: EnergyBalance::default(),
            group_friction: vec![0.0; asm.group_count()],
            group_power: vec![0.0; asm.group_count()],
            potential0: 0.0,
            max_residual: ConstraintResiduals::default(),
            local,
            zone,
            events: Events::new(&asm),
            started: None,
            ws,
            n,
            m,
            opt,
            asm,
        };
        s.initialise()?;
        Ok(s)
    }

    /// Current time \[s\].
    pub fn time(&self) -> f64 {
        self.t
    }

    /// Current positions.
    pub fn positions(&self) -> &[f64] {
        &self.q
    }

    /// Current velocities.
    pub fn velocities(&self) -> &[f64] {
        &self.v
    }

    /// Current constraint multipliers.
    pub fn multipliers(&self) -> &[f64] {
        &self.lam
    }

    /// Counters so far.
    pub fn stats(&self) -> Stats {
        let mut s = self.stats;
        s.faer_fallbacks = self.real.fallbacks + self.cplx.fallbacks;
        if let Some(sp) = &self.spare {
            s.faer_fallbacks += sp.real.fallbacks + sp.cplx.fallbacks;
        }
        s
    }

    /// Energy balance so far.
    pub fn energy(&self) -> &EnergyBalance {
        &self.energy
    }

    /// The energy friction dissipated so far in each group of bodies
    /// ([`crate::System::set_group`]) \[J\], by the same quadrature as
    /// [`EnergyBalance::friction`] (whose sum they are, to round-off, when
    /// every friction element is in a group).
    pub fn group_friction_energy(&self) -> &[f64] {
        &self.group_friction
    }

    /// Largest |g| and |G v + g_t| over all accepted states so far, every
    /// equation together [m or rad; m/s or rad/s].
    pub fn max_constraint_residuals(&self) -> (f64, f64) {
        let r = &self.max_residual;
        (r.position.max(r.angle), r.velocity.max(r.angular_velocity))
    }

    /// Largest residuals over all accepted states so far, by kind, each in
    /// its unit.
    pub fn constraint_residuals(&self) -> ConstraintResiduals {
        self.max_residual
    }

    /// The compiled system.
    pub fn assembly(&self) -> &Arc<Assembly> {
        &self.asm
    }

    /// Integrates to `t_end`, calling `observer` after every accepted step
    /// ([`Radau5::advance`] in a loop; the wall-clock limit counts from
    /// this call). Returns `Ok(false)` if the observer stopped the run
    /// early.
    pub fn run(&mut self, t_end: f64, observer: &mut dyn Observer) -> Result<bool, SolverError> {
        self.started = Some(Instant::now());
        while let Some(mut view) = self.advance(t_end)? {
            if !observer.step(&mut view) {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// Advances by one accepted step towards `t_end`: the caller drives the
    /// integrator (pull-style, as diffsol's `step`), between steps free to
    /// read the state, stop, or go on to another end time. Returns the
    /// step's view with its dense output and its contact events, or `None`
    /// once the integrator has reached `t_end`. The step and wall-clock
    /// limits hold as in [`Radau5::run`] (the clock counts from the first
    /// call, or from the last `run`).
    ///
    /// ```
    /// use std::sync::Arc;
    /// use quakejoint_solver::*;
    ///
    /// // 1 kg on a 1 N/m spring along x, released from 1 m: half a period
    /// // later it is at -1 m
    /// let mut sys = System::new();
    /// let body = sys.add_body(Body::new("mass", 1.0, 1.0, [1.0, 0.0, 0.0]).only(&[Coord::X]));
    /// let spring = CoordinateSpring { body, coord: Coord::X, stiffness: 1.0, damping: 0.0, rest: 0.0 };
    /// sys.add_force(ForceElement::CoordinateSpring(spring));
    /// let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
    /// let mut sim = Radau5::new(asm, IntegratorOptions::default()).unwrap();
    /// let half = std::f64::consts::PI;
    /// let (mut steps, mut end) = (0, (0.0, 0.0));
    /// while let Some(step) = sim.advance(half).unwrap() {
    ///     steps += 1;
    ///     end = (step.t, step.q[0]);
    /// }
    /// assert!(steps > 5 && (end.0 - half).abs() < 1e-12 && (end.1 + 1.0).abs() < 1e-4, "{steps} {end:?}");
    /// ```
    pub fn advance(&mut self, t_end: f64) -> Result<Option<StepView<'_>>, SolverError> {
        if t_end < self.t {
            return Err(SolverError::EndBeforeStart { t_end, t: self.t });
        }
        // (the previous step's events were handed out with it)
        self.events.last.clear();
        if self.t >= t_end {
            return Ok(None);
        }
        if self.stats.steps + self.stats.rejected + self.stats.failed_attempts >= self.opt.max_steps {
            return Err(SolverError::StepLimit { limit: self.opt.max_steps, time: self.t });
        }
        let started = *self.started.get_or_insert_with(Instant::now);
        if let Some(limit) = self.opt.max_wall_time {
            if started.elapsed().as_secs_f64() > limit {
                return Err(SolverError::WallClockLimit { limit_s: limit, time: self.t });
            }
        }
        self.step(t_end)?;
        Ok(Some(StepView {
            t_prev: self.t_prev,
            t: self.t,
            q: &self.q,
            v: &self.v,
            lambda: &self.lam,
            assembly: &self.asm,
            workspace: &mut self.ws,
            events: &self.events.last,
            dense: DenseRef {
                t1: self.t,
                h: self.h_cont,
                q: [&self.q, &self.cont_q[0], &self.cont_q[1], &self.cont_q[2]],
                v: [&self.v, &self.cont_v[0], &self.cont_v[1], &self.cont_v[2]],
                l: [&self.lam, &self.cont_l[0], &self.cont_l[1], &self.cont_l[2]],
            },
        }))
    }

    // ----------------------------------------------------------------- setup

    /// Projects the given initial state onto the constraints and computes
    /// consistent multipliers from `[M G^T; G 0] [a; lambda] = [Q; -gamma]`.
    fn initialise(&mut self) -> Result<(), SolverError> {
        self.consistent_state(true)
    }

    /// [`Radau5::initialise`] at the current state; `fresh`: the start of
    /// a run (contacts penetrating are closed and the energy balance
    /// starts here), else a resumed run ([`Radau5::resume`]: its modes
    /// and energies carried over).
    fn consistent_state(&mut self, fresh: bool) -> Result<(), SolverError> {
        let asm = Arc::clone(&self.asm);
        let (n, m) = (self.n, self.m);
        asm.jacobian(&mut self.ws, self.t, &self.q, &self.v, &self.lam, &mut self.jac);
        self.stats.jacobian_evaluations += 1;
        {
            let jac = &self.jac;
            let a = &asm;
            let desc = |p: usize| a.layout.position_names[p].clone();
            self.real
                .factor(
                    a.block_structure(),
                    &mut self.faer,
                    &|out: &mut [f64]| matrices::form(a, 1.0, 0.0, 0.0, 1.0, jac, out),
                    &desc,
                )
                .map_err(SolverError::Initialisation)?;
        }
        self.gscale_r = 1.0;
        self.fact_h = f64::NAN;
        // positions
        asm.residual(&mut self.ws, self.t, &self.q, &self.v, &self.lam);
        let (worst, gmax) = worst_equation(self.ws.constraints());
        if gmax > self.opt.initial_tolerance {
            return Err(SolverError::Build(BuildError::InconsistentInitialState {
                constraint: asm.constraint_name(asm.equation_constraint(worst)).to_string(),
                residual: gmax,
                tolerance: self.opt.initial_tolerance,
            }));
        }
        for _ in 0..5 {
            asm.residual(&mut self.ws, self.t, &self.q, &self.v, &self.lam);
            if worst_equation(self.ws.constraints()).1 <= self.opt.constraint_tolerance {
                break;
            }
            self.bl.copy_from_slice(self.ws.constraints());
            self.bl.iter_mut().for_each(|x| *x = -*x);
            self.bv.iter_mut().for_each(|x| *x = 0.0);
            self.solve_real_into_bq().map_err(SolverError::Initialisation)?;
            for c in 0..n {
                self.q[c] += self.bq[c];
            }
        }
        // velocities
        for _ in 0..5 {
            asm.residual(&mut self.ws, self.t, &self.q, &self.v, &self.lam);
            if worst_equation(self.ws.velocity_constraints()).1 <= self.opt.constraint_tolerance {
                break;
            }
            self.bl.copy_from_slice(self.ws.velocity_constraints());
            self.bl.iter_mut().for_each(|x| *x = -*x);
            self.bv.iter_mut().for_each(|x| *x = 0.0);
            self.solve_real_into_bq().map_err(SolverError::Initialisation)?;
            for c in 0..n {
                self.v[c] += self.bq[c];
            }
        }
        // consistent multipliers: M a + G^T lambda = Q, G a = -gamma
        let zeros = vec![0.0; m];
        asm.residual(&mut self.ws, self.t, &self.q, &self.v, &zeros);
        self.bv.copy_from_slice(self.ws.forces());
        asm.constraint_gamma(&mut self.ws, self.t, &self.q, &self.v);
        self.bl.copy_from_slice(self.ws.constraints());
        self.bl.iter_mut().for_each(|x| *x = -*x);
        self.solve_real_into_bq().map_err(SolverError::Initialisation)?;
        self.lam.copy_from_slice(&self.bl);
        self.stats.residual_evaluations += 3;
        // contacts penetrating at the start are closed
        if fresh && !self.events.is_empty() {
            let asm2 = Arc::clone(&self.asm);
            let mut cv = vec![crate::assembly::ContactValue::default(); asm2.contact_count()];
            asm2.contacts(&mut self.ws, &self.q, &self.v, &mut cv);
            let closing: Vec<usize> = (0..cv.len()).filter(|&i| cv[i].penetration > 0.0).collect();
            let at = State { t: self.t, q: &self.q, v: &self.v };
            self.events.change(&asm2, &mut self.ws, at, &closing, &mut self.energy);
            self.events.last.clear();
            asm2.jacobian(&mut self.ws, self.t, &self.q, &self.v, &self.lam, &mut self.jac);
        }
        // start-of-step residual, energy, constraint residuals
        self.update_y0();
        self.energy.kinetic = asm.kinetic_energy(&self.v);
        if fresh {
            self.energy.initial = self.energy.kinetic + self.energy.potential;
            self.potential0 = self.energy.potential;
        }
        self.energy.record(self.potential0);
        self.track_constraint_residuals();
        self.events.record_start(&asm, &mut self.ws, &self.q, &self.v);
        self.need_jac = true;
        Ok(())
    }

    /// The residual at the current state (for the next error estimate) and
    /// the stored energy there, from the kinematics the residual loaded.
    fn update_y0(&mut self) {
        self.asm.residual(&mut self.ws, self.t, &self.q, &self.v, &self.lam);
        self.energy.potential = self.asm.loaded_potential_energy(&self.ws, &self.q);
        self.ws.swap_results(&mut self.y0f, &mut self.y0g);
        self.stats.residual_evaluations += 1;
    }

    fn track_constraint_residuals(&mut self) {
        self.asm.constraint_residuals(&mut self.ws, self.t, &self.q, &self.v);
        self.record_constraint_residuals();
    }

    /// Folds the constraint residuals in the workspace into the maxima.
    fn record_constraint_residuals(&mut self) {
        let angular = &self.asm.eq_angular;
        let r = &mut self.max_residual;
        for (e, (&g, &gv)) in self.ws.constraints().iter().zip(self.ws.velocity_constraints()).enumerate() {
            if angular[e] {
                r.angle = r.angle.max(g.abs());
                r.angular_velocity = r.angular_velocity.max(gv.abs());
            } else {
                r.position = r.position.max(g.abs());
                r.velocity = r.velocity.max(gv.abs());
            }
        }
    }

    // --------------------------------------------------------- linear algebra

    /// Solves the real system for right-hand side (`bv`, `bl`):
    /// `S x + G^T y = bv`, `G x = bl`; `x` lands in `bq`, `y` in `bl`.
    fn solve_real_into_bq(&mut self) -> Result<(), LinalgError> {
        let lay = &self.asm.layout;
        for c in 0..self.n {
            self.rhs_r[lay.unknown_of_coord[c] as usize] = self.bv[c];
        }
        for e in 0..self.m {
            self.rhs_r[lay.unknown_of_eq[e] as usize] = self.gscale_r * self.asm.eq_mref[e] * self.bl[e];
        }
        self.real.solve(self.asm.block_structure(), &mut self.faer, &mut self.rhs_r)?;
        self.stats.linear_solves += 1;
        for c in 0..self.n {
            self.bq[c] = self.rhs_r[lay.unknown_of_coord[c] as usize];
        }
        for e in 0..self.m {
            self.bl[e] = self.gscale_r * self.asm.eq_mref[e] * self.rhs_r[lay.unknown_of_eq[e] as usize];
        }
        Ok(())
    }

    /// Evaluates the Jacobian at the current accepted state.
    fn evaluate_jacobian(&mut self) {
        let asm = Arc::clone(&self.asm);
        match self.opt.jacobian {
            JacobianMode::Analytic => {
                asm.iteration_jacobian(&mut self.ws, self.t, &self.q, &self.v, &self.lam, &self.zone, &mut self.jac)
            }
            JacobianMode::FiniteDifference { parallel } => {
                let colouring = self.colouring.get_or_insert_with(|| fd::Colouring::new(&asm));
                let state = (self.t, &self.q[..], &self.v[..], &self.lam[..]);
                let evals = fd::jacobian_with(&asm, colouring, state, &mut self.jac, parallel, Some(&self.ws));
                self.stats.residual_evaluations += evals as u64;
            }
        }
        self.stats.jacobian_evaluations += 1;
        self.need_jac = false;
        self.jac_fresh = true;
        // a new Jacobian is always factorised
        self.fact_h = f64::NAN;
        if let Some(sp) = self.spare.as_deref_mut() {
            sp.h = f64::NAN;
        }
    }

    /// Forms and factorises the real and complex iteration matrices for step `h`.
    fn factorize(&mut self, h: f64) -> Result<(), LinalgError> {
        let asm = Arc::clone(&self.asm);
        let sym = asm.block_structure();
        // steps fitted between record samples alternate between a few sizes
        // (one and two steps per sample): the previous factorisation is
        // kept and taken back when the step size returns to it
        if self.spare.as_ref().is_some_and(|sp| (h - sp.h).abs() <= FACT_RTOL * h) {
            self.swap_spare();
            self.stats.factorizations_reused += 1;
            return Ok(());
        }
        if self.fact_h.is_finite() {
            let mode = self.opt.linear_solver;
            self.spare.get_or_insert_with(|| {
                Box::new(Spare {
                    real: KktSolver::new(sym, mode),
                    cplx: KktSolver::new(sym, mode),
                    h: f64::NAN,
                    gscale_r: 0.0,
                    gscale_c: 0.0,
                })
            });
            self.swap_spare();
        }
        let desc = self.describe_owned();
        let g = GAMMA / h;
        let jac = &self.jac;
        self.fact_h = f64::NAN;
        self.real.factor(sym, &mut self.faer, &|out: &mut [f64]| form_real(&asm, g, jac, out), &desc)?;
        let c = Complex64::new(ALPHA / h, BETA / h);
        let gs = c.norm_sqr();
        self.cplx.factor(sym, &mut self.faer, &|out: &mut [Complex64]| form_complex(&asm, c, jac, out), &desc)?;
        self.gscale_r = g * g;
        self.gscale_c = gs;
        self.fact_h = h;
        self.stats.factorizations += 1;
        Ok(())
    }

    /// Exchanges the current factorisation with the spare one.
    fn swap_spare(&mut self) {
        if let Some(sp) = self.spare.as_deref_mut() {
            std::mem::swap(&mut self.real, &mut sp.real);
            std::mem::swap(&mut self.cplx, &mut sp.cplx);
            std::mem::swap(&mut self.fact_h, &mut sp.h);
            std::mem::swap(&mut self.gscale_r, &mut sp.gscale_r);
            std::mem::swap(&mut self.gscale_c, &mut sp.gscale_c);
        }
    }

    fn describe_owned(&self) -> impl Fn(usize) -> String {
        let names = self.asm.layout.position_names.clone();
        move |p| names[p].clone()
    }
}

/// A factorised pair of iteration matrices kept aside ([`Radau5`]'s
/// `spare`).
struct Spare {
    real: KktSolver<f64>,
    cplx: KktSolver<Complex64>,
    /// Step size it was formed for [s] (NaN: not valid).
    h: f64,
    gscale_r: f64,
    gscale_c: f64,
}

/// Largest constraint residuals by kind, each in its unit.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ConstraintResiduals {
    /// Largest |g| of translational equations (points, lines, drivers of x
    /// or y) \[m\].
    pub position: f64,
    /// Largest |g| of angular equations (relative angles, drivers of phi)
    /// \[rad\].
    pub angle: f64,
    /// Largest |G v + g_t| of translational equations [m/s].
    pub velocity: f64,
    /// Largest |G v + g_t| of angular equations [rad/s].
    pub angular_velocity: f64,
}

/// Index and magnitude of the largest |value|.
fn worst_equation(values: &[f64]) -> (usize, f64) {
    values.iter().enumerate().fold((0, 0.0), |(bi, bv), (i, v)| if v.abs() > bv { (i, v.abs()) } else { (bi, bv) })
}
