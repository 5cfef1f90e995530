//! The exact step of a linear single-degree-of-freedom oscillator under
//! piecewise-linear ground acceleration (Nigam & Jennings 1969), with
//! coefficients that keep full relative precision for any ω·dt.
//!
//! The oscillator `u'' + 2ζω u' + ω² u = -a_g(t)` with
//! `a_g(t_n + τ) = a_n + s τ`, `s = (a_{n+1} - a_n)/dt`, is the linear
//! autonomous system `z' = A z` for `z = (u, u', a, s)`:
//!
//! ```text
//!     | 0     1     0  0 |
//! A = | -ω²  -2ζω  -1  0 |
//!     | 0     0     0  1 |
//!     | 0     0     0  0 |
//! ```
//!
//! so one step is `z_{n+1} = exp(A·dt) z_n`, exact. The state is scaled
//! with a time unit `c` (`x = (u, c u', c² a, c³ s)`, `c = dt/L`,
//! `L = max(1, ω·dt)`) so that the matrix `K` whose exponential is taken has
//! entries of order one or of order ω·dt:
//!
//! ```text
//!     | 0       L      0  0 |
//! K = | -θ²/L  -2ζθ   -L  0 |     θ = ω·dt
//!     | 0       0      0  L |
//!     | 0       0      0  0 |
//! ```
//!
//! `exp(K) - I` is computed directly (never `exp(K)` followed by a
//! subtraction): a Taylor series of `K/2^s` (`‖K/2^s‖ <= 1/2`, 18 terms)
//! followed by `s` doublings `X <- 2X + X²`. Every entry, including the
//! diagonal deviations from one (of order θ² at long periods) and the load
//! coefficients (of order dt² and dt³), keeps relative precision: there is
//! no subtraction of nearly equal numbers, unlike the textbook closed form
//! whose load terms cancel to O(θ²) out of O(1/θ) parts. The step is then
//! taken in increment form, `u_{n+1} = u_n + (ΔA u_n + ...)`, so the
//! precision of the diagonal deviations reaches the response.

use crate::error::SpectrumError;

/// Coefficients of one exact step of length dt \[s\]:
///
/// ```text
/// u_{n+1} = u_n + a11m1·u_n + a12·v_n + b1·a_n + c1·a_{n+1}
/// v_{n+1} = v_n + a21·u_n + a22m1·v_n + b2·a_n + c2·a_{n+1}
/// ```
///
/// with u the relative displacement \[m\], v the relative velocity [m/s] and
/// a the ground acceleration [m/s²].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepCoefficients {
    /// A11 - 1 [-]
    pub a11m1: f64,
    /// A12 \[s\]
    pub a12: f64,
    /// load coefficient of a_n in u \[s²\]
    pub b1: f64,
    /// load coefficient of a_{n+1} in u \[s²\]
    pub c1: f64,
    /// A21 [1/s]
    pub a21: f64,
    /// A22 - 1 [-]
    pub a22m1: f64,
    /// load coefficient of a_n in v \[s\]
    pub b2: f64,
    /// load coefficient of a_{n+1} in v \[s\]
    pub c2: f64,
}

type M4 = [[f64; 4]; 4];

fn mul4(a: &M4, b: &M4) -> M4 {
    let mut c = [[0.0; 4]; 4];
    for i in 0..4 {
        for j in 0..4 {
            c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j] + a[i][3] * b[3][j];
        }
    }
    c
}

/// `exp(K) - I` by scaling and squaring of a Taylor series, with the
/// identity never added (relative precision of every entry is kept).
pub fn expm1_4(k: &M4) -> M4 {
    const TERMS: u32 = 18;
    let norm = k.iter().map(|row| row.iter().map(|x| x.abs()).sum::<f64>()).fold(0.0, f64::max);
    let mut s = 0i32;
    let mut scaled_norm = norm;
    while scaled_norm > 0.5 && s < 1100 {
        scaled_norm *= 0.5;
        s += 1;
    }
    let f = 0.5f64.powi(s);
    let mut ks = *k;
    ks.iter_mut().flatten().for_each(|x| *x *= f);
    // Horner: X = Ks (I + Ks/2 (I + Ks/3 (... (I + Ks/N))))
    //   p_N = Ks/N, p_j = (Ks/j)(I + p_{j+1}), X = Ks (I + p_2)
    let plus_identity = |mut m: M4| {
        for (i, row) in m.iter_mut().enumerate() {
            row[i] += 1.0;
        }
        m
    };
    let mut p = ks;
    p.iter_mut().flatten().for_each(|x| *x /= TERMS as f64);
    for j in (2..TERMS).rev() {
        p = mul4(&ks, &plus_identity(p));
        p.iter_mut().flatten().for_each(|x| *x /= j as f64);
    }
    let ip = plus_identity(p);
    let mut x = mul4(&ks, &ip);
    for _ in 0..s {
        let xx = mul4(&x, &x);
        for i in 0..4 {
            for j in 0..4 {
                x[i][j] = 2.0 * x[i][j] + xx[i][j];
            }
        }
    }
    x
}

