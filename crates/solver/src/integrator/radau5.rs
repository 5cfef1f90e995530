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
//! ([`super::local_friction`]).
//!
//! The factorisation is reused while the step size is unchanged to within
//! `FACT_RTOL` (steps fitted between breakpoints differ in the last bits),
//! and a new Jacobian is always factorised.

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

const SQ6: f64 = 2.449_489_742_783_178;
/// Stage abscissae `c_i`.
pub const C: [f64; 3] = [0.155_051_025_721_682_2, 0.644_948_974_278_317_8, 1.0];
const C1M1: f64 = C[0] - 1.0;
const C2M1: f64 = C[1] - 1.0;
const C1MC2: f64 = C[0] - C[1];
/// Butcher matrix of Radau IIA (s = 3).
pub const A: [[f64; 3]; 3] = [
    [0.196_815_477_223_660_43, -0.065_535_425_850_198_39, 0.023_770_974_348_220_15],
    [0.394_424_314_739_087_3, 0.292_073_411_665_228_46, -0.041_548_752_125_997_93],
    [0.376_403_062_700_467_27, 0.512_485_826_188_421_6, 1.0 / 9.0],
];
/// `T` with `T^-1 A^-1 T = [[gamma, 0, 0], [0, alpha, -beta], [0, beta, alpha]]`.
pub const T: [[f64; 3]; 3] = [
    [9.123_239_487_089_295e-2, -0.141_255_295_020_954_2, -3.002_919_410_514_742_4e-2],
    [0.241_717_932_707_107, 0.204_129_352_293_799_93, 0.382_942_112_757_261_9],
    [0.966_048_182_615_093, 1.0, 0.0],
];
/// `T^-1`.
pub const TI: [[f64; 3]; 3] = [
    [4.325_579_890_063_155, 0.339_199_251_815_809_87, 0.541_770_539_935_874_9],
    [-4.178_718_591_551_905, -0.327_682_820_761_062_4, 0.476_623_554_500_550_45],
    [-0.502_872_634_945_786_9, 2.571_926_949_855_605, -0.596_039_204_828_224_9],
];
/// Real eigenvalue of `A^-1`.
pub const GAMMA: f64 = 3.637_834_252_744_496;
/// Real part of the complex eigenvalues of `A^-1`.
pub const ALPHA: f64 = 2.681_082_873_627_752;
/// Imaginary part of the complex eigenvalues of `A^-1`.
pub const BETA: f64 = 3.050_430_199_247_410_6;
/// Coefficients of the embedded error estimate.
const DD: [f64; 3] = [-(13.0 + 7.0 * SQ6) / 3.0, (-13.0 + 7.0 * SQ6) / 3.0, -1.0 / 3.0];

