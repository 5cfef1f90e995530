//! The cost of fitting a limit state's fragility, what every write of a
//! multiple-stripe sweep's output repeats for each limit state and curve:
//! the maximum-likelihood fit of ten stripes, and the bootstrap of 1000
//! resamples of 5 and of 40 records (counts drawn from a known fragility,
//! median 0.65, beta 0.3), without and with the annual frequency of each
//! resample on a hazard curve, each the fastest of five, one thread:
//!
//!     cargo bench -p quakejoint-model --bench fragility

use std::time::Instant;

use quakejoint_model::fragility::{bootstrap, bootstrap_risk, fit, phi_cdf, Hazard, SplitMix64, Stripe};

const LEVELS: [f64; 10] = [0.3, 0.4, 0.5, 0.55, 0.6, 0.65, 0.7, 0.75, 0.8, 0.9];

/// `records` records' outcomes at every stripe.
fn outcomes(records: usize, rng: &mut SplitMix64) -> Vec<Vec<Option<bool>>> {
    (0..records)
        .map(|_| LEVELS.iter().map(|&x| Some(rng.uniform() < phi_cdf((x / 0.65f64).ln() / 0.3))).collect())
        .collect()
}

fn fastest(f: &mut dyn FnMut()) -> f64 {
    (0..5)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() {
    let mut rng = SplitMix64::new(7);
    println!("{:<40} {:>12}", "what", "time [ms]");
    for records in [5, 40] {
        let o = outcomes(records, &mut rng);
        let stripes: Vec<Stripe> = LEVELS
            .iter()
            .enumerate()
            .map(|(s, &intensity)| Stripe {
                intensity,
                runs: records as u32,
                exceeded: o.iter().filter(|r| r[s] == Some(true)).count() as u32,
            })
            .collect();
        let t_fit = fastest(&mut || {
            std::hint::black_box(fit(std::hint::black_box(&stripes)).ok());
        });
        let t_boot = fastest(&mut || {
            std::hint::black_box(bootstrap(&o, &LEVELS, 1000, 1, 0.9).ok());
        });
        let hazard =
            Hazard::new([0.05, 0.1, 0.2, 0.4, 0.8, 1.6].iter().map(|&x: &f64| (x, 1e-4 * x.powf(-2.5))).collect())
                .expect("a hazard curve");
        let t_risk = fastest(&mut || {
            std::hint::black_box(bootstrap_risk(&o, &LEVELS, 1000, 1, 0.9, Some(&hazard)).ok());
        });
        println!("{:<40} {:>12.4}", format!("fit, 10 stripes of {records} records"), 1e3 * t_fit);
        println!("{:<40} {:>12.2}", format!("bootstrap 1000, {records} records"), 1e3 * t_boot);
        println!("{:<40} {:>12.2}", format!("  with a hazard curve (6 points)"), 1e3 * t_risk);
    }
}
