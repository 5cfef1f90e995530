//! Test 1: the exact step against a second, independent method: classical
//! Runge-Kutta 4 with 1000 fixed sub-steps per sample interval on the same
//! piecewise-linear ground acceleration (the first 20 s of the Loma Prieta
//! Corralitos 090 record). Required: 1e-6 relative in Sa, Sv and Sd for
//! periods 0.05..10 s and dampings 0..0.2; asserted: 1e-9 (RK4's own error
//! here is far below that: ω·h <= 6.3e-4 per sub-step; the agreement seen
//! is about 1e-13).

mod common;

use common::{peer, rel, rk4_peaks};
use quakejoint_motion::{peaks, spectrum_samples, SpectrumOptions};

#[test]
fn exact_step_matches_fine_rk4() {
    let rec = peer("RSN753_LOMAP_CLS090-hor2.AT2");
    let accel = &rec.acceleration[..4000];
    let periods = [0.05, 0.2, 1.0, 3.0, 10.0];
    let dampings = [0.0, 0.02, 0.05, 0.2];
    let rows = spectrum_samples(accel, rec.dt, &periods, &dampings, SpectrumOptions::default()).unwrap();
    let mut worst = 0.0f64;
    for (k, row) in rows.iter().enumerate() {
        let (t, z) = (row.period, row.damping);
        assert_eq!((t, z), (periods[k % periods.len()], dampings[k / periods.len()]), "damping-major order");
        let reference = rk4_peaks(accel, rec.dt, t, z, 1000);
        let p = peaks(accel, rec.dt, t, z, SpectrumOptions::default());
        assert_eq!(p, row.peaks, "single-oscillator and lockstep paths agree bit for bit");
        let errs = [rel(p.sa, reference.sa), rel(p.sv, reference.sv), rel(p.sd, reference.sd)];
        println!(
            "T = {t:5} s  zeta = {z:4}:  Sa {:.6e} (rel err {:.1e})  Sv {:.6e} ({:.1e})  Sd {:.6e} ({:.1e})",
            p.sa, errs[0], p.sv, errs[1], p.sd, errs[2]
        );
        for e in errs {
            assert!(e < 1e-9, "T = {t}, zeta = {z}: relative error {e:e}");
            worst = worst.max(e);
        }
    }
    println!("largest relative difference to RK4: {worst:.2e}");
}
