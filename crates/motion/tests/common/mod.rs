//! Helpers shared by the integration tests: where the PEER records are, and
//! an independent reference integrator (classical Runge-Kutta 4 with many
//! fixed sub-steps per sample interval).

#![allow(dead_code)]

use std::path::PathBuf;

use quakejoint_motion::{load_record, Record, RecordSpec};

/// `ground_motions/` at the repository root.
pub fn ground_motions() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../ground_motions")
}

/// Load one of the copied PEER records (m/s²).
pub fn peer(file: &str) -> Record {
    load_record(&RecordSpec::new(file), &ground_motions()).expect("PEER record loads").record
}

/// Peaks of |u|, |u'| and |ω²u + 2ζωu'| at the sample times.
#[derive(Debug, Clone, Copy)]
pub struct RefPeaks {
    pub sd: f64,
    pub sv: f64,
    pub sa: f64,
}

/// Classical RK4 on u'' = -a_g(t) - 2ζωu' - ω²u with a_g linear between
/// samples, `sub` equal steps per sample interval, starting at rest;
/// peaks taken at the sample times.
pub fn rk4_peaks(accel: &[f64], dt: f64, period: f64, zeta: f64, sub: usize) -> RefPeaks {
    let w = 2.0 * std::f64::consts::PI / period;
    let (w2, c) = (w * w, 2.0 * zeta * w);
    let h = dt / sub as f64;
    let f = |u: f64, v: f64, a: f64| (v, -a - c * v - w2 * u);
    let (mut u, mut v) = (0.0f64, 0.0f64);
    let mut p = RefPeaks { sd: 0.0, sv: 0.0, sa: 0.0 };
    for win in accel.windows(2) {
        let (a0, a1) = (win[0], win[1]);
        let slope = (a1 - a0) / dt;
        for k in 0..sub {
            let t = k as f64 * h;
            let ag0 = a0 + slope * t;
            let agm = a0 + slope * (t + 0.5 * h);
            let ag1 = a0 + slope * (t + h);
            let (k1u, k1v) = f(u, v, ag0);
            let (k2u, k2v) = f(u + 0.5 * h * k1u, v + 0.5 * h * k1v, agm);
            let (k3u, k3v) = f(u + 0.5 * h * k2u, v + 0.5 * h * k2v, agm);
            let (k4u, k4v) = f(u + h * k3u, v + h * k3v, ag1);
            u += h / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u);
            v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        }
        p.sd = p.sd.max(u.abs());
        p.sv = p.sv.max(v.abs());
        p.sa = p.sa.max((w2 * u + c * v).abs());
    }
    p
}

/// Relative difference |a - b| / |b|.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}
