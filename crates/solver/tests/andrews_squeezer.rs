//! Andrews' squeezing mechanism (`reference::andrews`) against the
//! published reference solution of the IVP Test Set (F. Mazzia and F.
//! Iavernaro, University of Bari, problem "andrews"; E. Hairer and G.
//! Wanner, *Solving Ordinary Differential Equations II*, Section VII.7; W.
//! Schiehlen (ed.), *Multibody Systems Handbook*, 1990).
//!
//! The physics: seven rigid bodies in a plane without gravity, joined by
//! frictionless revolute joints into a closed mechanism of one degree of
//! freedom (three loops closing at one point), a crank driven by the
//! constant torque 0.033 N m against a spring of 4530 N/m on a lever. From
//! rest, the crank spins up to 1140 rad/s and turns 2.5 times in 0.03 s while
//! the lever and the four links swing; the test set integrates it in seven
//! angles with six multipliers, the solver in 21 absolute coordinates with
//! 20 constraint equations (the conversion is in the module doc of
//! `reference::andrews`).
//!
//! The source of the data and of the values compared: the test set as
//! distributed in the R package deTestSet (repository `rforge/bvpsolve`),
//! `pkg/deTestSet/R/ex_andrews.R` (parameters, initial angles) and subroutine
//! `andsoln` of `pkg/deTestSet/src/Ex_andrews.f` (the solution at t = 0.03 s,
//! computed with PSIDE at tolerances 1e-14); the same digits are in the test
//! set's MEBDFI driver and in pySDC's `AndrewsSqueezingMechanismDAE`.
//!
//! Checks:
//!
//! - a second method written apart from the solver: the test set's own
//!   equations in the seven angles (`andfunc` of `Ex_andrews.f`, its mass
//!   matrix, forces and loop closures, written out here), in index-1 form
//!   and integrated with the classical Runge-Kutta method at a fixed step;
//!   its accelerations at t = 0 are the test set's published consistent
//!   ones, and its solution at t = 0.03 s does not move when its step is
//!   halved (to 1e-12 rad);
//! - a convergence study at tolerances 1e-8, 1e-10 and 1e-12: the solver's
//!   distance to the second method falls with the tolerance (1.8e-7, 4.4e-9,
//!   9.9e-11 rad: a factor of 40 per factor 100) and its distance to the
//!   published angles falls too (1.8e-7, 5.9e-9, 1.5e-9 rad), but levels
//!   off: the published digits are themselves 1.15e-9 rad (beta) and 1.43e-9
//!   rad (Theta) off the converged solution of their own equations (relative
//!   7e-11). The solver and the second method share nothing but the data,
//!   and agree to 5e-13 rad (measured with the solver at 1e-14 and the
//!   second method at 600 000 steps), so the offset is in the published
//!   digits (presumably PSIDE's global error at its tolerances 1e-14), not a
//!   difference between the models;
//! - the band: every angle within 2e-9 rad of its published value at
//!   tolerances 1e-12 (measured: 1.53e-9, Theta's), the published digits'
//!   own 1.43e-9 plus room for the solver's 1e-10 to grow fivefold;
//! - the energy balance: the torque's work `mom (beta - beta0)` equals the
//!   kinetic energy plus the spring's.

use quakejoint_solver::reference::andrews::{
    self, Run, Squeezer, ANGLE_NAMES, END_TIME, INITIAL_ANGLES, REFERENCE_ANGLES,
};

/// The acceptance band on each angle at tolerances 1e-12 \[rad\] (module doc).
const BAND: f64 = 2e-9;

/// The test set's consistent initial accelerations of `beta` and `Theta`
/// (`y(15)`, `y(16)` of `ex_andrews.R`; the others are zero) \[rad/s^2\].
// the test set's 30 digits, verbatim (f64 keeps 17 of them)
#[allow(clippy::excessive_precision)]
const INITIAL_ACCELERATIONS: [f64; 2] = [14222.4439199541138705911625887, -10666.8329399655854029433719415];

