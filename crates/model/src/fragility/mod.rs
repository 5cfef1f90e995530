//! Fragility of a limit state from a multiple-stripe analysis, and its
//! mean annual frequency at a site (issue 30; the stripes themselves are
//! not yet a sweep axis).
//!
//! - [`fit`]: the lognormal fragility `P(LS | im) = Phi(ln(im / theta) /
//!   beta)` by maximum likelihood on the stripes' counts, each stripe a
//!   binomial draw (J. W. Baker, "Efficient analytical fragility function
//!   fitting using dynamic structural analysis", Earthquake Spectra 31
//!   (2015) 579-599). In `a + b ln im` (`b = 1/beta`, `a = -ln theta /
//!   beta`) the log-likelihood is that of a probit regression, concave, and
//!   Newton's method with step halving finds its one maximum; the standard
//!   errors come from its curvature there.
//! - [`bootstrap`]: confidence intervals of `theta` and `beta` by
//!   resampling the records (each record's outcome at every stripe kept
//!   together), with a seeded generator: the same seed gives the same
//!   intervals, bit for bit.
//! - [`Hazard::mean_annual_frequency`]: `lambda_LS = integral P(LS | im)
//!   |d lambda_IM / d im| d im` over a hazard curve given as a table, joined
//!   by power laws between its points (straight in log-log) and continued by
//!   its end segments' power laws, in closed form ([`hazard`]).

use thiserror::Error;

pub mod hazard;

pub use hazard::{Hazard, Parts};

/// One stripe: the intensity every record was scaled to, how many runs
/// count and how many of them exceeded the limit state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stripe {
    /// The intensity measure's level (Sa(T1) \[m/s^2\] or PGA \[m/s^2\]).
    pub intensity: f64,
    /// Runs that count at this level (failed or unchecked ones left out,
    /// or counted, as the user chose).
    pub runs: u32,
    /// Runs in which the limit state was exceeded.
    pub exceeded: u32,
}

/// A lognormal fragility function.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fragility {
    /// Median `theta`, in the intensity's unit.
    pub median: f64,
    /// Logarithmic standard deviation `beta` [-].
    pub beta: f64,
    /// The log-likelihood at the estimate.
    pub log_likelihood: f64,
    /// Standard error of `ln theta` [-] (from the curvature of the
    /// log-likelihood).
    pub se_ln_median: f64,
    /// Standard error of `beta` [-].
    pub se_beta: f64,
}

/// Why a fragility cannot be fitted.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FragilityError {
    /// A stripe's values cannot be.
    #[error("stripe {index}: {reason}")]
    Stripe {
        /// The stripe's index.
        index: usize,
        /// What is wrong.
        reason: String,
    },
    /// The counts do not determine a lognormal fragility.
    #[error("the stripes do not determine a fragility: {0}")]
    Undetermined(String),
    /// An argument out of its range.
    #[error("{0}")]
    Argument(String),
    /// A hazard curve's point cannot be.
    #[error("hazard curve, point {index}: {reason}")]
    Hazard {
        /// The point's index.
        index: usize,
        /// What is wrong.
        reason: String,
    },
}

/// The standard normal distribution function.
pub fn phi_cdf(t: f64) -> f64 {
    0.5 * libm::erfc(-t / std::f64::consts::SQRT_2)
}

/// `ln Phi(t)`, accurate in the far left tail.
pub(crate) fn ln_phi(t: f64) -> f64 {
    if t > -30.0 {
        phi_cdf(t).ln()
    } else {
        // Mills' ratio: Phi(t) ~ phi(t) / -t (1 - 1/t^2 + 3/t^4)
        let t2 = t * t;
        -0.5 * t2 - (-t).ln() - 0.5 * (2.0 * std::f64::consts::PI).ln() + (1.0 - 1.0 / t2 + 3.0 / (t2 * t2)).ln()
    }
}

/// `phi(t) / Phi(t)`, the inverse Mills ratio, accurate in the left tail.
fn mills(t: f64) -> f64 {
    if t > -30.0 {
        let pdf = (-0.5 * t * t).exp() / (2.0 * std::f64::consts::PI).sqrt();
        pdf / phi_cdf(t)
    } else {
        let t2 = t * t;
        -t / (1.0 - 1.0 / t2 + 3.0 / (t2 * t2))
    }
}

