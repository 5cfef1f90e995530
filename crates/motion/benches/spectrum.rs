//! Response spectrum of the Loma Prieta Corralitos 090 record (7999
//! samples at 0.005 s): 60 log-spaced periods 0.02..10 s × 2 dampings
//! (0.02, 0.05), one thread. Goal: under 5 ms. Also one oscillator alone
//! and the 120 sets of step coefficients alone.
//!
//! `CARGO_TARGET_DIR=/work/target-motion cargo bench -p quakejoint-motion --bench spectrum`

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion};
use quakejoint_motion::{load_record, peaks, period_range, spectrum, Oscillator, RecordSpec, SpectrumOptions};

fn bench(c: &mut Criterion) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../ground_motions");
    let rec = load_record(&RecordSpec::new("RSN753_LOMAP_CLS090-hor2.AT2"), &dir).expect("record").record;
    assert_eq!(rec.acceleration.len(), 7999);
    let periods = period_range(0.02, 10.0, 60, true).expect("periods");
    let dampings = [0.02, 0.05];
    let options = SpectrumOptions::default();

    c.bench_function("spectrum 60 periods x 2 dampings, 7999 samples", |b| {
        b.iter(|| spectrum(black_box(&rec), black_box(&periods), black_box(&dampings), options).expect("spectrum"))
    });
    c.bench_function("one oscillator, 7999 samples", |b| {
        b.iter(|| peaks(black_box(&rec.acceleration), rec.dt, black_box(1.0), 0.05, options))
    });
    c.bench_function("step coefficients for 120 oscillators", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for &z in &dampings {
                for &t in &periods {
                    s += Oscillator::new(black_box(t), z, rec.dt).expect("oscillator").step.map_or(0.0, |c| c.b1);
                }
            }
            s
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