/// The test set's mass matrix `M(q)` (`andfunc`, `m(i, j)`) \[kg m^2\].
fn mass_matrix(p: &Squeezer, q: &[f64; 7]) -> [[f64; 7]; 7] {
    let [m1, m2, m3, m4, m5, m6, m7] = p.masses;
    let [i1, i2, i3, i4, i5, i6, i7] = p.inertias;
    let (coth, siph, siom) = (q[1].cos(), q[3].sin(), q[5].sin());
    let (ee, ff, rr, da, zt, u) = (p.e - p.ea, p.zf - p.fa, p.rr, p.da, p.zt, p.u);
    let mut m = [[0.0; 7]; 7];
    m[0][0] = m1 * p.ra * p.ra + m2 * (rr * rr - 2.0 * da * rr * coth + da * da) + i1 + i2;
    m[1][0] = m2 * (da * da - da * rr * coth) + i2;
    m[1][1] = m2 * da * da + i2;
    m[2][2] = m3 * (p.sa * p.sa + p.sb * p.sb) + i3;
    m[3][3] = m4 * ee * ee + i4;
    m[4][3] = m4 * (ee * ee + zt * ee * siph) + i4;
    m[4][4] = m4 * (zt * zt + 2.0 * zt * ee * siph + ee * ee) + m5 * (p.ta * p.ta + p.tb * p.tb) + i4 + i5;
    m[5][5] = m6 * ff * ff + i6;
    m[6][5] = m6 * (ff * ff - u * ff * siom) + i6;
    m[6][6] = m6 * (ff * ff - 2.0 * u * ff * siom + u * u) + m7 * (p.ua * p.ua + p.ub * p.ub) + i6 + i7;
    for (i, j) in [(0, 1), (3, 4), (5, 6)] {
        m[i][j] = m[j][i];
    }
    m
}

/// The test set's generalised forces `f(q, q')` (`andfunc`, `ff`): the
/// torque, the spring and the velocity terms of Lagrange's equations [N m].
fn forces(p: &Squeezer, q: &[f64; 7], v: &[f64; 7]) -> [f64; 7] {
    let [_, m2, _, m4, _, m6, _] = p.masses;
    let [bp, tp, _, pp, dp, op, ep] = *v;
    let (siga, coga) = q[2].sin_cos();
    let (sc, sd) = (p.sc, p.sd);
    let xd = sd * coga + sc * siga + p.b[0];
    let yd = sd * siga - sc * coga + p.b[1];
    let length = ((xd - p.c[0]).powi(2) + (yd - p.c[1]).powi(2)).sqrt();
    let force = -p.c0 * (length - p.l0) / length;
    let (fx, fy) = (force * (xd - p.c[0]), force * (yd - p.c[1]));
    let (k2, k4, k6) =
        (m2 * p.da * p.rr * q[1].sin(), m4 * p.zt * (p.e - p.ea) * q[3].cos(), m6 * p.u * (p.zf - p.fa) * q[5].cos());
    [
        p.mom - k2 * tp * (tp + 2.0 * bp),
        k2 * bp * bp,
        fx * (sc * coga - sd * siga) + fy * (sd * coga + sc * siga),
        k4 * dp * dp,
        -k4 * pp * (pp + 2.0 * dp),
        -k6 * ep * ep,
        k6 * op * (op + 2.0 * ep),
    ]
}

/// The test set's loop closures at E: their Jacobian `G = dg/dq` (`gp`) and
/// `g''` at `q'' = 0` (the curvature term of the index-1 form) \[m\].
fn closures(p: &Squeezer, q: &[f64; 7], v: &[f64; 7]) -> ([[f64; 7]; 6], [f64; 6]) {
    let [be, th, ga, ph, de, om, ep] = *q;
    let [bp, tp, gp, pp, dp, op, epp] = *v;
    let (rr, d, ss, e, zt, zf, u) = (p.rr, p.d, p.ss, p.e, p.zt, p.zf, p.u);
    let ((sibe, cobe), (sibt, cobt)) = (be.sin_cos(), (be + th).sin_cos());
    let ((siga, coga), (side, code), (siep, coep)) = (ga.sin_cos(), de.sin_cos(), ep.sin_cos());
    let ((sipd, copd), (sioe, cooe)) = ((ph + de).sin_cos(), (om + ep).sin_cos());
    // the crank and coupler's part, common to the three loops
    let (cx, cy) = ([-rr * sibe + d * sibt, d * sibt], [rr * cobe - d * cobt, -d * cobt]);
    let mut g = [[0.0; 7]; 6];
    for k in 0..3 {
        g[2 * k][..2].copy_from_slice(&cx);
        g[2 * k + 1][..2].copy_from_slice(&cy);
    }
    (g[0][2], g[1][2]) = (-ss * coga, -ss * siga);
    (g[2][3], g[2][4]) = (-e * copd, -e * copd + zt * side);
    (g[3][3], g[3][4]) = (-e * sipd, -e * sipd - zt * code);
    (g[4][5], g[4][6]) = (zf * sioe, zf * sioe - u * coep);
    (g[5][5], g[5][6]) = (-zf * cooe, -zf * cooe - u * siep);
    let bt2 = (bp + tp).powi(2);
    let (ax, ay) = (-rr * cobe * bp * bp + d * cobt * bt2, -rr * sibe * bp * bp + d * sibt * bt2);
    let (pd2, oe2) = ((pp + dp).powi(2), (op + epp).powi(2));
    let curvature = [
        ax + ss * siga * gp * gp,
        ay - ss * coga * gp * gp,
        ax + e * sipd * pd2 + zt * code * dp * dp,
        ay - e * copd * pd2 + zt * side * dp * dp,
        ax + zf * cooe * oe2 + u * siep * epp * epp,
        ay + zf * sioe * oe2 - u * coep * epp * epp,
    ];
    (g, curvature)
}

