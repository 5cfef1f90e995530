//! Test 5: limits of the spectrum on a real record (Corralitos 090).
//!
//! Short periods: the oscillator follows the ground, Sa -> PGA. For T > 0
//! the absolute acceleration lags the ground by about 2ζ·ȧ_g/ω and each
//! change of slope of the piecewise-linear record starts a free vibration
//! of acceleration amplitude at most |Δȧ_g|/ω <= 2·max|ȧ_g|/ω, so
//! |Sa - PGA| <= (2ζ + 2)·max|ȧ_g|/ω (ȧ_g = Δa/dt, the record's largest
//! slope). T = 0 exactly is the rigid oscillator: Sa = PGA, Sd = Sv = 0.
//!
//! Long periods: the mass stays put, u -> -d_g, so Sd -> PGD and
//! Sv -> PGV (ground motion integrated from rest, sample times, no baseline
//! correction). The neglected spring and damper forces give
//! |u + d_g| <= (ζω·PGV + ω²·PGD/2)·t² and |u' + v_g| <=
//! (2ζω·PGV + ω²·PGD)·t over the record's duration t; that bound is the
//! tolerance (relative to PGD, PGV), and it shrinks like 1/T.

mod common;

use common::peer;
use quakejoint_motion::{spectrum, RecordStats, SpectrumOptions};

#[test]
fn short_periods_give_pga() {
    let rec = peer("RSN753_LOMAP_CLS090-hor2.AT2");
    let stats = RecordStats::of(&rec);
    let max_slope = rec.acceleration.windows(2).map(|w| (w[1] - w[0]).abs() / rec.dt).fold(0.0, f64::max);
    let periods = [0.0, 1e-3, 1e-4, 1e-5];
    let dampings = [0.02, 0.05, 0.2];
    let rows = spectrum(&rec, &periods, &dampings, SpectrumOptions::default()).unwrap();
    for row in &rows {
        let p = row.peaks;
        if row.period == 0.0 {
            assert_eq!((p.sa, p.sd, p.sv, p.psa, p.psv), (stats.pga, 0.0, 0.0, stats.pga, 0.0));
            assert_eq!(p.t_sa, stats.t_pga);
            continue;
        }
        let w = 2.0 * std::f64::consts::PI / row.period;
        let bound = (2.0 * row.damping + 2.0) * max_slope / w;
        let err = (p.sa - stats.pga).abs();
        println!(
            "T = {:e} s zeta = {}: Sa/PGA - 1 = {:+.2e} (bound {:.2e})",
            row.period,
            row.damping,
            p.sa / stats.pga - 1.0,
            bound / stats.pga
        );
        assert!(err <= bound, "T = {}: |Sa - PGA| = {err:e} > {bound:e}", row.period);
    }
}

#[test]
fn long_periods_give_pgd() {
    let rec = peer("RSN753_LOMAP_CLS090-hor2.AT2");
    let s = RecordStats::of(&rec);
    let t = rec.duration();
    let periods = [1e4, 1e6, 1e8];
    let dampings = [0.0, 0.05, 0.2];
    let rows = spectrum(&rec, &periods, &dampings, SpectrumOptions::default()).unwrap();
    for row in &rows {
        let p = row.peaks;
        let w = 2.0 * std::f64::consts::PI / row.period;
        let z = row.damping;
        let bound_d = (z * w * s.pgv + 0.5 * w * w * s.pgd) * t * t;
        let bound_v = (2.0 * z * w * s.pgv + w * w * s.pgd) * t;
        println!(
            "T = {:e} s zeta = {z}: Sd/PGD - 1 = {:+.2e} (bound {:.1e}), Sv/PGV - 1 = {:+.2e} (bound {:.1e})",
            row.period,
            p.sd / s.pgd - 1.0,
            bound_d / s.pgd,
            p.sv / s.pgv - 1.0,
            bound_v / s.pgv
        );
        assert!((p.sd - s.pgd).abs() <= bound_d + 1e-12 * s.pgd, "T = {}: Sd {} PGD {}", row.period, p.sd, s.pgd);
        assert!((p.sv - s.pgv).abs() <= bound_v + 1e-12 * s.pgv, "T = {}: Sv {} PGV {}", row.period, p.sv, s.pgv);
        if row.period >= 1e8 {
            assert!((p.sd / s.pgd - 1.0).abs() < 1e-4);
            assert!((p.t_sd - s.t_pgd).abs() < 1e-9, "time of Sd {} vs PGD {}", p.t_sd, s.t_pgd);
        }
    }
}
