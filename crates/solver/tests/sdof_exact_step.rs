//! Linear single-DOF oscillator under piecewise-linear base acceleration.
//!
//! Between two samples of the record the ground acceleration is linear in
//! time, so the oscillator `u'' + 2 zeta w u' + w^2 u = -a_g(t)` has an exact
//! step (Nigam and Jennings 1969). Here that step is computed independently
//! of the solver as the matrix exponential of the augmented linear system
//! `(u, u', a_j, slope)`, and the peak absolute acceleration
//! `|u'' + a_g| = |w^2 u + 2 zeta w u'|` over the sample times is compared
//! with the multibody solver's (a body restricted to x on a coordinate spring
//! and damper, loaded by `-m a_g`) at tight tolerances. The steps alternate
//! between a few sizes between samples, so the comparison also covers the
//! factorisations the integrator takes back instead of repeating.

use std::f64::consts::PI;
use std::sync::Arc;

use quakejoint_solver::reference::sdof;
use quakejoint_solver::*;

/// exp(A) for a 4x4 matrix by scaling and squaring of the Taylor series.
fn expm4(a: [[f64; 4]; 4]) -> [[f64; 4]; 4] {
    let norm = a.iter().map(|r| r.iter().map(|x| x.abs()).sum::<f64>()).fold(0.0, f64::max);
    let squarings = (norm.log2().ceil().max(0.0) as i32) + 4;
    let scale = 0.5f64.powi(squarings);
    let mul = |x: &[[f64; 4]; 4], y: &[[f64; 4]; 4]| {
        let mut z = [[0.0; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                for k in 0..4 {
                    z[i][j] += x[i][k] * y[k][j];
                }
            }
        }
        z
    };
    let mut s = [[0.0; 4]; 4];
    let mut term = [[0.0; 4]; 4];
    for i in 0..4 {
        s[i][i] = 1.0;
        term[i][i] = 1.0;
    }
    let mut x = a;
    for r in x.iter_mut() {
        for v in r.iter_mut() {
            *v *= scale;
        }
    }
    for k in 1..20 {
        term = mul(&term, &x);
        for r in term.iter_mut() {
            for v in r.iter_mut() {
                *v /= k as f64;
            }
        }
        for i in 0..4 {
            for j in 0..4 {
                s[i][j] += term[i][j];
            }
        }
    }
    for _ in 0..squarings {
        s = mul(&s, &s);
    }
    s
}

/// Exact peak absolute acceleration at the sample times.
fn exact_sa(period: f64, zeta: f64, dt: f64, ag: &[f64]) -> f64 {
    let w = 2.0 * PI / period;
    let a = [[0.0, 1.0, 0.0, 0.0], [-w * w, -2.0 * zeta * w, -1.0, 0.0], [0.0, 0.0, 0.0, 1.0], [0.0; 4]];
    let mut adt = a;
    for r in adt.iter_mut() {
        for v in r.iter_mut() {
            *v *= dt;
        }
    }
    let e = expm4(adt);
    let (mut u, mut v) = (0.0, 0.0);
    let mut sa = 0.0f64;
    for j in 0..ag.len() - 1 {
        let x = [u, v, ag[j], (ag[j + 1] - ag[j]) / dt];
        let un = e[0].iter().zip(&x).map(|(a, b)| a * b).sum::<f64>();
        let vn = e[1].iter().zip(&x).map(|(a, b)| a * b).sum::<f64>();
        u = un;
        v = vn;
        sa = sa.max((w * w * u + 2.0 * zeta * w * v).abs());
    }
    sa
}

/// A synthetic strong-motion-like record: a few harmonics with an envelope.
fn record(dt: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|j| {
            let t = j as f64 * dt;
            let env = (t / 2.0).min(1.0) * (-((t - 6.0).max(0.0)) / 4.0).exp();
            env * (3.0 * (2.0 * PI * 0.7 * t + 0.3).sin()
                + 2.0 * (2.0 * PI * 1.9 * t + 1.1).sin()
                + 1.5 * (2.0 * PI * 4.3 * t + 2.0).sin()
                + 0.8 * (2.0 * PI * 11.0 * t).sin())
        })
        .collect()
}

struct PeakAbsAcc {
    x: usize,
    k: f64,
    c: f64,
    mass: f64,
    dt: f64,
    sa: f64,
    samples: usize,
}

impl Observer for PeakAbsAcc {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        let j = (view.t / self.dt).round();
        if (view.t - j * self.dt).abs() < 1e-9 * self.dt {
            let a_abs = (-self.k * view.q[self.x] - self.c * view.v[self.x]) / self.mass;
            self.sa = self.sa.max(a_abs.abs());
            self.samples += 1;
        }
        true
    }
}

#[test]
fn sdof_peak_absolute_acceleration_matches_the_exact_piecewise_linear_step() {
    let dt = 0.01;
    let ag = record(dt, 1500);
    let mass = 1.0;
    let mut taken_back = 0;
    for &(period, zeta) in &[(0.2, 0.05), (1.0, 0.02), (1.0, 0.05), (3.0, 0.2)] {
        let w = 2.0 * PI / period;
        let series = TimeSeries::uniform(0.0, dt, ag.clone()).unwrap();
        let (sys, body) = sdof(mass, period, zeta, series);
        let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
        let x = asm.coordinate(body, Coord::X).unwrap();
        let opts = IntegratorOptions::default().scaled_tolerances(1e-3);
        let mut sim = Radau5::new(asm, opts).unwrap();
        let mut obs = PeakAbsAcc { x, k: mass * w * w, c: 2.0 * zeta * mass * w, mass, dt, sa: 0.0, samples: 0 };
        sim.run((ag.len() - 1) as f64 * dt, &mut obs).unwrap();
        assert_eq!(obs.samples, ag.len() - 1, "every sample time is a step");
        let exact = exact_sa(period, zeta, dt, &ag);
        let rel = (obs.sa - exact).abs() / exact;
        eprintln!(
            "T={period} zeta={zeta}: Sa {:.9} exact {exact:.9} rel {rel:.1e}, {} steps, {} factorisations, {} taken back",
            obs.sa,
            sim.stats().steps,
            sim.stats().factorizations,
            sim.stats().factorizations_reused
        );
        assert!(rel < 1e-6, "T={period} zeta={zeta}: Sa {} vs exact {exact} ({rel:e})", obs.sa);
        taken_back += sim.stats().factorizations_reused;
    }
    assert!(taken_back > 0, "no factorisation was taken back: the reuse path went untested");
}
