//! Andrews' squeezing mechanism, the standard test problem of planar
//! multibody codes: seven rigid bodies in a plane (no gravity), joined by
//! frictionless revolute joints into a mechanism of one degree of freedom,
//! driven by a constant torque on its crank against a spring, and checked
//! against the published reference solution at t = 0.03 s.
//!
//! Sources: W. Schiehlen (ed.), *Multibody Systems Handbook*, Springer 1990;
//! E. Hairer and G. Wanner, *Solving Ordinary Differential Equations II*,
//! 2nd ed., Springer 1996, Section VII.7;
//! the Test Set for IVP Solvers of F. Mazzia and F. Iavernaro (University of
//! Bari), problem "andrews", whose reference solution at t = 0.03 s was
//! computed with PSIDE at tolerances 1e-14 (Cray C90). The data and that
//! solution are taken from the test set as distributed in the R package
//! deTestSet (repository `rforge/bvpsolve`): the parameters and the initial
//! angles from `pkg/deTestSet/R/ex_andrews.R`, the reference solution from
//! subroutine `andsoln` of `pkg/deTestSet/src/Ex_andrews.f`. The same
//! parameters and initial angles are in `JonasBreuling/scipy_dae`,
//! `examples/daes/andrews.py`; the same digits of all three (parameters,
//! initial angles and solution) in the test set's MEBDFI drivers (Fortran
//! `SUBROUTINE F`, `INITIAL`, `SOLN`, and their MATLAB port) and in pySDC's
//! `AndrewsSqueezingMechanismDAE` (`u_exact`).
//!
//! # The mechanism
//!
//! The test set writes it in seven angles: `beta` (crank), `Theta` (coupler
//! relative to the crank), `gamma` (lever at B), `Phi` (link 4 relative to
//! link 5), `delta` (link 5 at A), `Omega` (link 6 relative to link 7) and
//! `epsilon` (link 7 at A). Three fixed pivots carry it, O at the origin, A
//! and B; three kinematic loops close at one point E where the coupler, the
//! lever and the two links 4 and 6 meet:
//!
//! ```text
//!   y                                   o C  spring anchor
//!   ^                                  /
//!   |                                 /  spring c0, l0
//!   |             B o                /
//!   |                |\_____________o D
//!   |                |   lever 3   /
//!   |      H5 o      |   (B, D, E)
//!   |        / \     |          /
//!   |     5 /   \ 4  |        /
//!   |      /     \   |      /
//!   |  A o        `-- o E ------------------ o P      crank 1 turns
//!   |     \          /      coupler 2     o O        about O, torque
//!   |    7 \        / 6                               mom
//!   |       o------'
//!   |      H7
//!   +-------------------------------------------------------> x
//! ```
//!
//! (A sketch: the two chains A-H5-E and A-H7-E are mirror images, so
//! `Omega = -Phi` throughout.) The joints, 10 revolutes of 2 equations
//! each on 7 bodies of 3 coordinates, leave 1 degree of freedom:
//!
//! | joint | bodies | point |
//! |---|---|---|
//! | O | crank 1, ground | origin |
//! | P | coupler 2, crank 1 | `rr` from O on the crank |
//! | B | lever 3, ground | `(xb, yb)` |
//! | A | link 5, ground | `(xa, ya)` |
//! | A | link 7, ground | `(xa, ya)` |
//! | H5 | link 4, link 5 | `zt` from A on link 5 |
//! | H7 | link 6, link 7 | `u` from A on link 7 |
//! | E | coupler 2, lever 3 | `d` from P, `ss` from B |
//! | E | coupler 2, link 4 | `e` from H5 |
//! | E | coupler 2, link 6 | `zf` from H7 |
//!
//! A spring of stiffness `c0` and rest length `l0` pulls the lever's point D
//! toward the fixed point C; the torque `mom` drives the crank. The test set
//! writes Lagrange's equations in the seven angles with six multipliers
//! (the loop closures at E); the solver here sees 21 absolute coordinates
//! and 20 constraint equations.
//!
//! # From the test set's angles to absolute coordinates
//!
//! Each body's frame is turned by its absolute angle, which is the sum of
//! the test set's angles along its chain from the ground: crank
//! `phi_1 = beta`, coupler `phi_2 = beta + Theta`, lever `phi_3 = gamma`,
//! link 4 `phi_4 = Phi + delta`, link 5 `phi_5 = delta`, link 6
//! `phi_6 = Omega + epsilon`, link 7 `phi_7 = epsilon`. With `R(phi)` the
//! rotation and `e_x = (1, 0)`, `-e_y = (0, -1)`, the test set's loop
//! equations place the points and the centres of mass (the reference points
//! of the solver's bodies):
//!
//! ```text
//! crank 1:   P  = O + rr R(phi_1) e_x,        G1 = O + ra R(phi_1) e_x
//! coupler 2: E  = P - d R(phi_2) e_x,         G2 = P - da R(phi_2) e_x
//! lever 3:   E  = B - ss R(phi_3) e_y,        D  = B + R(phi_3) (sd, -sc),
//!            G3 = B + R(phi_3) (sa, sb)
//! link 5:    H5 = A + zt R(phi_5) e_x,        G5 = A + R(phi_5) (ta, tb)
//! link 4:    E  = H5 - e R(phi_4) e_y,        G4 = H5 - (e - ea) R(phi_4) e_y
//! link 7:    H7 = A - u R(phi_7) e_y,         G7 = A + R(phi_7) (ua, ub)
//! link 6:    E  = H7 + zf R(phi_6) e_x,       G6 = H7 + (zf - fa) R(phi_6) e_x
//! ```
//!
//! The positions of G2, G4 and G6 follow from the test set's mass matrix
//! (its terms in `cos Theta`, `sin Phi` and `sin Omega`). The crank, the
//! lever and links 5 and 7 turn about fixed pivots and there is no gravity,
//! so only the distance of their centres of mass from the pivot enters
//! (through `I + m r^2`, the test set's `m1 ra^2 + I1`, `m3 (sa^2 + sb^2) +
//! I3`, ...): the directions chosen above are a convention and change
//! nothing but the pivots' reactions. The inertias `I1`..`I7` are about the
//! centres of mass. Back from the bodies' angles: `beta = phi_1`,
//! `Theta = phi_2 - phi_1`, `gamma = phi_3`, `Phi = phi_4 - phi_5`,
//! `delta = phi_5`, `Omega = phi_6 - phi_7`, `epsilon = phi_7`; the
//! solver's angles are not wrapped, so the crank's `beta` reaches 15.8 rad.
//!
//! The test set starts at rest from consistent angles (given to 30 digits);
//! its initial accelerations and multipliers are what the integrator
//! computes itself. `crates/solver/tests/andrews_squeezer.rs` compares the
//! seven angles at t = 0.03 s with the published values at three tolerances.

