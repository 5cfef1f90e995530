//! The limit states evaluated on a sweep's results, counted stripe by
//! stripe and fitted: one curve per case, damping ratio and period.

use quakejoint_model::fragility::{bootstrap_risk, fit, mean_annual_frequency, Fragility, Intervals, Stripe};
use quakejoint_model::validity::Flags;

use super::spec::{Failed, FragilitySpec, Kind, LimitState};
use crate::plan::Stripes;
use crate::results::{status, Results};

/// A run's outcome for a limit state (`/fragility/<key>/outcome`).
pub mod outcome {
    /// The limit state was exceeded.
    pub const EXCEEDED: i8 = 1;
    /// It was not.
    pub const NOT_EXCEEDED: i8 = 0;
    /// The run failed (stopped, invalid parameters, simulation failed).
    pub const FAILED: i8 = -1;
    /// The run has not run (another shard's, or not reached yet).
    pub const NOT_RUN: i8 = -2;
    /// The run finished but does not report what the limit state tests
    /// (NaN in the field).
    pub const UNDETERMINED: i8 = -3;
}

/// The runs of one stripe for one limit state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StripeCounts {
    /// Runs that count.
    pub runs: u32,
    /// Of them, runs that exceeded the limit state.
    pub exceeded: u32,
    /// Failed runs (counted as exceeding, or left out, as the config says).
    pub failed: u32,
    /// Runs not run.
    pub not_run: u32,
    /// Finished runs that do not report what the limit state tests (left out).
    pub undetermined: u32,
    /// Runs counted that the model flags for another reason than the
    /// limit state itself (beams passing through each other, say).
    pub flagged: u32,
}

/// A limit state's fragility for one case, damping ratio and period.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// The counts, stripe by stripe.
    pub counts: Vec<StripeCounts>,
    /// The maximum-likelihood fit (median in g), if the counts determine one.
    pub fit: Option<Fragility>,
    /// Its bootstrap intervals, if asked for and determined.
    pub intervals: Option<Intervals>,
    /// Its mean annual frequency at the site \[1/year\] (NaN without a
    /// hazard curve or a fit).
    pub annual_frequency: f64,
    /// What a user should know about the curve (empty when nothing).
    pub note: String,
}

/// One limit state over the sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct LimitStateResult {
    /// Every job's outcome ([`outcome`]), in the sweep's job order.
    pub outcome: Vec<i8>,
    /// Its curves, by case, damping ratio and period (`(c * nz + z) * nt + t`).
    pub curves: Vec<Curve>,
}

/// A job's outcome for `ls`.
fn outcome_of(ls: &LimitState, spec: &FragilitySpec, r: &Results, j: usize) -> i8 {
    if let Kind::Without { measure, threshold } = ls.test {
        let x = r.without[measure][r.without_index(j)];
        return if x.is_nan() { outcome::NOT_RUN } else { i8::from(x > threshold) };
    }
    match r.status[j] {
        status::NOT_RUN => return outcome::NOT_RUN,
        status::OK => {}
        _ => return if spec.failed == Failed::Exceed { outcome::EXCEEDED } else { outcome::FAILED },
    }
    match ls.test {
        Kind::Flag(f) => i8::from(r.validity[j] & f.0 != 0),
        Kind::Field { field, threshold, above } => {
            let x = r.values[field][j];
            if x.is_nan() {
                outcome::UNDETERMINED
            } else {
                i8::from(if above { x > threshold } else { x < threshold })
            }
        }
        Kind::Without { .. } => unreachable!("handled above"),
    }
}