/// `q''` of the test set's equations in index-1 form:
/// `[M G^T; G 0] [q''; lambda] = [f; -g''(q'' = 0)]`, by Gaussian elimination
/// with partial pivoting \[rad/s^2\].
fn accelerations(p: &Squeezer, q: &[f64; 7], v: &[f64; 7]) -> [f64; 7] {
    let (m, f) = (mass_matrix(p, q), forces(p, q, v));
    let (g, curvature) = closures(p, q, v);
    let mut a = [[0.0; 14]; 13];
    for i in 0..7 {
        a[i][..7].copy_from_slice(&m[i]);
        for j in 0..6 {
            a[i][7 + j] = g[j][i];
        }
        a[i][13] = f[i];
    }
    for j in 0..6 {
        a[7 + j][..7].copy_from_slice(&g[j]);
        a[7 + j][13] = -curvature[j];
    }
    for k in 0..13 {
        let pivot = (k..13).max_by(|&r, &s| a[r][k].abs().total_cmp(&a[s][k].abs())).unwrap_or(k);
        a.swap(k, pivot);
        let (done, rest) = a.split_at_mut(k + 1);
        let pivot_row = &done[k];
        for row in rest.iter_mut() {
            let factor = row[k] / pivot_row[k];
            for (x, p) in row[k..].iter_mut().zip(&pivot_row[k..]) {
                *x -= factor * p;
            }
        }
    }
    let mut x = [0.0; 13];
    for k in (0..13).rev() {
        let s: f64 = (k + 1..13).map(|c| a[k][c] * x[c]).sum();
        x[k] = (a[k][13] - s) / a[k][k];
    }
    std::array::from_fn(|i| x[i])
}

/// The classical Runge-Kutta method on `(q, q')` from rest at the test set's
/// initial angles to t = 0.03 s in `steps` steps: the seven angles \[rad\].
fn runge_kutta(p: &Squeezer, steps: usize) -> [f64; 7] {
    let h = END_TIME / steps as f64;
    let f = |y: &[f64; 14]| -> [f64; 14] {
        let (q, v) = (std::array::from_fn(|i| y[i]), std::array::from_fn(|i| y[7 + i]));
        let w = accelerations(p, &q, &v);
        std::array::from_fn(|i| if i < 7 { v[i] } else { w[i - 7] })
    };
    let mut y = [0.0; 14];
    y[..7].copy_from_slice(&INITIAL_ANGLES);
    for _ in 0..steps {
        let k1 = f(&y);
        let k2 = f(&std::array::from_fn(|i| y[i] + 0.5 * h * k1[i]));
        let k3 = f(&std::array::from_fn(|i| y[i] + 0.5 * h * k2[i]));
        let k4 = f(&std::array::from_fn(|i| y[i] + h * k3[i]));
        y = std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
    }
    std::array::from_fn(|i| y[i])
}

fn largest(d: impl Iterator<Item = f64>) -> f64 {
    d.map(f64::abs).fold(0.0, f64::max)
}

#[test]
fn the_transcribed_test_set_equations_give_its_initial_accelerations() {
    let w = accelerations(&Squeezer::default(), &INITIAL_ANGLES, &[0.0; 7]);
    eprintln!("initial accelerations {w:?} [rad/s^2]");
    for (k, published) in INITIAL_ACCELERATIONS.iter().enumerate() {
        assert!(
            (w[k] - published).abs() < 1e-11 * published.abs(),
            "{}'' = {} against {published}",
            ANGLE_NAMES[k],
            w[k]
        );
    }
    // (measured: at most 1.5e-13 rad/s^2, rounding against 1.4e4)
    assert!(largest(w[2..].iter().copied()) < 1e-11, "the other angles start at rest: {w:?}");
}