use std::sync::Arc;

use thiserror::Error;

use crate::assembly::{Assembly, AssemblyOptions};
use crate::error::{BuildError, DenseOutputError, SolverError};
use crate::integrator::{EnergyBalance, IntegratorOptions, NoObserver, Radau5, Stats};
use crate::model::body::{Body, BodyId, Coord};
use crate::model::constraint::{Constraint, Revolute};
use crate::model::force::{AppliedLoad, ForceElement, SpringDamper};
use crate::model::system::System;
use crate::timefn::TimeFunction;

/// End of the test set's interval, where its reference solution is given \[s\].
pub const END_TIME: f64 = 0.03;

/// Names of the test set's seven angles, in its order.
pub const ANGLE_NAMES: [&str; 7] = ["beta", "Theta", "gamma", "Phi", "delta", "Omega", "epsilon"];

/// The test set's consistent initial angles \[rad\] (`y(1)`..`y(7)` of
/// `ex_andrews.R`; the velocities are zero).
// the test set's 30 digits, verbatim (f64 keeps 17 of them)
#[allow(clippy::excessive_precision)]
pub const INITIAL_ANGLES: [f64; 7] = [
    -0.0617138900142764496358948458001,
    0.0,
    0.455279819163070380255912382449,
    0.222668390165885884674473185609,
    0.487364979543842550225598953530,
    -0.222668390165885884674473185609,
    1.23054744454982119249735015568,
];