/// The limit states of `spec` on `results` (a sweep over `stripes`).
pub fn evaluate(spec: &FragilitySpec, stripes: &Stripes, results: &Results) -> Vec<LimitStateResult> {
    let [nc, nr, nz, nt] = results.dims;
    let n = results.status.len();
    spec.limit_states
        .iter()
        .map(|ls| {
            let outcome: Vec<i8> = (0..n).map(|j| outcome_of(ls, spec, results, j)).collect();
            let mut curves = Vec::with_capacity(nc * nz * nt);
            for c in 0..nc {
                for z in 0..nz {
                    for t in 0..nt {
                        let jobs: Vec<usize> = (0..nr).map(|rec| ((c * nr + rec) * nz + z) * nt + t).collect();
                        let tally = Tally::of(ls, stripes, results, &outcome, &jobs);
                        curves.push(curve(spec, stripes, tally));
                    }
                }
            }
            LimitStateResult { outcome, curves }
        })
        .collect()
}

/// The runs of one curve, counted.
struct Tally {
    /// Per stripe.
    counts: Vec<StripeCounts>,
    /// `by_record[g][s]`: record `g`'s outcome at stripe `s` (for the
    /// bootstrap; None: the run does not count).
    by_record: Vec<Vec<Option<bool>>>,
    /// How many counted runs carry each other flag (`capacity_exceeded 3`).
    flagged: Vec<String>,
}

impl Tally {
    /// Counts `jobs` (the curve's job of each record of the sweep).
    fn of(ls: &LimitState, stripes: &Stripes, results: &Results, outcome: &[i8], jobs: &[usize]) -> Self {
        let own = match ls.test {
            Kind::Flag(f) => f.0,
            _ => 0,
        };
        let alone = matches!(ls.test, Kind::Without { .. });
        let mut counts = vec![StripeCounts::default(); stripes.levels.len()];
        let mut by_record = vec![vec![None; stripes.levels.len()]; stripes.ground.len()];
        let mut other = vec![0u32; Flags::ALL.len()];
        for (run, &j) in stripes.runs.iter().zip(jobs) {
            let k = &mut counts[run.stripe];
            let ran_ok = results.status[j] == status::OK;
            if results.status[j] != status::NOT_RUN && !ran_ok && !alone {
                k.failed += 1;
            }
            match outcome[j] {
                o @ (outcome::EXCEEDED | outcome::NOT_EXCEEDED) => {
                    k.runs += 1;
                    k.exceeded += u32::from(o == outcome::EXCEEDED);
                    let flags = Flags(results.validity[j] & !own & !Flags::NOT_CHECKED.0);
                    if ran_ok && !alone && flags.is_flagged() {
                        k.flagged += 1;
                        for (n, (f, _)) in other.iter_mut().zip(Flags::ALL.iter()) {
                            *n += u32::from(flags.contains(*f));
                        }
                    }
                    by_record[run.ground][run.stripe] = Some(o == outcome::EXCEEDED);
                }
                outcome::NOT_RUN => k.not_run += 1,
                outcome::UNDETERMINED => k.undetermined += 1,
                _ => {}
            }
        }
        let flagged =
            Flags::ALL.iter().zip(&other).filter(|(_, &n)| n > 0).map(|((_, name), n)| format!("{name} {n}")).collect();
        Self { counts, by_record, flagged }
    }
}