/// Exact step coefficients for period `period` \[s\] (> 0), damping ratio
/// `damping` [-] and step `dt` \[s\]. Inputs are assumed valid.
pub fn step_coefficients(period: f64, damping: f64, dt: f64) -> StepCoefficients {
    let omega = 2.0 * std::f64::consts::PI / period;
    let theta = omega * dt;
    let l = theta.max(1.0);
    let c = dt / l;
    let k: M4 = [
        [0.0, l, 0.0, 0.0],
        [-theta * theta / l, -2.0 * damping * theta, -l, 0.0],
        [0.0, 0.0, 0.0, l],
        [0.0, 0.0, 0.0, 0.0],
    ];
    let x = expm1_4(&k);
    let cc = c * c;
    StepCoefficients {
        a11m1: x[0][0],
        a12: x[0][1] * c,
        b1: x[0][2] * cc - x[0][3] * cc / l,
        c1: x[0][3] * cc / l,
        a21: x[1][0] / c,
        a22m1: x[1][1],
        b2: x[1][2] * c - x[1][3] * c / l,
        c2: x[1][3] * c / l,
    }
}

/// Check an oscillator's parameters: period \[s\] finite and >= 0, damping
/// ratio [-] in [0, 1), time step \[s\] finite and > 0.
pub fn check_parameters(period: f64, damping: f64, dt: f64) -> Result<(), SpectrumError> {
    if !(period.is_finite() && (period == 0.0 || period >= MIN_PERIOD)) {
        return Err(SpectrumError::Period(period));
    }
    if !(damping.is_finite() && (0.0..1.0).contains(&damping)) {
        return Err(SpectrumError::Damping(damping));
    }
    if !(dt.is_finite() && dt > 0.0) {
        return Err(SpectrumError::Dt(dt));
    }
    Ok(())
}

/// The shortest positive period of an oscillator \[s\]: a microsecond, far
/// below any structure's (shorter ones overflow `w^2`; 0 is the rigid
/// oscillator, Sa = PGA).
pub const MIN_PERIOD: f64 = 1e-6;

/// A linear oscillator with its exact step for one time step: period T,
/// damping ratio ζ, time step dt. T = 0 is the rigid oscillator (it moves
/// with the ground: relative response zero, absolute acceleration a_g).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Oscillator {
    /// natural period T \[s\] (0: rigid)
    pub period: f64,
    /// damping ratio ζ [-]
    pub damping: f64,
    /// time step dt \[s\] of the step coefficients
    pub dt: f64,
    /// circular frequency ω = 2π/T [rad/s] (infinite for T = 0)
    pub omega: f64,
    /// exact step coefficients (None for T = 0)
    pub step: Option<StepCoefficients>,
}

impl Oscillator {
    /// Build the oscillator and its step; errors on invalid parameters
    /// (see [`check_parameters`]).
    pub fn new(period: f64, damping: f64, dt: f64) -> Result<Self, SpectrumError> {
        check_parameters(period, damping, dt)?;
        let omega = 2.0 * std::f64::consts::PI / period;
        let step = if period > 0.0 { Some(step_coefficients(period, damping, dt)) } else { None };
        Ok(Oscillator { period, damping, dt, omega, step })
    }

    /// ω² [1/s²]
    pub fn omega2(&self) -> f64 {
        self.omega * self.omega
    }
}

/// Raw peaks of one oscillator over a sample sequence: the largest |u|,
/// |v| and |a_abs| and the sample index where each first occurs.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct RawPeaks {
    pub u: f64,
    pub iu: usize,
    pub v: f64,
    pub iv: usize,
    pub a: f64,
    pub ia: usize,
}

/// Steps per block of the peak search in [`run_lanes`].
const BLOCK: usize = 64;