/// The published reference angles at t = 0.03 s \[rad\] (`y(1)`..`y(7)` of
/// subroutine `andsoln`, `Ex_andrews.f`: PSIDE at tolerances 1e-14).
pub const REFERENCE_ANGLES: [f64; 7] = [
    0.1581077119629904e+2,
    -0.1575637105984298e+2,
    0.4082224013073101e-1,
    -0.5347301163226948e+0,
    0.5244099658805304e+0,
    0.5347301163226948e+0,
    0.1048080741042263e+1,
];

/// The mechanism's data, named as in the test set (SI units). Lengths not
/// given a point are distances along the bodies (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Squeezer {
    /// Masses `m1`..`m7` of the crank, coupler, lever and links 4 to 7 \[kg\].
    pub masses: [f64; 7],
    /// Inertias `I1`..`I7` about the centres of mass \[kg m^2\].
    pub inertias: [f64; 7],
    /// Fixed pivot A of links 5 and 7, `(xa, ya)` \[m\].
    pub a: [f64; 2],
    /// Fixed pivot B of the lever, `(xb, yb)` \[m\].
    pub b: [f64; 2],
    /// Fixed anchor C of the spring, `(xc, yc)` \[m\].
    pub c: [f64; 2],
    /// Spring stiffness `c0` \[N/m\].
    pub c0: f64,
    /// Spring rest length `l0` \[m\].
    pub l0: f64,
    /// Driving torque on the crank `mom` \[N m\].
    pub mom: f64,
    /// Crank pin P from O `rr` \[m\].
    pub rr: f64,
    /// Crank centre of mass from O `ra` \[m\].
    pub ra: f64,
    /// Coupler length P to E `d` \[m\].
    pub d: f64,
    /// Coupler centre of mass from P `da` \[m\].
    pub da: f64,
    /// Lever, E from B `ss` \[m\].
    pub ss: f64,
    /// Lever centre of mass from B, `(sa, sb)` in its frame \[m\].
    pub sa: f64,
    /// See `sa` \[m\].
    pub sb: f64,
    /// Lever, spring point D from B: `sd` along, `sc` across \[m\].
    pub sc: f64,
    /// See `sc` \[m\].
    pub sd: f64,
    /// Link 4 length H5 to E `e` \[m\].
    pub e: f64,
    /// Link 4 centre of mass from E `ea` \[m\].
    pub ea: f64,
    /// Link 5, H5 from A `zt` \[m\].
    pub zt: f64,
    /// Link 5 centre of mass from A, `(ta, tb)` in its frame \[m\].
    pub ta: f64,
    /// See `ta` \[m\].
    pub tb: f64,
    /// Link 6 length H7 to E `zf` \[m\].
    pub zf: f64,
    /// Link 6 centre of mass from E `fa` \[m\].
    pub fa: f64,
    /// Link 7, H7 from A `u` \[m\].
    pub u: f64,
    /// Link 7 centre of mass from A, `(ua, ub)` in its frame \[m\].
    pub ua: f64,
    /// See `ua` \[m\].
    pub ub: f64,
}

impl Default for Squeezer {
    /// The test set's data (`ex_andrews.R`, `parameter`).
    fn default() -> Self {
        Self {
            masses: [0.04325, 0.00365, 0.02373, 0.00706, 0.07050, 0.00706, 0.05498],
            inertias: [2.194e-6, 4.410e-7, 5.255e-6, 5.667e-7, 1.169e-5, 5.667e-7, 1.912e-5],
            a: [-0.06934, -0.00227],
            b: [-0.03635, 0.03273],
            c: [0.014, 0.072],
            c0: 4530.0,
            l0: 0.07785,
            mom: 0.033,
            rr: 0.007,
            ra: 0.00092,
            d: 0.028,
            da: 0.0115,
            ss: 0.035,
            sa: 0.01874,
            sb: 0.01043,
            sc: 0.018,
            sd: 0.02,
            e: 0.02,
            ea: 0.01421,
            zt: 0.04,
            ta: 0.02308,
            tb: 0.00916,
            zf: 0.02,
            fa: 0.01421,
            u: 0.04,
            ua: 0.01228,
            ub: 0.00449,
        }
    }
}

