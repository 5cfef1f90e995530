//! Precision at long periods and small time steps (ω·dt down to 3e-4).
//!
//! Reference: the textbook closed-form step (Nigam & Jennings 1969, in the
//! form of Chopra, Dynamics of Structures, table 5.2.1) evaluated in
//! double-double arithmetic (about 32 digits), where its cancellations
//! (load terms of order θ² assembled from parts of order 1/θ, θ = ω·dt)
//! still leave more than 20 digits. Checked: every step coefficient of the
//! crate (computed in f64 from the matrix exponential) to 2e-15 relative,
//! and the whole response to a real record (Sd, Sv, Sa) against a
//! double-double run of the closed-form recurrence, to 1e-13 relative.

mod common;

use std::ops::{Add, Div, Mul, Neg, Sub};

use common::{peer, rel};
use quakejoint_motion::oscillator::StepCoefficients;
use quakejoint_motion::{peaks, Oscillator, SpectrumOptions};

/// Double-double number hi + lo (|lo| <= ulp(hi)/2).
#[derive(Debug, Clone, Copy)]
struct Dd(f64, f64);

fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

fn quick_two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    Dd(s, b - (s - a))
}

impl Dd {
    fn f(x: f64) -> Dd {
        Dd(x, 0.0)
    }
    fn to_f64(self) -> f64 {
        self.0 + self.1
    }
    fn sqrt(self) -> Dd {
        let y = Dd::f(self.0.sqrt());
        y + (self - y * y) / (y * Dd::f(2.0))
    }
    /// Taylor series; for |x| < 1
    fn exp(self) -> Dd {
        let (mut sum, mut term) = (Dd::f(1.0), Dd::f(1.0));
        for k in 1..60 {
            term = term * self / Dd::f(k as f64);
            sum = sum + term;
            if term.0.abs() < 1e-36 {
                break;
            }
        }
        sum
    }
    /// (sin x, cos x) by Taylor series; for |x| < 1
    fn sin_cos(self) -> (Dd, Dd) {
        let x2 = self * self;
        let (mut s, mut ts) = (self, self);
        let (mut c, mut tc) = (Dd::f(1.0), Dd::f(1.0));
        for k in 1..40 {
            let k = k as f64;
            ts = -(ts * x2) / Dd::f((2.0 * k) * (2.0 * k + 1.0));
            tc = -(tc * x2) / Dd::f((2.0 * k - 1.0) * (2.0 * k));
            s = s + ts;
            c = c + tc;
            if ts.0.abs() < 1e-36 && tc.0.abs() < 1e-36 {
                break;
            }
        }
        (s, c)
    }
}

impl Add for Dd {
    type Output = Dd;
    fn add(self, o: Dd) -> Dd {
        let (s, e) = two_sum(self.0, o.0);
        let (t, f) = two_sum(self.1, o.1);
        let r = quick_two_sum(s, e + t);
        quick_two_sum(r.0, r.1 + f)
    }
}
impl Neg for Dd {
    type Output = Dd;
    fn neg(self) -> Dd {
        Dd(-self.0, -self.1)
    }
}
impl Sub for Dd {
    type Output = Dd;
    fn sub(self, o: Dd) -> Dd {
        self + (-o)
    }
}
impl Mul for Dd {
    type Output = Dd;
    fn mul(self, o: Dd) -> Dd {
        let p = self.0 * o.0;
        let e = self.0.mul_add(o.0, -p);
        quick_two_sum(p, e + (self.0 * o.1 + self.1 * o.0))
    }
}
impl Div for Dd {
    type Output = Dd;
    fn div(self, o: Dd) -> Dd {
        let q1 = self.0 / o.0;
        let r = self - o * Dd::f(q1);
        let q2 = r.0 / o.0;
        let r = r - o * Dd::f(q2);
        let q3 = r.0 / o.0;
        quick_two_sum(q1, q2) + Dd::f(q3)
    }
}

const PI: Dd = Dd(std::f64::consts::PI, 1.224_646_799_147_353_2e-16);

/// Closed-form step coefficients (Chopra table 5.2.1 with k = ω², p = -a_g)
/// in the crate's layout, in double-double.
struct DdStep {
    a11m1: Dd,
    a12: Dd,
    b1: Dd,
    c1: Dd,
    a21: Dd,
    a22m1: Dd,
    b2: Dd,
    c2: Dd,
    w2: Dd,
    tzw: Dd,
}

fn closed_form(period: f64, zeta: f64, dt: f64) -> DdStep {
    let one = Dd::f(1.0);
    let two = Dd::f(2.0);
    let (z, h) = (Dd::f(zeta), Dd::f(dt));
    let w = two * PI / Dd::f(period);
    let k = w * w;
    let sq = (one - z * z).sqrt();
    let wd = w * sq;
    let e = (-(z * w * h)).exp();
    let (s, c) = (wd * h).sin_cos();
    let a = e * (z / sq * s + c);
    let b = e * (s / wd);
    let cc =
        (two * z / (w * h) + e * (((one - two * z * z) / (wd * h) - z / sq) * s - (one + two * z / (w * h)) * c)) / k;
    let d = (one - two * z / (w * h) + e * ((two * z * z - one) / (wd * h) * s + two * z / (w * h) * c)) / k;
    let ap = -(e * (w / sq * s));
    let bp = e * (c - z / sq * s);
    let cp = (-(one / h) + e * ((w / sq + z / (h * sq)) * s + one / h * c)) / k;
    let dp = (one - e * (z / sq * s + c)) / (k * h);
    DdStep {
        a11m1: a - one,
        a12: b,
        b1: -cc,
        c1: -d,
        a21: ap,
        a22m1: bp - one,
        b2: -cp,
        c2: -dp,
        w2: k,
        tzw: two * z * w,
    }
}