/// Coefficients of `L` lanes, one array per coefficient.
struct Lanes<const L: usize> {
    a11: [f64; L],
    a12: [f64; L],
    b1: [f64; L],
    c1: [f64; L],
    a21: [f64; L],
    a22: [f64; L],
    b2: [f64; L],
    c2: [f64; L],
    w2: [f64; L],
    tzw: [f64; L],
}

/// Step all lanes over `acc` (a block: `acc.len() - 1` steps) from (u, v),
/// returning the largest |u|, |v| and |a_abs| of each lane in the block.
/// Branch-free so that the lanes can share vector instructions.
#[inline(always)]
fn block_max<const L: usize>(
    k: &Lanes<L>,
    u: &mut [f64; L],
    v: &mut [f64; L],
    acc: &[f64],
) -> ([f64; L], [f64; L], [f64; L]) {
    let mut bu = [0.0f64; L];
    let mut bv = [0.0f64; L];
    let mut ba = [0.0f64; L];
    for w in acc.windows(2) {
        let (a0, a1) = (w[0], w[1]);
        for l in 0..L {
            let du = k.a11[l] * u[l] + k.a12[l] * v[l] + (k.b1[l] * a0 + k.c1[l] * a1);
            let dv = k.a21[l] * u[l] + k.a22[l] * v[l] + (k.b2[l] * a0 + k.c2[l] * a1);
            let un = u[l] + du;
            let vn = v[l] + dv;
            u[l] = un;
            v[l] = vn;
            let (au, av, aa) = (un.abs(), vn.abs(), (k.w2[l] * un + k.tzw[l] * vn).abs());
            bu[l] = if au > bu[l] { au } else { bu[l] };
            bv[l] = if av > bv[l] { av } else { bv[l] };
            ba[l] = if aa > ba[l] { aa } else { ba[l] };
        }
    }
    (bu, bv, ba)
}

/// Where a peak was found: its value, the first step of its block and the
/// lane's state at the start of that block.
#[derive(Clone, Copy, Default)]
struct Found {
    value: f64,
    block: usize,
    u: f64,
    v: f64,
}

/// The ground acceleration with `m` points per sample interval: linear
/// interpolation between samples, the samples themselves exact.
#[derive(Clone, Copy)]
pub(crate) struct Refined<'a> {
    acc: &'a [f64],
    m: usize,
}

impl<'a> Refined<'a> {
    /// `acc` must not be empty; `m` >= 1.
    pub(crate) fn new(acc: &'a [f64], m: usize) -> Self {
        Refined { acc, m: m.max(1) }
    }

    /// Number of steps ((samples - 1)·m).
    fn steps(&self) -> usize {
        self.acc.len().saturating_sub(1) * self.m
    }

    /// Points `start..=end` of the refined sequence: borrowed from the
    /// record for m = 1, else interpolated into `buf`.
    fn segment<'b>(&self, start: usize, end: usize, buf: &'b mut [f64; BLOCK + 1]) -> &'b [f64]
    where
        'a: 'b,
    {
        if self.m == 1 {
            return &self.acc[start..=end];
        }
        let m = self.m;
        for (slot, i) in buf.iter_mut().zip(start..=end) {
            let (n, k) = (i / m, i % m);
            *slot = if k == 0 {
                self.acc[n]
            } else {
                let f = k as f64 / m as f64;
                self.acc[n] * (1.0 - f) + self.acc[n + 1] * f
            };
        }
        &buf[..=end - start]
    }
}

/// First point index (from `found.block`) where the quantity `which`
/// (0: |u|, 1: |v|, 2: |a_abs|) equals `found.value`, re-running the
/// block from its stored state with the same arithmetic.
fn locate(s: &StepCoefficients, w2: f64, tzw: f64, acc: Refined<'_>, found: &Found, which: usize) -> usize {
    if found.value == 0.0 {
        return 0;
    }
    let (mut u, mut v) = (found.u, found.v);
    let end = (found.block + BLOCK).min(acc.steps());
    let mut buf = [0.0; BLOCK + 1];
    let seg = acc.segment(found.block, end, &mut buf);
    for (j, w) in seg.windows(2).enumerate() {
        (u, v) = step_once(s, u, v, w[0], w[1]);
        let x = match which {
            0 => u.abs(),
            1 => v.abs(),
            _ => (w2 * u + tzw * v).abs(),
        };
        if x == found.value {
            return found.block + j + 1;
        }
    }
    // not reached: the block is re-run with identical arithmetic
    found.block
}