/// One row of the convergence study: the run at `rtol`, its largest
/// distance to the published angles and to the second method \[rad\].
fn study_row(mech: &Squeezer, rtol: f64, second: &[f64; 7]) -> (Run, f64, f64) {
    let start = std::time::Instant::now();
    let run = mech.simulate(andrews::options(rtol), END_TIME).unwrap();
    let to_published = largest(run.errors().into_iter());
    let to_second = largest((0..7).map(|k| run.angles[k] - second[k]));
    eprintln!(
        "rtol {rtol:.0e}: {:.3} s wall, {} steps ({} rejected, {} failed attempts); largest distance to the \
         published angles {to_published:.2e} rad, to the second method {to_second:.2e} rad",
        start.elapsed().as_secs_f64(),
        run.stats.steps,
        run.stats.rejected,
        run.stats.failed_attempts
    );
    for k in 0..7 {
        eprintln!(
            "    {:8} {:20.15} (published {:20.15}, error {:9.2e}; second method {:20.15})",
            ANGLE_NAMES[k],
            run.angles[k],
            REFERENCE_ANGLES[k],
            run.errors()[k],
            second[k]
        );
    }
    (run, to_published, to_second)
}

#[test]
fn the_squeezer_converges_to_the_published_angles() {
    let mech = Squeezer::default();
    let (second, halved) = (runge_kutta(&mech, 50_000), runge_kutta(&mech, 100_000));
    let own = largest((0..7).map(|k| second[k] - halved[k]));
    let published_off = largest((0..7).map(|k| halved[k] - REFERENCE_ANGLES[k]));
    eprintln!("second method: its step halved moves it {own:.1e} rad; the published angles are {published_off:.3e} rad off it");
    // (measured: 2e-12 rad; 1.43e-9 rad, Theta's)
    assert!(own < 1e-11, "the second method's own error {own:e} rad");
    assert!(published_off < BAND, "the published digits' own error {published_off:e} rad");

    let rows: Vec<_> = [1e-8, 1e-10, 1e-12].into_iter().map(|rtol| study_row(&mech, rtol, &halved)).collect();
    for pair in rows.windows(2) {
        let ((_, p0, s0), (_, p1, s1)) = (&pair[0], &pair[1]);
        // tolerance down 100 times: the error 41 and 45 times (measured)
        assert!(s1 * 10.0 < *s0, "the distance to the second method falls: {s0:e} then {s1:e} rad");
        assert!(p1 < p0, "the distance to the published angles falls: {p0:e} then {p1:e} rad");
    }
    let (run, _, to_second) = &rows[2];
    // (measured: 9.9e-11 rad at rtol 1e-12, Theta's)
    assert!(*to_second < 3e-10, "the solver's own error {to_second:e} rad");
    for (k, e) in run.errors().iter().enumerate() {
        assert!(e.abs() < BAND, "{} = {} rad, published {} rad", ANGLE_NAMES[k], run.angles[k], REFERENCE_ANGLES[k]);
    }
    // the chains A-H5-E and A-H7-E are mirror images
    assert!((run.angles[3] + run.angles[5]).abs() < 1e-12, "Omega = -Phi: {:?}", run.angles);
    assert!(largest((0..7).map(|k| run.start[k] - INITIAL_ANGLES[k])) < 1e-15, "the initial angles are consistent");
    assert!((run.t - END_TIME).abs() < 1e-15);
}

#[test]
fn the_torque_s_work_goes_into_kinetic_and_spring_energy() {
    let mech = Squeezer::default();
    let run = mech.simulate(andrews::options(1e-10), END_TIME).unwrap();
    let e = &run.energy;
    let work = mech.mom * (run.angles[0] - INITIAL_ANGLES[0]);
    // at rest at the start: the initial energy is the spring's
    let spring = e.potential - e.initial;
    eprintln!(
        "torque's work {:.9e} J (mom x beta turned {work:.9e} J), kinetic {:.6e} J, spring {:+.6e} J, balance error \
         {:.1e} of the energy scale; constraints held to {:.1e} m, {:.1e} m/s",
        e.applied,
        e.kinetic,
        spring,
        e.relative_error(),
        run.residuals.0,
        run.residuals.1
    );
    assert!((e.applied - work).abs() < 1e-9 * work, "applied work {} J, mom x angle {work} J", e.applied);
    assert!(e.relative_error() < 1e-8, "energy balance {:e}", e.relative_error());
}