/// The same closed form in plain f64 (the textbook way), for comparison.
fn closed_form_f64(period: f64, z: f64, h: f64) -> StepCoefficients {
    let w = 2.0 * std::f64::consts::PI / period;
    let k = w * w;
    let sq = (1.0 - z * z).sqrt();
    let wd = w * sq;
    let e = (-z * w * h).exp();
    let (s, c) = (wd * h).sin_cos();
    let cc =
        (2.0 * z / (w * h) + e * (((1.0 - 2.0 * z * z) / (wd * h) - z / sq) * s - (1.0 + 2.0 * z / (w * h)) * c)) / k;
    let d = (1.0 - 2.0 * z / (w * h) + e * ((2.0 * z * z - 1.0) / (wd * h) * s + 2.0 * z / (w * h) * c)) / k;
    let cp = (-1.0 / h + e * ((w / sq + z / (h * sq)) * s + c / h)) / k;
    let dp = (1.0 - e * (z / sq * s + c)) / (k * h);
    StepCoefficients {
        a11m1: e * (z / sq * s + c) - 1.0,
        a12: e * s / wd,
        b1: -cc,
        c1: -d,
        a21: -e * w / sq * s,
        a22m1: e * (c - z / sq * s) - 1.0,
        b2: -cp,
        c2: -dp,
    }
}

fn as_array(s: &StepCoefficients) -> [f64; 8] {
    [s.a11m1, s.a12, s.b1, s.c1, s.a21, s.a22m1, s.b2, s.c2]
}

fn dd_array(s: &DdStep) -> [f64; 8] {
    [s.a11m1, s.a12, s.b1, s.c1, s.a21, s.a22m1, s.b2, s.c2].map(Dd::to_f64)
}

#[test]
fn step_coefficients_keep_full_precision() {
    let dt = 0.005;
    let mut worst = 0.0f64;
    for period in [2.0, 10.0, 20.0, 100.0] {
        for zeta in [0.0, 0.02, 0.05, 0.2] {
            let reference = dd_array(&closed_form(period, zeta, dt));
            let ours = as_array(&Oscillator::new(period, zeta, dt).unwrap().step.unwrap());
            let naive = as_array(&closed_form_f64(period, zeta, dt));
            let err = |c: &[f64; 8]| c.iter().zip(&reference).map(|(a, b)| rel(*a, *b)).fold(0.0, f64::max);
            let (e_ours, e_naive) = (err(&ours), err(&naive));
            println!("T = {period:5} s zeta = {zeta:4}: largest relative error, matrix exponential {e_ours:.1e}, textbook f64 {e_naive:.1e}");
            assert!(e_ours < 2e-15, "T = {period}, zeta = {zeta}: {e_ours:e}");
            worst = worst.max(e_ours);
        }
    }
    println!("worst: {worst:.1e}");
}

/// Peaks (Sd, Sv, Sa) of the double-double closed-form recurrence.
fn dd_peaks(accel: &[f64], dt: f64, period: f64, zeta: f64) -> (f64, f64, f64) {
    let s = closed_form(period, zeta, dt);
    let (mut u, mut v) = (Dd::f(0.0), Dd::f(0.0));
    let (mut sd, mut sv, mut sa) = (0.0f64, 0.0f64, 0.0f64);
    for w in accel.windows(2) {
        let (a0, a1) = (Dd::f(w[0]), Dd::f(w[1]));
        let un = u + s.a11m1 * u + s.a12 * v + s.b1 * a0 + s.c1 * a1;
        let vn = v + s.a21 * u + s.a22m1 * v + s.b2 * a0 + s.c2 * a1;
        u = un;
        v = vn;
        sd = sd.max(u.to_f64().abs());
        sv = sv.max(v.to_f64().abs());
        sa = sa.max((s.w2 * u + s.tzw * v).to_f64().abs());
    }
    (sd, sv, sa)
}

#[test]
fn long_period_response_matches_double_double() {
    let rec = peer("RSN753_LOMAP_CLS090-hor2.AT2");
    for period in [10.0, 20.0] {
        for zeta in [0.0, 0.05] {
            let (sd, sv, sa) = dd_peaks(&rec.acceleration, rec.dt, period, zeta);
            let p = peaks(&rec.acceleration, rec.dt, period, zeta, SpectrumOptions::default());
            let errs = [rel(p.sd, sd), rel(p.sv, sv), rel(p.sa, sa)];
            println!("T = {period} s zeta = {zeta}: Sd {sd:.9e} Sv {sv:.9e} Sa {sa:.9e}; relative errors {:.1e} {:.1e} {:.1e}", errs[0], errs[1], errs[2]);
            for e in errs {
                assert!(e < 1e-13, "T = {period}, zeta = {zeta}: {e:e}");
            }
        }
    }
}