/// The log-likelihood of `a + b x` and its gradient and Hessian.
fn likelihood(stripes: &[Stripe], a: f64, b: f64) -> (f64, [f64; 2], [f64; 3]) {
    let (mut l, mut g, mut h) = (0.0, [0.0; 2], [0.0; 3]);
    for s in stripes {
        let x = s.intensity.ln();
        let eta = a + b * x;
        let (z, n) = (s.exceeded as f64, s.runs as f64);
        l += z * ln_phi(eta) + (n - z) * ln_phi(-eta);
        let (m1, m2) = (mills(eta), mills(-eta));
        let d1 = z * m1 - (n - z) * m2;
        let d2 = -z * m1 * (eta + m1) - (n - z) * m2 * (-eta + m2);
        g[0] += d1;
        g[1] += d1 * x;
        h[0] += d2;
        h[1] += d2 * x;
        h[2] += d2 * x * x;
    }
    (l, g, h)
}

/// Largest dispersion a fit is given with: beyond it the fraction exceeded
/// does not change over any range of intensities that matters (beta 10 is
/// a factor of e^10 = 22000 in intensity per standard deviation).
pub const MAX_BETA: f64 = 10.0;

/// The maximum-likelihood lognormal fragility of the stripes' counts.
pub fn fit(stripes: &[Stripe]) -> Result<Fragility, FragilityError> {
    for (index, s) in stripes.iter().enumerate() {
        let bad = |reason: &str| Err(FragilityError::Stripe { index, reason: reason.to_string() });
        if !(s.intensity.is_finite() && s.intensity > 0.0) {
            return bad(&format!("intensity {} must be positive and finite", s.intensity));
        }
        if s.exceeded > s.runs {
            return bad(&format!("{} runs exceeded of {}", s.exceeded, s.runs));
        }
    }
    let counted: Vec<&Stripe> = stripes.iter().filter(|s| s.runs > 0).collect();
    let levels = {
        let mut l: Vec<f64> = counted.iter().map(|s| s.intensity).collect();
        l.sort_by(f64::total_cmp);
        l.dedup();
        l.len()
    };
    let (z, n): (u64, u64) = counted.iter().fold((0, 0), |(z, n), s| (z + s.exceeded as u64, n + s.runs as u64));
    if levels < 2 {
        return Err(FragilityError::Undetermined("runs at two intensities at least are needed".into()));
    }
    if z == 0 || z == n {
        return Err(FragilityError::Undetermined(format!(
            "{} of {n} runs exceeded the limit state: raise {} the stripes",
            z,
            if z == 0 { "the highest of" } else { "or lower" }
        )));
    }
    // the fraction exceeded must grow with the intensity: the runs-weighted
    // slope of the fractions against ln im
    let (w, sx, sy) = counted.iter().fold((0.0, 0.0, 0.0), |(w, sx, sy), s| {
        let n = f64::from(s.runs);
        (w + n, sx + n * s.intensity.ln(), sy + f64::from(s.exceeded))
    });
    let (mx, my) = (sx / w, sy / w);
    let slope: f64 =
        counted.iter().map(|s| (s.intensity.ln() - mx) * (f64::from(s.exceeded) - f64::from(s.runs) * my)).sum();
    if slope <= 0.0 {
        return Err(FragilityError::Undetermined(
            "the fraction exceeded does not grow with the intensity (is the limit state the wrong way round, \
             `above` for `below`?)"
                .into(),
        ));
    }
    match separation(&counted) {
        Some(Separation::Quasi { level, exceeded, runs }) => Err(FragilityError::Undetermined(format!(
            "every run below {level} survives and every run above it exceeds; at {level}, {exceeded} of {runs} \
             exceeded: the median is about {level} and the dispersion is not determined (add stripes about it)"
        ))),
        Some(Separation::Complete { top_safe, low_fail }) => Err(FragilityError::Undetermined(format!(
            "every run below {low_fail} survives and every run from it on exceeds: the median lies between \
             {top_safe} and {low_fail} and the dispersion is not determined (add stripes between)"
        ))),
        None => newton(stripes, &counted),
    }
}

/// How counts are separated, when they are: the likelihood then grows
/// without bound as beta -> 0.
enum Separation {
    /// Every run below `low_fail` survives and every run from it on
    /// exceeds (`top_safe` is the highest level with a survivor).
    Complete { top_safe: f64, low_fail: f64 },
    /// The runs overlap at one level only, `level`, where `exceeded` of
    /// `runs` exceeded.
    Quasi { level: f64, exceeded: u32, runs: u32 },
}

fn separation(counted: &[&Stripe]) -> Option<Separation> {
    let top_safe = counted.iter().filter(|s| s.exceeded < s.runs).map(|s| s.intensity).fold(0.0, f64::max);
    let low_fail = counted.iter().filter(|s| s.exceeded > 0).map(|s| s.intensity).fold(f64::INFINITY, f64::min);
    if top_safe == low_fail {
        let (exceeded, runs) =
            counted.iter().filter(|s| s.intensity == low_fail).fold((0, 0), |a, s| (a.0 + s.exceeded, a.1 + s.runs));
        Some(Separation::Quasi { level: low_fail, exceeded, runs })
    } else if top_safe < low_fail {
        Some(Separation::Complete { top_safe, low_fail })
    } else {
        None
    }
}