/// Run `L` oscillators in lockstep over the (refined) ground acceleration
/// `acc`, starting at rest, and return their peaks and the first point
/// index of each. `w2` and `tzw` are ω²
/// and 2ζω of each lane. Lanes are independent; each does exactly the
/// arithmetic of a single run.
///
/// The hot loop only keeps running maxima per block of [`BLOCK`] steps;
/// when a block beats the lane's peak so far, the block's start and the
/// state there are kept, and at the end that one block is re-run to find
/// the sample of the peak.
pub(crate) fn run_lanes<const L: usize>(
    steps: &[StepCoefficients; L],
    w2: &[f64; L],
    tzw: &[f64; L],
    acc: Refined<'_>,
) -> [RawPeaks; L] {
    let k = Lanes {
        a11: steps.map(|s| s.a11m1),
        a12: steps.map(|s| s.a12),
        b1: steps.map(|s| s.b1),
        c1: steps.map(|s| s.c1),
        a21: steps.map(|s| s.a21),
        a22: steps.map(|s| s.a22m1),
        b2: steps.map(|s| s.b2),
        c2: steps.map(|s| s.c2),
        w2: *w2,
        tzw: *tzw,
    };
    let mut u = [0.0f64; L];
    let mut v = [0.0f64; L];
    let mut found = [[Found::default(); 3]; L];
    let n_steps = acc.steps();
    let mut buf = [0.0; BLOCK + 1];
    let mut start = 0;
    while start < n_steps {
        let end = (start + BLOCK).min(n_steps);
        let (u0, v0) = (u, v);
        let (bu, bv, ba) = block_max(&k, &mut u, &mut v, acc.segment(start, end, &mut buf));
        for l in 0..L {
            for (q, b) in [bu[l], bv[l], ba[l]].into_iter().enumerate() {
                if b > found[l][q].value {
                    found[l][q] = Found { value: b, block: start, u: u0[l], v: v0[l] };
                }
            }
        }
        start = end;
    }
    std::array::from_fn(|l| {
        let f = &found[l];
        let at = |q: usize| locate(&steps[l], w2[l], tzw[l], acc, &f[q], q);
        RawPeaks { u: f[0].value, iu: at(0), v: f[1].value, iv: at(1), a: f[2].value, ia: at(2) }
    })
}

/// One step of the oscillator from (u, v) under a_n -> a_{n+1}.
#[inline(always)]
pub(crate) fn step_once(s: &StepCoefficients, u: f64, v: f64, a0: f64, a1: f64) -> (f64, f64) {
    let du = s.a11m1 * u + s.a12 * v + (s.b1 * a0 + s.c1 * a1);
    let dv = s.a21 * u + s.a22m1 * v + (s.b2 * a0 + s.c2 * a1);
    (u + du, v + dv)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// exp of a nilpotent-free diagonal block: expm1 of diag(x) is expm1(x)
    #[test]
    fn expm1_of_diagonal_and_jordan_block() {
        for x in [1e-8, 1e-3, 0.4, 3.0, -20.0] {
            let k = [[x, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0], [0.0, 0.0, x, 1.0], [0.0, 0.0, 0.0, x]];
            let e = expm1_4(&k);
            let want = x.exp_m1();
            assert!((e[0][0] - want).abs() <= 4e-16 * want.abs(), "{x}: {} vs {want}", e[0][0]);
            assert_eq!(e[1][1], 0.0);
            // Jordan block: exp([[x,1],[0,x]]) = e^x [[1,1],[0,1]]; a
            // decaying exponential is accurate relative to the O(1) entries
            assert!((e[2][3] - x.exp()).abs() <= 1e-14 * x.exp().max(1.0), "{x}");
        }
    }

    /// undamped rotation: exp(θ[[0,1],[-1,0]]) = [[cos, sin],[-sin, cos]]
    #[test]
    fn expm1_of_rotation() {
        for th in [1e-6, 0.01, 1.0, 7.5, 100.0] {
            let k = [[0.0, th, 0.0, 0.0], [-th, 0.0, 0.0, 0.0], [0.0; 4], [0.0; 4]];
            let e = expm1_4(&k);
            let cm1 = -2.0 * (th / 2.0).sin().powi(2);
            let tol = 1e-15 * (1.0 + th);
            assert!((e[0][0] - cm1).abs() <= tol.max(4e-16 * cm1.abs()) * 4.0, "{th}: {} {cm1}", e[0][0]);
            assert!((e[0][1] - th.sin()).abs() <= 4.0 * tol, "{th}");
            assert!((e[1][0] + th.sin()).abs() <= 4.0 * tol, "{th}");
        }
    }
}