/// Fits one curve from its tally.
fn curve(spec: &FragilitySpec, stripes: &Stripes, tally: Tally) -> Curve {
    let Tally { counts, by_record, flagged } = tally;
    let data: Vec<Stripe> = stripes
        .levels
        .iter()
        .zip(&counts)
        .map(|(&intensity, k)| Stripe { intensity, runs: k.runs, exceeded: k.exceeded })
        .collect();
    let mut notes = Vec::new();
    let (failed, not_run, undetermined) =
        counts.iter().fold((0, 0, 0), |a, k| (a.0 + k.failed, a.1 + k.not_run, a.2 + k.undetermined));
    if failed > 0 {
        notes.push(match spec.failed {
            Failed::Exclude => format!("{failed} failed runs left out (sweep.fragility.failed = \"exclude\")"),
            Failed::Exceed => {
                format!("{failed} failed runs counted as exceeding (sweep.fragility.failed = \"exceed\")")
            }
        });
    }
    if not_run > 0 {
        notes.push(format!("{not_run} runs not run yet (or another shard's): the fit is on the runs finished"));
    }
    if undetermined > 0 {
        notes.push(format!("{undetermined} runs do not report what the limit state tests (NaN): left out"));
    }
    if !flagged.is_empty() {
        notes.push(format!(
            "{} runs counted are flagged by the model for another reason ({}): the curve rests on results the model \
             cannot stand behind",
            counts.iter().map(|k| k.flagged).sum::<u32>(),
            flagged.join(", ")
        ));
    }
    let fitted = fit(&data);
    let (fit, intervals, annual_frequency) = match fitted {
        Ok(f) => {
            let hazard = spec.hazard.as_ref().map(|h| &h.0[..]);
            let intervals = if spec.bootstrap > 0 {
                let levels = &stripes.levels;
                match bootstrap_risk(&by_record, levels, spec.bootstrap, spec.seed, spec.confidence, hazard) {
                    Ok(i) => {
                        if i.separated > 0 {
                            notes.push(format!(
                                "{} of {} bootstrap resamples have separated counts: they enter the intervals with \
                                 beta = 0",
                                i.separated, spec.bootstrap
                            ));
                        }
                        if i.undetermined > 0 {
                            notes.push(format!(
                                "{} of {} bootstrap resamples determined no fragility (every run survived or every \
                                 one exceeded): left out of the intervals",
                                i.undetermined, spec.bootstrap
                            ));
                        }
                        Some(i)
                    }
                    Err(e) => {
                        notes.push(format!("no intervals: {e}"));
                        None
                    }
                }
            } else {
                None
            };
            let annual = match &spec.hazard {
                Some((points, _)) => mean_annual_frequency(&f, points).unwrap_or_else(|e| {
                    notes.push(format!("no annual frequency: {e}"));
                    f64::NAN
                }),
                None => f64::NAN,
            };
            notes.extend(extrapolation(&f, &data, spec.hazard.as_ref().map(|h| (&h.0[..], annual))));
            (Some(f), intervals, annual)
        }
        Err(e) => {
            notes.push(format!("no fit: {e}"));
            (None, None, f64::NAN)
        }
    };
    Curve { counts, fit, intervals, annual_frequency, note: notes.join("; ") }
}

/// What a fit rests on beyond the data: a median outside the stripes, a
/// dispersion so large that the intensity hardly matters, and, with a hazard curve (its points and the annual frequency
/// `lambda`), a share of `lambda` above 1 % from below the curve's lowest
/// intensity or from above its highest, where the curve is continued by
/// its end segments' power laws.
fn extrapolation(f: &Fragility, stripes: &[Stripe], hazard: Option<(&[(f64, f64)], f64)>) -> Vec<String> {
    let mut notes = Vec::new();
    let counted = stripes.iter().filter(|s| s.runs > 0).map(|s| s.intensity);
    let (lo, hi) = counted.fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
    if f.median < lo || f.median > hi {
        notes.push(format!(
            "the median ({:.4} g) lies outside the stripes ({lo} to {hi} g): it is extrapolated",
            f.median
        ));
    }
    if f.beta > 1.5 {
        notes.push(format!(
            "beta {:.2}: the limit state hardly depends on the measure over the stripes (a run's outcome is the \
             record's, not the level's)",
            f.beta
        ));
    }
    let Some((points, lambda)) = hazard else { return notes };
    if points.len() < 2 || !(lambda.is_finite() && lambda > 0.0) {
        return notes;
    }
    let n = points.len();
    let slope = |a: (f64, f64), b: (f64, f64)| -(b.1 / a.1).ln() / (b.0 / a.0).ln();
    let below = beyond(f, points[0], slope(points[0], points[1]), true) / lambda;
    if below > 0.01 {
        notes.push(format!(
            "{:.0} % of the annual frequency comes from below the hazard curve's lowest intensity ({} g), where \
             the curve is continued by its first segment's power law",
            100.0 * below.min(1.0),
            points[0].0
        ));
    }
    let above = beyond(f, points[n - 1], slope(points[n - 2], points[n - 1]), false) / lambda;
    if above > 0.01 {
        notes.push(format!(
            "{:.0} % of the annual frequency comes from above the hazard curve's highest intensity ({} g), where \
             the curve is continued by its last segment's power law",
            100.0 * above.min(1.0),
            points[n - 1].0
        ));
    }
    notes
}

