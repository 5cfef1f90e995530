//! The public API's shapes and conventions: period grids, row order,
//! rigid oscillators inside a spectrum, subdivisions, histories, damping
//! ratios near 1.

mod common;

use common::{peer, rel, rk4_peaks};
use quakejoint_motion::{history, peaks, period_range, spectrum, Oscillator, Record, SpectrumOptions};

#[test]
fn period_grids() {
    let p = period_range(0.02, 10.0, 60, true).unwrap();
    assert_eq!((p.len(), p[0], p[59]), (60, 0.02, 10.0));
    let ratio = (10.0f64 / 0.02).powf(1.0 / 59.0);
    for w in p.windows(2) {
        assert!(rel(w[1] / w[0], ratio) < 1e-12);
    }
    let p = period_range(0.0, 2.0, 5, false).unwrap();
    assert_eq!(p, vec![0.0, 0.5, 1.0, 1.5, 2.0]);
    assert_eq!(period_range(1.0, 1.0, 1, true).unwrap(), vec![1.0]);
}

#[test]
fn rows_are_damping_major_with_rigid_oscillators_mixed_in() {
    let rec = peer("RSN1690_NORTH151_SYL090-hor1.AT2");
    let periods = [0.0, 0.1, 0.5, 1.0, 0.0, 2.0, 4.0];
    let dampings = [0.0, 0.05, 0.3];
    let rows = spectrum(&rec, &periods, &dampings, SpectrumOptions::default()).unwrap();
    assert_eq!(rows.len(), 21);
    for (k, row) in rows.iter().enumerate() {
        let (t, z) = (periods[k % 7], dampings[k / 7]);
        assert_eq!((row.period, row.damping), (t, z));
        // each row equals the single-oscillator computation
        assert_eq!(row.peaks, peaks(&rec.acceleration, rec.dt, t, z, SpectrumOptions::default()));
        if t == 0.0 {
            assert_eq!(row.peaks.sa, rec.pga());
        } else {
            let w = 2.0 * std::f64::consts::PI / t;
            assert_eq!(row.peaks.psa, w * w * row.peaks.sd);
            assert_eq!(row.peaks.psv, w * row.peaks.sd);
        }
    }
}

#[test]
fn subdivisions_equal_a_linearly_refined_record() {
    let rec = peer("RSN1690_NORTH151_SYL360-hor2.AT2");
    let m = 7usize;
    // refine by hand: the ground acceleration is linear between samples
    let mut fine = Vec::new();
    for w in rec.acceleration.windows(2) {
        for k in 0..m {
            fine.push(w[0] + (w[1] - w[0]) * k as f64 / m as f64);
        }
    }
    fine.push(*rec.acceleration.last().unwrap());
    for (t, z) in [(0.1, 0.05), (1.0, 0.02), (3.0, 0.0)] {
        let sub = peaks(&rec.acceleration, rec.dt, t, z, SpectrumOptions { subdivisions: m as u32 });
        let by_hand = peaks(&fine, rec.dt / m as f64, t, z, SpectrumOptions::default());
        let coarse = peaks(&rec.acceleration, rec.dt, t, z, SpectrumOptions::default());
        for (a, b) in [(sub.sa, by_hand.sa), (sub.sv, by_hand.sv), (sub.sd, by_hand.sd)] {
            assert!(rel(a, b) < 1e-12, "T = {t}: {a} vs {b}");
        }
        assert!((sub.t_sa - by_hand.t_sa).abs() < 1e-9);
        assert!(sub.sa >= coarse.sa * (1.0 - 1e-14) && sub.sd >= coarse.sd * (1.0 - 1e-14));
        println!("T = {t}: Sa at samples {:.6e}, with {m} subdivisions {:.6e}", coarse.sa, sub.sa);
    }
}

