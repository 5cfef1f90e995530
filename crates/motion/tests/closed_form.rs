//! Test 2: against closed forms.
//!
//! - Steady harmonic response at resonance: a long record a_g = a0 sin(ωt)
//!   (1000 samples per cycle) at the oscillator's own period gives relative
//!   displacement amplitude a0/(2ζω²) and absolute acceleration amplitude
//!   a0·sqrt(1 + 4ζ²)/(2ζ), times sinc²(ωdt/2) = 1 - 3.3e-6: the
//!   fundamental of the piecewise-linear interpolant of the sampled sine
//!   (the record the oscillator actually sees). Tolerances: 6e-6 for
//!   amplitudes read at the sample times (a crest can fall between samples:
//!   up to 1 - cos(ωdt/2) = 4.9e-6 low), 5e-7 for peaks read with 8
//!   subdivisions per interval (7.7e-8); transients have decayed to e^-30.
//! - PGV, PGD, Arias intensity and D5-95 of piecewise-linear records whose
//!   integrals are known in closed form (a ramp, a triangular pulse).

mod common;

use std::f64::consts::PI;

use common::rel;
use quakejoint_motion::{history, peaks, Record, RecordStats, SpectrumOptions, G};

fn harmonic(a0: f64, period: f64, per_cycle: usize, cycles: usize) -> (Vec<f64>, f64) {
    let dt = period / per_cycle as f64;
    let w = 2.0 * PI / period;
    ((0..=per_cycle * cycles).map(|i| a0 * (w * i as f64 * dt).sin()).collect(), dt)
}

#[test]
fn resonance_amplitudes() {
    let (period, a0) = (1.0, 1.5);
    let w = 2.0 * PI / period;
    for zeta in [0.02, 0.05, 0.2] {
        // transients decay as exp(-ζωt): 30 e-foldings
        let cycles = (30.0 / (zeta * w * period)).ceil() as usize + 2;
        let (acc, dt) = harmonic(a0, period, 1000, cycles);
        let h = history(&acc, dt, period, zeta);
        let last_two = acc.len() - 2000..acc.len();
        let u_amp = h.u[last_two.clone()].iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let a_amp = h.a_abs[last_two].iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let x = w * dt / 2.0;
        let sinc2 = (x.sin() / x).powi(2);
        let u_exact = a0 / (2.0 * zeta * w * w) * sinc2;
        let a_exact = a0 * (1.0 + 4.0 * zeta * zeta).sqrt() / (2.0 * zeta) * sinc2;
        println!(
            "zeta = {zeta}: w²·u_amp/a0 = {:.7} (sinc²/(2ζ) = {:.7}), a_amp/a0 = {:.7} (exact {:.7})",
            w * w * u_amp / a0,
            sinc2 / (2.0 * zeta),
            a_amp / a0,
            a_exact / a0
        );
        assert!(rel(u_amp, u_exact) < 6e-6, "zeta {zeta}: {}", rel(u_amp, u_exact));
        assert!(rel(a_amp, a_exact) < 6e-6, "zeta {zeta}: {}", rel(a_amp, a_exact));

        // the spectrum's peak over the whole record: at resonance the
        // response builds up towards the steady amplitude, so Sd ω²/a0 tends
        // to 1/(2ζ) (subdivided to read the crest between samples)
        let p = peaks(&acc, dt, period, zeta, SpectrumOptions { subdivisions: 8 });
        println!("   peaks: w²·Sd/a0 = {:.7}, Sa/a0 = {:.7}", w * w * p.sd / a0, p.sa / a0);
        println!(
            "   relative errors: u_amp {:.1e} a_amp {:.1e} Sd {:.1e} Sa {:.1e}",
            rel(u_amp, u_exact),
            rel(a_amp, a_exact),
            rel(p.sd, u_exact),
            rel(p.sa, a_exact)
        );
        assert!(rel(p.sd, u_exact) < 5e-7, "zeta {zeta}: Sd {}", rel(p.sd, u_exact));
        assert!(rel(p.sa, a_exact) < 5e-7, "zeta {zeta}: Sa {}", rel(p.sa, a_exact));
        assert!(rel(p.psa, w * w * p.sd) < 1e-15 && rel(p.psv, w * p.sd) < 1e-15);
    }
}

#[test]
fn ramp_statistics() {
    // a = k t for 0 <= t <= T: v = k t²/2, d = k t³/6, ∫a² = k² T³/3,
    // running Arias ∝ t³, so t_x = T x^(1/3)
    let (k, dt, n) = (0.7, 0.01, 2001);
    let acc: Vec<f64> = (0..n).map(|i| k * (i as f64 * dt)).collect();
    let rec = Record::new("ramp", dt, acc).unwrap();
    let s = RecordStats::of(&rec);
    let t = (n - 1) as f64 * dt;
    assert_eq!(s.samples, n);
    assert!(rel(s.duration, t) < 1e-14);
    assert!(rel(s.pga, k * t) < 1e-14);
    assert!(rel(s.pgv, k * t * t / 2.0) < 1e-12, "PGV {}", s.pgv);
    assert!(rel(s.pgd, k * t.powi(3) / 6.0) < 1e-12, "PGD {}", s.pgd);
    assert!(rel(s.arias, PI / (2.0 * G) * k * k * t.powi(3) / 3.0) < 1e-12, "Arias {}", s.arias);
    let (t5, t95) = (t * 0.05f64.cbrt(), t * 0.95f64.cbrt());
    assert!((s.t5 - t5).abs() < 1e-9 && (s.t95 - t95).abs() < 1e-9, "{} {}", s.t5, s.t95);
    assert!((s.d5_95 - (t95 - t5)).abs() < 1e-9);
    assert_eq!((s.t_pga, s.t_pgv, s.t_pgd), (t, t, t));
}

#[test]
fn triangular_pulse_statistics() {
    // triangle of height A from 0 to 2·t1 (peak at t1), then zero until T:
    // v = A t1 after the pulse, d(2 t1) = A t1², then d grows linearly:
    // d(T) = A t1² + A t1 (T - 2 t1); ∫a² = 2 A² t1 / 3.
    let (amp, dt, m, n) = (2.5, 0.02, 50usize, 1001usize);
    let t1 = m as f64 * dt;
    let acc: Vec<f64> = (0..n)
        .map(|i| {
            let i = i.min(2 * m);
            amp * (1.0 - (i as f64 - m as f64).abs() / m as f64)
        })
        .collect();
    let rec = Record::new("triangle", dt, acc).unwrap();
    let s = RecordStats::of(&rec);
    let t = (n - 1) as f64 * dt;
    assert!(rel(s.pga, amp) < 1e-15);
    assert!((s.t_pga - t1).abs() < 1e-12);
    assert!(rel(s.pgv, amp * t1) < 1e-12, "PGV {}", s.pgv);
    assert!(rel(s.pgd, amp * t1 * t1 + amp * t1 * (t - 2.0 * t1)) < 1e-12, "PGD {}", s.pgd);
    assert!(rel(s.arias, PI / (2.0 * G) * 2.0 * amp * amp * t1 / 3.0) < 1e-12, "Arias {}", s.arias);
    // running integral on the rising half: A²t³/(3 t1²); 5 % of the total
    // (2A²t1/3) is reached at t = t1·0.1^(1/3); 95 % symmetrically
    let t5 = t1 * 0.1f64.cbrt();
    let t95 = 2.0 * t1 - t1 * 0.1f64.cbrt();
    assert!((s.t5 - t5).abs() < 1e-9 && (s.t95 - t95).abs() < 1e-9, "{} {}", s.t5, s.t95);
}