/// The part of `lambda_LS = integral lambda_IM dP` beyond the hazard
/// curve's end point `(im, rate)`, where `lambda_IM` is the power law of
/// slope `k` through it: below it (`below`) or above it. This is the part
/// that rests on the curve's continuation. By Simpson's rule in `x = ln im`
/// over the integrand's support (the fragility's density, a Gaussian in x,
/// times an exponential).
fn beyond(f: &Fragility, (im, rate): (f64, f64), k: f64, below: bool) -> f64 {
    let (mu, beta, x1) = (f.median.ln(), f.beta, im.ln());
    if !(k.is_finite() && k > 0.0 && beta > 0.0) {
        return 0.0;
    }
    // the integrand peaks at mu - k beta^2
    let centre = mu - k * beta * beta;
    let (a, b) = if below { ((centre - 12.0 * beta).min(x1), x1) } else { (x1, (centre + 12.0 * beta).max(x1)) };
    let density = |x: f64| {
        let u = (x - mu) / beta;
        (-0.5 * u * u).exp() / (beta * (2.0 * std::f64::consts::PI).sqrt())
    };
    let g = |x: f64| rate * (-k * (x - x1)).exp() * density(x);
    let m = 4000;
    let h = (b - a) / m as f64;
    let sum: f64 = (0..=m)
        .map(|i| {
            let w = if i == 0 || i == m {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            w * g(a + i as f64 * h)
        })
        .sum();
    sum * h / 3.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use quakejoint_model::fragility::phi_cdf;

    /// Below a power-law hazard `k0 im^-k`'s point `x1 = ln im1`, the part
    /// of `lambda = integral lambda_IM dP` has a closed form (completing
    /// the square): `lambda Phi((x1 - mu + k beta^2) / beta)`, with `lambda
    /// = k0 theta^-k exp(k^2 beta^2 / 2)` the whole integral; above `x2`
    /// the rest, `lambda (1 - Phi((x2 - mu + k beta^2) / beta))`.
    #[test]
    fn the_parts_beyond_a_power_law_hazard_are_its_closed_form() {
        let (k0, k) = (1e-4, 2.5);
        for (median, beta) in [(0.3, 0.4), (0.05, 0.8), (1.2, 0.2)] {
            let f = Fragility { median, beta, log_likelihood: 0.0, se_ln_median: 0.0, se_beta: 0.0 };
            let lambda = k0 * median.powf(-k) * (k * k * beta * beta / 2.0).exp();
            let (mu, rate) = (median.ln(), |im: f64| k0 * im.powf(-k));
            for (im1, im2) in [(0.1, 1.0), (0.02, 2.0)] {
                let (x1, x2) = (f64::ln(im1), f64::ln(im2));
                let below = lambda * phi_cdf((x1 - mu + k * beta * beta) / beta);
                let got = beyond(&f, (im1, rate(im1)), k, true);
                assert!((got - below).abs() < 1e-9 * lambda, "below {im1}: {got} against {below}");
                let above = lambda * (1.0 - phi_cdf((x2 - mu + k * beta * beta) / beta));
                let got = beyond(&f, (im2, rate(im2)), k, false);
                assert!((got - above).abs() < 1e-9 * lambda, "above {im2}: {got} against {above}");
            }
        }
    }
}