/// The seven bodies of the built system, in the test set's order (crank,
/// coupler, lever, links 4 to 7).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Bodies(pub [BodyId; 7]);

/// One body's place: the absolute angle of its frame \[rad\] and its centre
/// of mass \[m\].
#[derive(Debug, Clone, Copy, PartialEq)]
struct Placed {
    phi: f64,
    centre: [f64; 2],
}

/// `p + R(phi) v`.
fn along(p: [f64; 2], phi: f64, v: [f64; 2]) -> [f64; 2] {
    let (s, c) = phi.sin_cos();
    [p[0] + c * v[0] - s * v[1], p[1] + s * v[0] + c * v[1]]
}

impl Squeezer {
    /// Frame angles of the seven bodies from the test set's angles \[rad\].
    pub fn body_angles(angles: &[f64; 7]) -> [f64; 7] {
        let [beta, theta, gamma, phi, delta, omega, epsilon] = *angles;
        [beta, beta + theta, gamma, phi + delta, delta, omega + epsilon, epsilon]
    }

    /// The test set's angles from the seven bodies' frame angles \[rad\].
    pub fn relative_angles(phi: &[f64; 7]) -> [f64; 7] {
        [phi[0], phi[1] - phi[0], phi[2], phi[3] - phi[4], phi[4], phi[5] - phi[6], phi[6]]
    }

    /// Joint points of each body relative to its centre of mass, in its
    /// frame \[m\]: the crank's O and P, the coupler's P and E, the lever's
    /// B, E and D, link 4's H5 and E, link 5's A and H5, link 6's H7 and E,
    /// link 7's A and H7.
    fn points(&self) -> Points {
        let (ea_e, fa_f) = (self.e - self.ea, self.zf - self.fa);
        let (sa, sb, ta, tb, ua, ub) = (self.sa, self.sb, self.ta, self.tb, self.ua, self.ub);
        Points {
            crank_o: [-self.ra, 0.0],
            crank_p: [self.rr - self.ra, 0.0],
            coupler_p: [self.da, 0.0],
            coupler_e: [self.da - self.d, 0.0],
            lever_b: [-sa, -sb],
            lever_e: [-sa, -self.ss - sb],
            lever_d: [self.sd - sa, -self.sc - sb],
            link4_h: [0.0, ea_e],
            link4_e: [0.0, -self.ea],
            link5_a: [-ta, -tb],
            link5_h: [self.zt - ta, -tb],
            link6_h: [-fa_f, 0.0],
            link6_e: [self.fa, 0.0],
            link7_a: [-ua, -ub],
            link7_h: [-ua, -self.u - ub],
        }
    }

    /// The seven bodies' frame angles and centres of mass at the test set's
    /// `angles` \[rad\] (module doc, "From the test set's angles").
    fn place(&self, angles: &[f64; 7]) -> [Placed; 7] {
        let phi = Self::body_angles(angles);
        let pt = self.points();
        // each centre from a fixed pivot, or from the joint it hangs on
        let g1 = along([0.0, 0.0], phi[0], [self.ra, 0.0]);
        let p = along(g1, phi[0], pt.crank_p);
        let g2 = along(p, phi[1], [-self.da, 0.0]);
        let g3 = along(self.b, phi[2], [self.sa, self.sb]);
        let g5 = along(self.a, phi[4], [self.ta, self.tb]);
        let h5 = along(g5, phi[4], pt.link5_h);
        let g4 = along(h5, phi[3], [0.0, -(self.e - self.ea)]);
        let g7 = along(self.a, phi[6], [self.ua, self.ub]);
        let h7 = along(g7, phi[6], pt.link7_h);
        let g6 = along(h7, phi[5], [self.zf - self.fa, 0.0]);
        let centres = [g1, g2, g3, g4, g5, g6, g7];
        std::array::from_fn(|k| Placed { phi: phi[k], centre: centres[k] })
    }