/// The limit of the likelihood's maximum for separated counts (beta -> 0):
/// the median at the one overlapping level, or at the geometric middle of
/// the gap between the levels that separate the runs; None when the counts
/// are not separated or have no run on one side (every run survived, or
/// every run exceeded).
pub fn separated_limit(stripes: &[Stripe]) -> Option<f64> {
    let counted: Vec<&Stripe> = stripes.iter().filter(|s| s.runs > 0).collect();
    let (z, n) = counted.iter().fold((0u64, 0u64), |(z, n), s| (z + u64::from(s.exceeded), n + u64::from(s.runs)));
    if z == 0 || z == n {
        return None;
    }
    match separation(&counted)? {
        Separation::Quasi { level, .. } => Some(level),
        Separation::Complete { top_safe, low_fail } => Some((top_safe * low_fail).sqrt()),
    }
}

/// Newton's method on the probit likelihood of counts that are not
/// separated.
fn newton(stripes: &[Stripe], counted: &[&Stripe]) -> Result<Fragility, FragilityError> {
    // start: beta 0.5 about the log-mean of the levels
    let mean_x = counted.iter().map(|s| s.intensity.ln()).sum::<f64>() / counted.len() as f64;
    let (mut a, mut b) = (-mean_x / 0.5, 1.0 / 0.5);
    let (mut l, mut g, mut h) = likelihood(stripes, a, b);
    for _ in 0..200 {
        let [h0, h1, h2] = h;
        let det = h0 * h2 - h1 * h1;
        if !(det.is_finite() && det > 0.0) {
            return Err(FragilityError::Undetermined("the likelihood has no curvature (separated counts?)".into()));
        }
        // Newton: step = -H^-1 g
        let da = -(h2 * g[0] - h1 * g[1]) / det;
        let db = -(-h1 * g[0] + h0 * g[1]) / det;
        let mut step = 1.0;
        let mut improved = false;
        for _ in 0..60 {
            let (na, nb) = (a + step * da, b + step * db);
            let next = likelihood(stripes, na, nb);
            if nb > 0.0 && next.0 >= l {
                (a, b, l, g, h) = (na, nb, next.0, next.1, next.2);
                improved = true;
                break;
            }
            step *= 0.5;
        }
        if !improved || (step * da).abs() + (step * db).abs() < 1e-13 * (1.0 + a.abs() + b.abs()) {
            break;
        }
    }
    if b <= 0.0 {
        return Err(FragilityError::Undetermined("the fraction exceeded does not grow with the intensity".into()));
    }
    if 1.0 / b > MAX_BETA {
        return Err(FragilityError::Undetermined(format!(
            "the fraction exceeded hardly changes with the intensity (beta {:.3e} beyond {MAX_BETA}): the limit state \
             does not depend on the measure over the stripes",
            1.0 / b
        )));
    }
    let [h0, h1, h2] = h;
    let det = h0 * h2 - h1 * h1;
    // covariance of (a, b) = (-H)^-1; ln theta = -a/b, beta = 1/b
    let (caa, cab, cbb) = (-h2 / det, h1 / det, -h0 / det);
    let (dla, dlb) = (-1.0 / b, a / (b * b));
    let var_ln = dla * dla * caa + 2.0 * dla * dlb * cab + dlb * dlb * cbb;
    let var_beta = cbb / b.powi(4);
    Ok(Fragility {
        median: (-a / b).exp(),
        beta: 1.0 / b,
        log_likelihood: l,
        se_ln_median: var_ln.max(0.0).sqrt(),
        se_beta: var_beta.max(0.0).sqrt(),
    })
}

/// SplitMix64 (G. Steele, D. Lea and C. Flood, "Fast splittable
/// pseudorandom number generators", OOPSLA 2014): a seeded generator whose
/// draws are the same on every machine.
#[derive(Debug, Clone)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform draw in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A uniform index below `n`.
    pub fn below(&mut self, n: usize) -> usize {
        ((self.uniform() * n as f64) as usize).min(n - 1)
    }
}

