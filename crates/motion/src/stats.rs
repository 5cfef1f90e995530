//! Summary statistics of a record: peaks of ground acceleration, velocity
//! and displacement, Arias intensity and significant duration.
//!
//! The ground acceleration is taken as linear between samples and the
//! ground starts at rest (v = d = 0 at the first sample), the same
//! convention as the spectra; velocity and displacement are integrated
//! exactly for that acceleration (no baseline correction, no filtering):
//!
//! ```text
//! v_{n+1} = v_n + dt (a_n + a_{n+1}) / 2
//! d_{n+1} = d_n + dt v_n + dt² (2 a_n + a_{n+1}) / 6
//! ```
//!
//! PGA, PGV and PGD are the largest absolute values at the sample times
//! (as for the spectra, so that Sd tends to PGD at long periods).
//! Arias intensity is `I_A = π/(2g) ∫ a² dt`, exact for piecewise-linear a
//! (`dt (a_n² + a_n a_{n+1} + a_{n+1}²) / 3` per interval); D5-95 is the
//! time between the instants where the running integral reaches 5 % and
//! 95 % of I_A, each found within its sample interval by solving the cubic
//! running integral (not a linear interpolation of it).

use crate::record::Record;
use crate::G;

/// Statistics of a record, SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecordStats {
    /// time step \[s\]
    pub dt: f64,
    /// number of samples
    pub samples: usize,
    /// duration (samples - 1)·dt \[s\]
    pub duration: f64,
    /// peak ground acceleration [m/s²]
    pub pga: f64,
    /// time of the PGA \[s\]
    pub t_pga: f64,
    /// peak ground velocity [m/s]
    pub pgv: f64,
    /// time of the PGV \[s\]
    pub t_pgv: f64,
    /// peak ground displacement \[m\]
    pub pgd: f64,
    /// time of the PGD \[s\]
    pub t_pgd: f64,
    /// Arias intensity π/(2g)·∫a² dt [m/s]
    pub arias: f64,
    /// significant duration D5-95 = t95 - t5 \[s\]
    pub d5_95: f64,
    /// time at which 5 % of the Arias intensity is reached \[s\]
    pub t5: f64,
    /// time at which 95 % of the Arias intensity is reached \[s\]
    pub t95: f64,
}

/// Index and value of the largest |x| (first occurrence; (0, 0) if empty).
fn peak(x: impl Iterator<Item = f64>) -> (usize, f64) {
    let mut best = (0, 0.0f64);
    for (i, v) in x.enumerate() {
        if v.abs() > best.1 {
            best = (i, v.abs());
        }
    }
    best
}

impl RecordStats {
    /// Statistics of `record` (which should be valid, see [`Record::new`];
    /// an empty record gives zeros).
    pub fn of(record: &Record) -> Self {
        let a = &record.acceleration;
        let h = record.dt;
        let n = a.len();
        let (ia, pga) = peak(a.iter().copied());

        // exact integration of the piecewise-linear acceleration
        let (mut v, mut d) = (0.0f64, 0.0f64);
        let (mut pgv, mut ipv, mut pgd, mut ipd) = (0.0f64, 0usize, 0.0f64, 0usize);
        // running Arias integral ∫a² dt at the sample times (without π/2g)
        let mut cum = Vec::with_capacity(n);
        let mut c = 0.0f64;
        cum.push(c);
        for (i, w) in a.windows(2).enumerate() {
            let (a0, a1) = (w[0], w[1]);
            d += h * v + h * h * (2.0 * a0 + a1) / 6.0;
            v += h * (a0 + a1) / 2.0;
            c += h * (a0 * a0 + a0 * a1 + a1 * a1) / 3.0;
            cum.push(c);
            if v.abs() > pgv {
                pgv = v.abs();
                ipv = i + 1;
            }
            if d.abs() > pgd {
                pgd = d.abs();
                ipd = i + 1;
            }
        }
        let total = c;
        let (t5, t95) = if total > 0.0 {
            (crossing(a, h, &cum, 0.05 * total), crossing(a, h, &cum, 0.95 * total))
        } else {
            (0.0, 0.0)
        };
        RecordStats {
            dt: h,
            samples: n,
            duration: record.duration(),
            pga,
            t_pga: ia as f64 * h,
            pgv,
            t_pgv: ipv as f64 * h,
            pgd,
            t_pgd: ipd as f64 * h,
            arias: std::f64::consts::PI / (2.0 * G) * total,
            d5_95: t95 - t5,
            t5,
            t95,
        }
    }
}

/// First time \[s\] at which the running integral of a² reaches `target`
/// (0 < target <= total), solving the cubic within the sample interval.
fn crossing(a: &[f64], h: f64, cum: &[f64], target: f64) -> f64 {
    // first k with cum[k + 1] >= target
    let k = cum.partition_point(|&c| c < target).saturating_sub(1).min(a.len().saturating_sub(2));
    if a.len() < 2 {
        return 0.0;
    }
    let (a0, a1) = (a[k], a[k + 1]);
    let s = (a1 - a0) / h;
    let f = |tau: f64| cum[k] + a0 * a0 * tau + a0 * s * tau * tau + s * s * tau * tau * tau / 3.0;
    // the running integral is nondecreasing: bisection on [0, h]
    let (mut lo, mut hi) = (0.0f64, h);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if f(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    k as f64 * h + 0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_and_shortest_records() {
        let r = Record::new("z", 0.01, vec![0.0; 10]).unwrap();
        let s = RecordStats::of(&r);
        assert_eq!((s.pga, s.pgv, s.pgd, s.arias, s.d5_95), (0.0, 0.0, 0.0, 0.0, 0.0));
        // a single sample has no duration: not a record
        assert!(Record::new("one", 0.01, vec![1.0]).is_err());
        let r = Record::new("two", 0.01, vec![1.0, 1.0]).unwrap();
        let s = RecordStats::of(&r);
        assert_eq!((s.samples, s.duration, s.pga), (2, 0.01, 1.0));
    }
}