#[test]
fn history_matches_peaks_and_equation_of_motion() {
    let rec = peer("RSN6_IMPVALL.I_I-ELC180-hor1.AT2");
    let (t, z) = (0.8, 0.05);
    let h = history(&rec.acceleration, rec.dt, t, z);
    let p = peaks(&rec.acceleration, rec.dt, t, z, SpectrumOptions::default());
    let n = rec.acceleration.len();
    assert_eq!((h.u.len(), h.v.len(), h.a_abs.len()), (n, n, n));
    assert_eq!((h.u[0], h.v[0], h.a_abs[0]), (0.0, 0.0, 0.0));
    let (i, sd) = h.u.iter().enumerate().fold((0, 0.0f64), |b, (i, x)| if x.abs() > b.1 { (i, x.abs()) } else { b });
    assert_eq!(sd, p.sd);
    assert!((i as f64 * rec.dt - p.t_sd).abs() < 1e-12);
    assert_eq!(h.a_abs.iter().fold(0.0f64, |m, x| m.max(x.abs())), p.sa);
    // u'' + a_g = a_abs: central differences of u against a_abs (O(dt²))
    let scale = p.sa;
    for k in (100..n - 1).step_by(97) {
        let udd = (h.u[k + 1] - 2.0 * h.u[k] + h.u[k - 1]) / (rec.dt * rec.dt);
        let vd = (h.v[k + 1] - h.v[k - 1]) / (2.0 * rec.dt);
        assert!((udd + rec.acceleration[k] - h.a_abs[k]).abs() < 2e-2 * scale, "k = {k}");
        assert!((vd + rec.acceleration[k] - h.a_abs[k]).abs() < 2e-2 * scale, "k = {k}");
    }
    // rigid oscillator
    let r = history(&rec.acceleration, rec.dt, 0.0, z);
    assert_eq!(r.a_abs, rec.acceleration);
    assert!(r.u.iter().chain(&r.v).all(|x| *x == 0.0));
}

#[test]
fn damping_near_one_and_zero() {
    let rec = peer("RSN1690_NORTH151_SYL090-hor1.AT2");
    let acc = &rec.acceleration[..400];
    for z in [0.0, 0.5, 0.9, 0.999] {
        for t in [0.05, 1.0] {
            let p = peaks(acc, rec.dt, t, z, SpectrumOptions::default());
            let r = rk4_peaks(acc, rec.dt, t, z, 4000);
            assert!(rel(p.sd, r.sd) < 1e-9 && rel(p.sv, r.sv) < 1e-9 && rel(p.sa, r.sa) < 1e-9, "T = {t} zeta = {z}");
        }
    }
    assert!(Oscillator::new(1.0, 0.9999999, 0.01).is_ok());
}

#[test]
fn constant_acceleration_overshoot() {
    // a suddenly applied constant ground acceleration a (the first sample
    // counts from t = 0, no ramp): undamped u = -(a/ω²)(1 - cos ωt), so
    // Sd = 2a/ω² once t >= T/2; with damping ζ the first overshoot is
    // (a/ω²)(1 + exp(-ζπ/sqrt(1-ζ²))).
    let a = 2.0;
    let rec = Record::new("step", 0.001, vec![a; 3001]).unwrap();
    for z in [0.0, 0.1, 0.3] {
        let t = 1.0;
        let w = 2.0 * std::f64::consts::PI / t;
        let p = peaks(&rec.acceleration, rec.dt, t, z, SpectrumOptions { subdivisions: 20 });
        let want = a / (w * w) * (1.0 + (-z * std::f64::consts::PI / (1.0 - z * z).sqrt()).exp());
        // the crest can fall between the 20 points per sample interval:
        // 1 - cos(ω·dt/40) = 1.2e-8 at most
        assert!(rel(p.sd, want) < 2e-8, "zeta {z}: {} vs {want}", p.sd);
        let td = t / (1.0 - z * z).sqrt();
        assert!((p.t_sd - td / 2.0).abs() < 1e-3, "time of the first overshoot {}", p.t_sd);
    }
}