const UROUND: f64 = f64::EPSILON;
const SAFE: f64 = 0.9;
const FACL: f64 = 5.0;
const FACR: f64 = 0.125;
/// Keep h (and the factorisation) while `QUOT1 <= h_new / h <= QUOT2`.
/// RADAU5 uses 1.0; 0.8 halves the factorisations of the expansion-joint
/// runs (medium model: 1.9k -> 0.8k) and takes 7 % fewer steps.
const QUOT1: f64 = 0.8;
const QUOT2: f64 = 1.2;
/// Relative difference of step sizes below which a factorisation is reused.
const FACT_RTOL: f64 = 1e-9;
/// Largest first step after a contact changes mode [s]: impacts of stiff
/// contacts last milliseconds; the error control takes it from there.
const CONTACT_STEP: f64 = 1e-4;

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
    /// F(t_n, y_n) and g(q_n, t_n): the start-of-step residual of the error estimate.
    y0f: Vec<f64>,
    y0g: Vec<f64>,
    // stages
    zq: Stages,
    zv: Stages,
    zl: Stages,
    wv: Stages,
    wl: Stages,
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
    // scratch
    bq: Vec<f64>,
    bv: Vec<f64>,
    bl: Vec<f64>,
    rhs_r: Vec<f64>,
    rhs_c: Vec<Complex64>,
    dq: Stages,
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
    scal_q: Vec<f64>,
    scal_v: Vec<f64>,
    scal_l: Vec<f64>,
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
            atol_q[c] = conv * if rotational { opt.atol_rotation } else { opt.atol_translation };
            atol_v[c] = conv * if rotational { opt.atol_angular_velocity } else { opt.atol_velocity };
        }
        let fnewt = (10.0 * UROUND / rtol)
            .max(opt.newton_tolerance.unwrap_or_else(|| 0.03f64.min(rtol.powf(1.0 / (2.0 / 3.0) - 1.0))));
        let local = LocalFriction::new(&asm, opt.local_friction && opt.jacobian == JacobianMode::Analytic);
        let zone = local.zone_mask(asm.friction_count());
        let mut s = Self {
            real: KktSolver::new(sym, opt.linear_solver),
            cplx: KktSolver::new(sym, opt.linear_solver),
            faer: FaerCache::default(),
            t: 0.0,
            q_ref: q0.clone(),
            q: q0,
            v: v0,
            lam: vec![0.0; m],
            y0f: vec![0.0; n],
            y0g: vec![0.0; m],
            zq: stages(n),
            zv: stages(n),
            zl: stages(m),
            wv: stages(n),
            wl: stages(m),
            fv: stages(n),
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
            gscale_r: 0.0,
            gscale_c: 0.0,
            bq: vec![0.0; n],
            bv: vec![0.0; n],
            bl: vec![0.0; m],
            rhs_r: vec![0.0; n + m],
            rhs_c: vec![Complex64::new(0.0, 0.0); n + m],
            dq: stages(n),
            e1q: vec![0.0; n],
            e1v: vec![0.0; n],
            ecq: vec![0.0; n],
            ecv: vec![0.0; n],
            ecg: vec![0.0; m],
            emd: vec![0.0; n],
            mass: asm.coordinate_masses().to_vec(),

            colouring: None,
            t_new: 0.0,
            scal_q: vec![1.0; n],
            scal_v: vec![1.0; n],
            scal_l: vec![1.0; m],
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
            potential0: 0.0,
            max_residual: ConstraintResiduals::default(),
            local,
            zone,
            events: Events::new(&asm),
            ws,
            n,
            m,
            opt,
            asm,
        };
        s.initialise()?;
        Ok(s)
    }

    /// Current time [s].
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
        s
    }

    /// Energy balance so far.
    pub fn energy(&self) -> &EnergyBalance {
        &self.energy
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

    /// Integrates to `t_end`, calling `observer` after every accepted step.
    /// Returns `Ok(false)` if the observer stopped the run early.
    pub fn run(&mut self, t_end: f64, observer: &mut dyn Observer) -> Result<bool, SolverError> {
        if t_end < self.t {
            return Err(SolverError::EndBeforeStart { t_end, t: self.t });
        }
        let start = Instant::now();
        while self.t < t_end {
            if self.stats.steps + self.stats.rejected + self.stats.failed_attempts >= self.opt.max_steps {
                return Err(SolverError::StepLimit { limit: self.opt.max_steps, time: self.t });
            }
            if let Some(limit) = self.opt.max_wall_time {
                if start.elapsed().as_secs_f64() > limit {
                    return Err(SolverError::WallClockLimit { limit_s: limit, time: self.t });
                }
            }
            self.step(t_end)?;
            let asm = Arc::clone(&self.asm);
            let mut view = StepView {
                t_prev: self.t_prev,
                t: self.t,
                q: &self.q,
                v: &self.v,
                lambda: &self.lam,
                assembly: &asm,
                workspace: &mut self.ws,
                events: &self.events.last,
                dense: DenseRef {
                    t1: self.t,
                    h: self.h_cont,
                    q: [&self.q, &self.cont_q[0], &self.cont_q[1], &self.cont_q[2]],
                    v: [&self.v, &self.cont_v[0], &self.cont_v[1], &self.cont_v[2]],
                    l: [&self.lam, &self.cont_l[0], &self.cont_l[1], &self.cont_l[2]],
                },
            };
            if !observer.step(&mut view) {
                return Ok(false);
            }
            self.events.last.clear();
        }
        Ok(true)
    }

    // ----------------------------------------------------------------- setup

    /// Projects the given initial state onto the constraints and computes
    /// consistent multipliers from `[M G^T; G 0] [a; lambda] = [Q; -gamma]`.
    fn initialise(&mut self) -> Result<(), SolverError> {
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
                    &|out: &mut [f64]| a.form(1.0, 0.0, 0.0, 1.0, jac, out),
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
        if !self.events.is_empty() {
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
        self.energy.potential = asm.potential_energy(&mut self.ws, &self.q);
        self.energy.initial = self.energy.kinetic + self.energy.potential;
        self.potential0 = self.energy.potential;
        self.energy.record(self.potential0);
        self.track_constraint_residuals();
        self.events.record_start(&asm, &mut self.ws, &self.q, &self.v);
        self.need_jac = true;
        Ok(())
    }

    fn update_y0(&mut self) {
        self.asm.residual(&mut self.ws, self.t, &self.q, &self.v, &self.lam);
        self.y0f.copy_from_slice(self.ws.forces());
        self.y0g.copy_from_slice(self.ws.velocity_constraints());
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
    }

    /// Forms and factorises the real and complex iteration matrices for step `h`.
    fn factorize(&mut self, h: f64) -> Result<(), LinalgError> {
        let asm = Arc::clone(&self.asm);
        let sym = asm.block_structure();
        let desc = self.describe_owned();
        let g = GAMMA / h;
        let jac = &self.jac;
        self.fact_h = f64::NAN;
        self.real.factor(sym, &mut self.faer, &|out: &mut [f64]| asm.form_real(g, jac, out), &desc)?;
        let c = Complex64::new(ALPHA / h, BETA / h);
        let gs = c.norm_sqr();
        self.cplx.factor(sym, &mut self.faer, &|out: &mut [Complex64]| asm.form_complex(c, jac, out), &desc)?;
        self.gscale_r = g * g;
        self.gscale_c = gs;
        self.fact_h = h;
        self.stats.factorizations += 1;
        Ok(())
    }

    fn describe_owned(&self) -> impl Fn(usize) -> String {
        let names = self.asm.layout.position_names.clone();
        move |p| names[p].clone()
    }

    // ------------------------------------------------------------------ steps

    /// Step size and end time: the step lands exactly on the next breakpoint
    /// or end time, splitting the remaining interval into equal steps.
    fn fit_step(&self, t_end: f64) -> (f64, f64) {
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

    fn fail(&mut self, cause: StepFailure, failures: &mut u32, factor: f64) -> Result<(), SolverError> {
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
    fn step(&mut self, t_end: f64) -> Result<(), SolverError> {
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
            let mut quot = FACR.max(FACL.min(err.powf(0.25) / fac));
            let mut h_new = h / quot;
            if err < 1.0 && !self.events.is_empty() {
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
                    continue;
                }
            }
            if err < 1.0 {
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
                return Ok(());
            }
            // rejected by the error test
            self.stats.rejected += 1;
            failures += 1;
            if failures >= self.opt.max_failures {
                return Err(SolverError::StepFailed {
                    time: self.t,
                    h,
                    attempts: failures,
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
                    attempts: failures,
                    cause: StepFailure::StepTooSmall { h: self.h, h_min: self.opt.h_min },
                });
            }
        }
    }

    /// After contacts changed mode at the current state: the start-of-step
    /// residual, the stored energy and the contacts' states are recomputed,
    /// and the next step starts afresh (new Jacobian, no extrapolation across
    /// the change, a step short against a contact's duration).
    fn after_contact_change(&mut self, changed: usize) {
        self.stats.contact_events += changed as u64;
        self.update_y0();
        self.energy.potential = self.asm.potential_energy(&mut self.ws, &self.q);
        self.energy.record(self.potential0);
        let asm = Arc::clone(&self.asm);
        self.events.record_start(&asm, &mut self.ws, &self.q, &self.v);
        self.need_jac = true;
        self.first = true;
        self.reject = false;
        self.have_cont = false;
        self.h = self.h.min(CONTACT_STEP);
    }

    /// Error scales of a step of size `h` from the current state: positions
    /// and velocities (error test and Newton norm) and multipliers (Newton
    /// norm only): `(rtol (|lambda_e| + max |lambda|) + m_ref scal_v) / h`,
    /// relative to the largest multiplier so that a component passing through
    /// zero is not held to an absolute tolerance; the velocity-equivalent
    /// floor only matters while every multiplier is near zero.
    fn set_scales(&mut self, h: f64) {
        for c in 0..self.n {
            self.scal_q[c] = self.atol_q[c] + self.rtol * (self.q[c] - self.q_ref[c]).abs();
            self.scal_v[c] = self.atol_v[c] + self.rtol * self.v[c].abs();
        }
        let lam_max = self.lam.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let lay = &self.asm.layout;
        for e in 0..self.m {
            let floor = self.asm.eq_mref[e] * self.scal_v[lay.eq_coord[e] as usize];
            self.scal_l[e] = (self.rtol * (self.lam[e].abs() + lam_max) + floor) / h;
        }
    }

    /// Extrapolates the last collocation polynomial to the new stages (or
    /// starts from zero), and derives the position stages.
    fn starting_values(&mut self, h: f64) {
        if self.first || !self.have_cont {
            for i in 0..3 {
                self.zv[i].iter_mut().for_each(|x| *x = 0.0);
                self.zl[i].iter_mut().for_each(|x| *x = 0.0);
            }
        } else {
            let c3q = h / self.h_cont;
            let cq = [C[0] * c3q, C[1] * c3q, c3q];
            let extrapolate = |cont: &Stages, z: &mut Stages| {
                for j in 0..cont[0].len() {
                    let (a1, a2, a3) = (cont[0][j], cont[1][j], cont[2][j]);
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
    fn derive_zq(&mut self, h: f64) {
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
    fn stage_time(&self, i: usize, h: f64) -> f64 {
        if i == 2 {
            self.t_new
        } else {
            self.t + C[i] * h
        }
    }

    /// Evaluates the residual at the three stages.
    fn stage_residuals(&mut self, h: f64, record_sliders: bool) -> bool {
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
            self.fv[i].copy_from_slice(self.ws.forces());
            self.fg[i].copy_from_slice(self.ws.velocity_constraints());
            // (no early exit, so that the test vectorises)
            finite &= self.fv[i].iter().chain(&self.fg[i]).fold(true, |ok, x| ok & x.is_finite());
        }
        self.stats.residual_evaluations += 3;
        finite
    }

    /// Simplified Newton iteration on the transformed stage equations.
    fn newton(&mut self, h: f64) -> Result<Newton, LinalgError> {
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
            for c in 0..n {
                let f = [self.fv[0][c], self.fv[1][c], self.fv[2][c]];
                let r = tmul(&TI, f);
                let w = [self.wv[0][c], self.wv[1][c], self.wv[2][c]];
                let mc = self.mass[c];
                let u = lay.unknown_of_coord[c] as usize;
                self.rhs_r[u] = r[0] - g_r * mc * w[0];
                self.rhs_c[u] = Complex64::new(
                    r[1] - mc * (c_c.re * w[1] - c_c.im * w[2]),
                    r[2] - mc * (c_c.im * w[1] + c_c.re * w[2]),
                );
            }
            let inv_c = c_c.inv();
            for e in 0..m {
                let r = tmul(&TI, [self.fg[0][e], self.fg[1][e], self.fg[2][e]]);
                let u = lay.unknown_of_eq[e] as usize;
                let s = self.asm.eq_mref[e];
                self.rhs_r[u] = -self.gscale_r * s * r[0] / g_r;
                self.rhs_c[u] = -Complex64::new(r[1], r[2]) * inv_c * (self.gscale_c * s);
            }
            let sym = self.asm.block_structure();
            self.real.solve(sym, &mut self.faer, &mut self.rhs_r)?;
            self.cplx.solve(sym, &mut self.faer, &mut self.rhs_c)?;
            self.stats.linear_solves += 2;
            newt += 1;
            self.stats.newton_iterations += 1;
            // increments of W and the Newton norm
            let mut sum = 0.0;
            for c in 0..n {
                let u = lay.unknown_of_coord[c] as usize;
                let d1 = self.rhs_r[u];
                let d23 = self.rhs_c[u];
                let dv23 = c_c * d23;
                self.dq[0][c] = d1;
                self.dq[1][c] = d23.re;
                self.dq[2][c] = d23.im;
                let (sq, sv) = (self.scal_q[c], self.scal_v[c]);
                let dv1 = g_r * d1;
                sum += (d1 / sq).powi(2) + (d23.re / sq).powi(2) + (d23.im / sq).powi(2);
                sum += (dv1 / sv).powi(2) + (dv23.re / sv).powi(2) + (dv23.im / sv).powi(2);
                self.wv[0][c] += dv1;
                self.wv[1][c] += dv23.re;
                self.wv[2][c] += dv23.im;
            }
            // multipliers (index-2 variables, whose errors are O(1/h) larger;
            // Hairer and Wanner IV.8 and VII.4) with the scales of `set_scales`
            for e in 0..m {
                let u = lay.unknown_of_eq[e] as usize;
                let s = self.asm.eq_mref[e];
                let d1 = self.gscale_r * s * self.rhs_r[u];
                let d23 = self.rhs_c[u] * (self.gscale_c * s);
                self.wl[0][e] += d1;
                self.wl[1][e] += d23.re;
                self.wl[2][e] += d23.im;
                let sl = self.scal_l[e];
                sum += (d1 / sl).powi(2) + (d23.re / sl).powi(2) + (d23.im / sl).powi(2);
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
    fn solve_frictions_locally(&mut self, h: f64) -> bool {
        if self.local.is_empty() || !self.local.solve(h, &self.mass, &self.jac, &self.fv, &mut self.zv) {
            return false;
        }
        transform(&TI, &self.zv, &mut self.wv);
        self.derive_zq(h);
        true
    }

    /// Embedded error estimate of RADAU5 (filtered through the real system).
    fn error_estimate(&mut self, h: f64) -> Result<f64, LinalgError> {
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
    fn filtered_error(&mut self, h: f64) -> Result<f64, LinalgError> {
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

    /// Accepts the step: new state, dense output, projection, energy.
    fn accept(&mut self, h: f64) -> Result<(), SolverError> {
        let (n, m) = (self.n, self.m);
        // energy quadrature over the stages (weights b = last row of A)
        let mut pw = [crate::assembly::Powers::default(); 3];
        for (i, p) in pw.iter_mut().enumerate() {
            for c in 0..n {
                self.bq[c] = self.q[c] + self.zq[i][c];
                self.bv[c] = self.v[c] + self.zv[i][c];
            }
            for e in 0..m {
                self.bl[e] = self.lam[e] + self.zl[i][e];
            }
            let ti = self.stage_time(i, h);
            *p = self.asm.powers(&mut self.ws, ti, &self.bq, &self.bv, &self.bl);
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
            for j in 0..len {
                let (z1, z2, z3) = (z[0][j], z[1][j], z[2][j]);
                let c1 = (z2 - z3) / C2M1;
                let ak = (z1 - z2) / C1MC2;
                let acont3 = (ak - z1 / C[0]) / C[1];
                let c2 = (ak - c1) / C1M1;
                cont[0][j] = c1;
                cont[1][j] = c2;
                cont[2][j] = c2 - acont3;
            }
        }
        for c in 0..n {
            self.q[c] += self.zq[2][c];
            self.v[c] += self.zv[2][c];
        }
        for e in 0..m {
            self.lam[e] += self.zl[2][e];
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
        self.energy.potential = self.asm.potential_energy(&mut self.ws, &self.q);
        self.energy.record(self.potential0);
        let asm = Arc::clone(&self.asm);
        self.events.record_start(&asm, &mut self.ws, &self.q, &self.v);
        Ok(())
    }

    /// Projects the accepted state onto `g = 0` and `G v + g_t = 0` with the
    /// current real factorisation (stale gradients are iterated out), and
    /// records the residuals left.
    fn project(&mut self) -> Result<(), LinalgError> {
        let tol = self.opt.constraint_tolerance;
        // whether the workspace holds the constraint residuals at (q, v)
        let mut current = false;
        for velocity in [false, true] {
            let mut last = f64::INFINITY;
            for _ in 0..12 {
                self.asm.constraint_residuals(&mut self.ws, self.t, &self.q, &self.v);
                current = true;
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

/// `out = a + b` elementwise.
#[inline]
fn add_into(out: &mut [f64], a: &[f64], b: &[f64]) {
    for ((o, &x), &y) in out.iter_mut().zip(a).zip(b) {
        *o = x + y;
    }
}

/// `y = M x` for a 3x3 matrix and a 3-vector.
#[inline]
fn tmul(mat: &[[f64; 3]; 3], x: [f64; 3]) -> [f64; 3] {
    [
        mat[0][0] * x[0] + mat[0][1] * x[1] + mat[0][2] * x[2],
        mat[1][0] * x[0] + mat[1][1] * x[1] + mat[1][2] * x[2],
        mat[2][0] * x[0] + mat[2][1] * x[1] + mat[2][2] * x[2],
    ]
}

/// Applies a 3x3 matrix across three stage vectors.
fn transform(mat: &[[f64; 3]; 3], src: &Stages, dst: &mut Stages) {
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

/// Index and magnitude of the largest |value|.
/// Largest constraint residuals by kind, each in its unit.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ConstraintResiduals {
    /// Largest |g| of translational equations (points, lines, drivers of x
    /// or y) [m].
    pub position: f64,
    /// Largest |g| of angular equations (relative angles, drivers of phi)
    /// [rad].
    pub angle: f64,
    /// Largest |G v + g_t| of translational equations [m/s].
    pub velocity: f64,
    /// Largest |G v + g_t| of angular equations [rad/s].
    pub angular_velocity: f64,
}

fn worst_equation(values: &[f64]) -> (usize, f64) {
    values.iter().enumerate().fold((0, 0.0), |(bi, bv), (i, v)| if v.abs() > bv { (i, v.abs()) } else { (bi, bv) })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transformation_diagonalises_the_inverse_butcher_matrix() {
        // A^-1 by cofactors: (A^-1)_ij = C_ji / det A
        let a = A;
        let minor = |r: usize, c: usize| {
            let rows: Vec<usize> = (0..3).filter(|&x| x != r).collect();
            let cols: Vec<usize> = (0..3).filter(|&x| x != c).collect();
            a[rows[0]][cols[0]] * a[rows[1]][cols[1]] - a[rows[0]][cols[1]] * a[rows[1]][cols[0]]
        };
        let det = (0..3).map(|c| a[0][c] * minor(0, c) * if c % 2 == 0 { 1.0 } else { -1.0 }).sum::<f64>();
        let mut ai = [[0.0; 3]; 3];
        for (i, row) in ai.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                let sign = if (i + j) % 2 == 0 { 1.0 } else { -1.0 };
                *x = sign * minor(j, i) / det;
            }
        }
        let mut prod = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                for k in 0..3 {
                    for l in 0..3 {
                        prod[i][j] += TI[i][k] * ai[k][l] * T[l][j];
                    }
                }
            }
        }
        let expect = [[GAMMA, 0.0, 0.0], [0.0, ALPHA, -BETA], [0.0, BETA, ALPHA]];
        for i in 0..3 {
            for j in 0..3 {
                assert!((prod[i][j] - expect[i][j]).abs() < 1e-12, "{i}{j}: {}", prod[i][j]);
            }
        }
        // collocation: row sums of A are the abscissae
        for i in 0..3 {
            assert!((A[i].iter().sum::<f64>() - C[i]).abs() < 1e-15);
        }
    }
}