    /// The mechanism as a solver system, at rest at the test set's `angles`
    /// \[rad\] (normally [`INITIAL_ANGLES`]), and its bodies.
    pub fn system(&self, angles: &[f64; 7]) -> (System, Bodies) {
        const NAMES: [&str; 7] = ["crank", "coupler", "lever", "link 4", "link 5", "link 6", "link 7"];
        let mut sys = System::new();
        let placed = self.place(angles);
        let ids: [BodyId; 7] = std::array::from_fn(|k| {
            let Placed { phi, centre } = placed[k];
            sys.add_body(Body::new(NAMES[k], self.masses[k], self.inertias[k], [centre[0], centre[1], phi]))
        });
        let [crank, coupler, lever, link4, link5, link6, link7] = ids;
        let pt = self.points();
        let ground = BodyId::GROUND;
        let joints = [
            ("O", crank, pt.crank_o, ground, [0.0, 0.0]),
            ("P", coupler, pt.coupler_p, crank, pt.crank_p),
            ("B", lever, pt.lever_b, ground, self.b),
            ("A of link 5", link5, pt.link5_a, ground, self.a),
            ("A of link 7", link7, pt.link7_a, ground, self.a),
            ("H5", link4, pt.link4_h, link5, pt.link5_h),
            ("H7", link6, pt.link6_h, link7, pt.link7_h),
            ("E of the lever", lever, pt.lever_e, coupler, pt.coupler_e),
            ("E of link 4", link4, pt.link4_e, coupler, pt.coupler_e),
            ("E of link 6", link6, pt.link6_e, coupler, pt.coupler_e),
        ];
        for (name, body_a, point_a, body_b, point_b) in joints {
            sys.add_constraint_named(name, Constraint::Revolute(Revolute { body_a, point_a, body_b, point_b }));
        }
        sys.add_force_named(
            "spring",
            ForceElement::SpringDamper(SpringDamper {
                body_a: lever,
                point_a: pt.lever_d,
                body_b: ground,
                point_b: self.c,
                stiffness: self.c0,
                damping: 0.0,
                rest_length: self.l0,
            }),
        );
        sys.add_force_named(
            "driving torque",
            ForceElement::AppliedLoad(AppliedLoad {
                body: crank,
                point: [0.0, 0.0],
                fx: TimeFunction::Constant(0.0),
                fy: TimeFunction::Constant(0.0),
                torque: TimeFunction::Constant(self.mom),
            }),
        );
        (sys, Bodies(ids))
    }

    /// Runs the mechanism from rest at [`INITIAL_ANGLES`] to `t_end` \[s\]
    /// (the test set's [`END_TIME`]) with `options` ([`options`] gives
    /// tolerances suited to it) and reads the seven angles there.
    pub fn simulate(&self, options: IntegratorOptions, t_end: f64) -> Result<Run, RunError> {
        let (sys, bodies) = self.system(&INITIAL_ANGLES);
        let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default())?);
        let reader = AngleReader::new(&asm, &bodies)?;
        let mut sim = Radau5::new(asm, options)?;
        let start = reader.read(sim.positions())?;
        sim.run(t_end, &mut NoObserver)?;
        let angles = reader.read(sim.positions())?;
        Ok(Run {
            t: sim.time(),
            start,
            angles,
            stats: sim.stats(),
            energy: *sim.energy(),
            residuals: sim.max_constraint_residuals(),
        })
    }
}