/// Confidence intervals of a fragility by the bootstrap over records.
#[derive(Debug, Clone, PartialEq)]
pub struct Intervals {
    /// The interval's level [-] (0.9: from the 5th to the 95th percentile).
    pub level: f64,
    /// The median's interval.
    pub median: [f64; 2],
    /// The dispersion's interval.
    pub beta: [f64; 2],
    /// The mean annual frequency's interval \[1/year\], with a hazard
    /// curve ([`bootstrap_risk`]).
    pub annual_frequency: Option<[f64; 2]>,
    /// Resamples whose counts determined no fragility, every run having
    /// survived or every one exceeded (left out).
    pub undetermined: usize,
    /// Resamples whose counts are separated (every run below a level
    /// survives, every run above it exceeds): their likelihood's supremum
    /// is at beta -> 0, and they enter the intervals with beta = 0 and the
    /// median at [`separated_limit`].
    pub separated: usize,
}

/// Most bootstrap resamples [`bootstrap_risk`] draws.
pub const MAX_SAMPLES: usize = 100_000;

/// The bootstrap of [`fit`] over records (a resample whose counts are
/// separated enters with beta = 0, the limit of its likelihood's maximum,
/// so that the intervals are not biased towards the resamples that
/// overlap): `outcomes[r][s]` is record `r`'s
/// outcome at stripe `s` (`Some(true)`: exceeded; `None`: a run that does
/// not count), `intensities[s]` the stripes' levels; `samples` resamples
/// of the records with replacement from `seed`, percentile intervals at
/// `level`.
pub fn bootstrap(
    outcomes: &[Vec<Option<bool>>],
    intensities: &[f64],
    samples: usize,
    seed: u64,
    level: f64,
) -> Result<Intervals, FragilityError> {
    bootstrap_risk(outcomes, intensities, samples, seed, level, None)
}

/// [`bootstrap`], and with a hazard curve the interval of the mean annual
/// frequency over the same resamples ([`Intervals::annual_frequency`]).
pub fn bootstrap_risk(
    outcomes: &[Vec<Option<bool>>],
    intensities: &[f64],
    samples: usize,
    seed: u64,
    level: f64,
    hazard: Option<&Hazard>,
) -> Result<Intervals, FragilityError> {
    if !(1..=MAX_SAMPLES).contains(&samples) {
        return Err(FragilityError::Argument(format!(
            "{samples} bootstrap resamples: from 1 to {MAX_SAMPLES} (1000 give the intervals to about 1 %)"
        )));
    }
    if !(level > 0.0 && level < 1.0) {
        return Err(FragilityError::Argument(format!("level {level}: between 0 and 1 (0.9: 5 % to 95 %)")));
    }
    let mut rng = SplitMix64::new(seed);
    let mut rates = Vec::new();
    let (mut medians, mut betas) = (Vec::with_capacity(samples), Vec::with_capacity(samples));
    let (mut undetermined, mut separated) = (0, 0);
    let n = outcomes.len();
    if n == 0 {
        return Err(FragilityError::Undetermined("no records".into()));
    }
    for _ in 0..samples {
        let mut stripes: Vec<Stripe> =
            intensities.iter().map(|&intensity| Stripe { intensity, runs: 0, exceeded: 0 }).collect();
        for _ in 0..n {
            let record = &outcomes[rng.below(n)];
            for (stripe, outcome) in stripes.iter_mut().zip(record) {
                if let Some(exceeded) = outcome {
                    stripe.runs += 1;
                    stripe.exceeded += u32::from(*exceeded);
                }
            }
        }
        let resample = match fit(&stripes) {
            Ok(f) => Some(f),
            // separated counts: the likelihood's supremum, beta -> 0
            Err(_) => match separated_limit(&stripes) {
                Some(median) => {
                    separated += 1;
                    Some(Fragility { median, beta: 0.0, log_likelihood: f64::NAN, se_ln_median: 0.0, se_beta: 0.0 })
                }
                None => {
                    undetermined += 1;
                    None
                }
            },
        };
        if let Some(f) = resample {
            medians.push(f.median);
            betas.push(f.beta);
            if let Some(h) = hazard {
                rates.push(h.mean_annual_frequency(&f)?);
            }
        }
    }
    if medians.is_empty() {
        return Err(FragilityError::Undetermined("no resample determined a fragility".into()));
    }
    let percentile = |v: &mut Vec<f64>, p: f64| {
        v.sort_by(f64::total_cmp);
        let i = ((v.len() - 1) as f64 * p).round() as usize;
        v[i]
    };
    let tail = (1.0 - level) / 2.0;
    Ok(Intervals {
        level,
        median: [percentile(&mut medians, tail), percentile(&mut medians, 1.0 - tail)],
        beta: [percentile(&mut betas, tail), percentile(&mut betas, 1.0 - tail)],
        annual_frequency: hazard.map(|_| [percentile(&mut rates, tail), percentile(&mut rates, 1.0 - tail)]),
        undetermined,
        separated,
    })
}