/// The joint points of [`Squeezer::points`].
struct Points {
    crank_o: [f64; 2],
    crank_p: [f64; 2],
    coupler_p: [f64; 2],
    coupler_e: [f64; 2],
    lever_b: [f64; 2],
    lever_e: [f64; 2],
    lever_d: [f64; 2],
    link4_h: [f64; 2],
    link4_e: [f64; 2],
    link5_a: [f64; 2],
    link5_h: [f64; 2],
    link6_h: [f64; 2],
    link6_e: [f64; 2],
    link7_a: [f64; 2],
    link7_h: [f64; 2],
}

/// Why a run of the squeezer ([`Squeezer::simulate`]) failed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum RunError {
    /// The system could not be compiled, or a body's angle is locked.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// The integration failed.
    #[error(transparent)]
    Solver(#[from] SolverError),
    /// The angles could not be read from the positions.
    #[error(transparent)]
    Read(#[from] DenseOutputError),
}

/// The integrator options of the squeezer at relative tolerance `rtol`
/// [-]: absolute tolerances `rtol` for the angles \[rad\] and angular
/// velocities \[rad/s\], `rtol` times the mechanism's length scale of 0.01 m
/// for positions \[m\] and velocities \[m/s\], the first step 1e-6 s (the
/// crank accelerates at 1.4e4 rad/s^2 from rest) and the constraints held
/// to `1e-3 rtol` \[m\] (at least 1e-14 m) so that projecting the state
/// onto them does not cost more accuracy than the step does.
pub fn options(rtol: f64) -> IntegratorOptions {
    IntegratorOptions {
        rtol,
        atol_rotation: rtol,
        atol_angular_velocity: rtol,
        atol_translation: 0.01 * rtol,
        atol_velocity: 0.01 * rtol,
        h_initial: 1e-6,
        constraint_tolerance: (1e-3 * rtol).max(1e-14),
        ..IntegratorOptions::default()
    }
}

/// What a run of the squeezer gives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Run {
    /// The time reached \[s\].
    pub t: f64,
    /// The seven angles after the integrator's initial projection \[rad\].
    pub start: [f64; 7],
    /// The seven angles at the end, in the test set's order \[rad\].
    pub angles: [f64; 7],
    /// The integrator's counters.
    pub stats: Stats,
    /// The run's energy balance \[J\] (the torque's work against the
    /// kinetic energy and the spring's).
    pub energy: EnergyBalance,
    /// Largest |g| \[m, rad\] and |G v| \[m/s, rad/s\] over the run.
    pub residuals: (f64, f64),
}

impl Run {
    /// Each angle minus its published value at t = 0.03 s \[rad\].
    pub fn errors(&self) -> [f64; 7] {
        std::array::from_fn(|k| self.angles[k] - REFERENCE_ANGLES[k])
    }

    /// The largest |angle - published value| \[rad\] and the index of that
    /// angle.
    pub fn worst(&self) -> (usize, f64) {
        self.errors().iter().map(|e| e.abs()).enumerate().fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a })
    }
}

/// Reads the test set's seven angles from the solver's positions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AngleReader {
    phi: [usize; 7],
    coordinates: usize,
}

impl AngleReader {
    /// The reader for `bodies` of `asm`; fails if a body's angle is locked.
    pub fn new(asm: &Assembly, bodies: &Bodies) -> Result<Self, BuildError> {
        let mut phi = [0; 7];
        for (slot, body) in phi.iter_mut().zip(bodies.0) {
            *slot = asm.coordinate(body, Coord::Phi).ok_or_else(|| BuildError::NoFreeCoordinate {
                what: format!("body {} of Andrews' squeezer", body.index()),
                detail: "its angle phi must be free".to_string(),
            })?;
        }
        Ok(Self { phi, coordinates: asm.coordinates() })
    }

    /// The seven angles \[rad\] from the positions `q` (of the assembly's
    /// length).
    pub fn read(&self, q: &[f64]) -> Result<[f64; 7], DenseOutputError> {
        if q.len() != self.coordinates {
            return Err(DenseOutputError::WrongLength { what: "q", len: q.len(), expected: self.coordinates });
        }
        Ok(Squeezer::relative_angles(&self.phi.map(|i| q[i])))
    }
}
