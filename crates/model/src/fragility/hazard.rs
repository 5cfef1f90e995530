//! A site's hazard curve and the mean annual frequency of a limit state on
//! it.
//!
//! The curve is a table of `(intensity, annual frequency of exceedance)`
//! joined by power laws between its points (straight in log-log) and
//! continued beyond its ends by its end segments' power laws. On a segment
//! `ln lambda(x) = L(mu) - k (x - mu)` in `x = ln im`, and the integral
//! `lambda_LS = integral lambda_IM(im) f_LS(im) d im` (by parts from
//! `integral P(LS | im) |d lambda_IM|`; `P` rises from 0 to 1) of the
//! lognormal fragility's density `f_LS` over the segment `[xa, xb]` has a
//! closed form, by completing the square:
//!
//! `exp(L(mu) + k^2 beta^2 / 2) [Phi(vb) - Phi(va)]`, `v = (x - mu) / beta + k beta`,
//!
//! summed over the segments and the two continuations. For a power law
//! `k0 im^-k` it is `k0 theta^-k exp(k^2 beta^2 / 2)` (Cornell's closed
//! form). Each term is formed in logarithms, so it neither overflows nor
//! loses its digits where `k beta` is large (the integrand then peaks far
//! out in the fragility's left tail, at `u = -k beta`).

use super::{ln_phi, phi_cdf, Fragility, FragilityError};

/// Above this annual frequency at an intensity of [`PLAUSIBLE_FROM_G`] or
/// more a hazard curve is refused \[1/year\]: no site sees that twice a
/// year; a table of probabilities (in percent, or over 50 years) read as
/// annual frequencies does.
pub const PLAUSIBLE_MAX_RATE: f64 = 1.0;

/// The intensity \[g\] from which [`PLAUSIBLE_MAX_RATE`] holds.
pub const PLAUSIBLE_FROM_G: f64 = 0.05;

/// A site's hazard curve, checked: at least two points, intensities \[g\]
/// increasing, annual frequencies \[1/year\] positive, finite, strictly
/// decreasing and plausible (module doc).
#[derive(Debug, Clone)]
pub struct Hazard {
    points: Vec<(f64, f64)>,
}

/// Two hazard curves are the same when their points are, bit for bit.
impl PartialEq for Hazard {
    fn eq(&self, other: &Self) -> bool {
        let bits = |p: &[(f64, f64)]| p.iter().map(|&(a, b)| (a.to_bits(), b.to_bits())).collect::<Vec<_>>();
        bits(&self.points) == bits(&other.points)
    }
}

/// The parts of a limit state's mean annual frequency \[1/year\]: from
/// below the curve's lowest intensity (its first segment continued), from
/// within it, and from above its highest (its last segment continued).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Parts {
    /// From below the lowest intensity.
    pub below: f64,
    /// From between the curve's points.
    pub within: f64,
    /// From above the highest intensity.
    pub above: f64,
}

impl Parts {
    /// The mean annual frequency \[1/year\].
    pub fn total(&self) -> f64 {
        self.below + self.within + self.above
    }
}

/// One power law `ln lambda = l0 - k (x - x0)` of the curve, in `x = ln im`.
#[derive(Debug, Clone, Copy)]
struct Law {
    x0: f64,
    l0: f64,
    k: f64,
}

impl Law {
    fn through(a: (f64, f64), b: (f64, f64)) -> Self {
        let (x0, l0) = (a.0.ln(), a.1.ln());
        Self { x0, l0, k: -(b.1.ln() - l0) / (b.0.ln() - x0) }
    }

    fn ln_rate(&self, x: f64) -> f64 {
        self.l0 - self.k * (x - self.x0)
    }

    /// `integral_xa^xb lambda(x) f(x) dx` for the fragility `f` (mu = ln
    /// theta, beta > 0): the module doc's closed form.
    fn integral(&self, mu: f64, beta: f64, xa: f64, xb: f64) -> f64 {
        let kb = self.k * beta;
        let v = |x: f64| if x.is_infinite() { x } else { (x - mu) / beta + kb };
        (self.ln_rate(mu) + 0.5 * kb * kb + ln_phi_between(v(xa), v(xb))).exp()
    }
}

/// `ln(Phi(b) - Phi(a))` for `a < b` (either may be infinite), with its
/// digits where both lie far in one tail.
fn ln_phi_between(a: f64, b: f64) -> f64 {
    if b <= a {
        return f64::NEG_INFINITY;
    }
    if a >= 0.0 {
        // the right tail: Phi(b) - Phi(a) = Phi(-a) - Phi(-b)
        return ln_phi_between(-b, -a);
    }
    if b <= 0.0 {
        let lb = ln_phi(b);
        if a == f64::NEG_INFINITY {
            return lb;
        }
        return lb + (-(ln_phi(a) - lb).exp()).ln_1p();
    }
    (phi_cdf(b) - phi_cdf(a)).ln()
}

impl Hazard {
    /// The curve of `points`, `(intensity [g], annual frequency [1/year])`,
    /// checked (the error names the point by its index).
    pub fn new(points: Vec<(f64, f64)>) -> Result<Self, FragilityError> {
        let bad = |index: usize, reason: String| Err(FragilityError::Hazard { index, reason });
        if points.len() < 2 {
            let n = points.len();
            return bad(0, format!("{n} point{}: two at least are needed", if n == 1 { "" } else { "s" }));
        }
        for (index, &(im, rate)) in points.iter().enumerate() {
            if !(im.is_finite() && im > 0.0 && rate.is_finite() && rate > 0.0) {
                return bad(index, format!("intensity {im} and frequency {rate} must be positive and finite"));
            }
            if index > 0 && im <= points[index - 1].0 {
                return bad(index, format!("intensity {im} after {}: intensities must increase", points[index - 1].0));
            }
            if index > 0 && rate >= points[index - 1].1 {
                return bad(
                    index,
                    format!(
                        "frequency {rate} after {}: annual frequencies of exceedance must decrease as the intensity \
                         grows (a flat or rising stretch is no hazard curve)",
                        points[index - 1].1
                    ),
                );
            }
            if im >= PLAUSIBLE_FROM_G && rate > PLAUSIBLE_MAX_RATE {
                return bad(
                    index,
                    format!(
                        "{rate} per year at {im} g: no site exceeds {PLAUSIBLE_FROM_G} g more than once a year. Is \
                         the table a probability (in percent, or over 50 years)? The annual frequency of a \
                         probability P in T years is -ln(1 - P) / T (10 % in 50 years: 0.0021 per year)"
                    ),
                );
            }
        }
        Ok(Self { points })
    }

    /// The points, `(intensity [g], annual frequency [1/year])`.
    pub fn points(&self) -> &[(f64, f64)] {
        &self.points
    }

    /// The annual frequency of exceeding `im` \[1/year\] (log-log between
    /// the points, the end segments continued).
    pub fn rate(&self, im: f64) -> f64 {
        let x = im.ln();
        self.law(self.points.partition_point(|p| p.0.ln() < x)).ln_rate(x).exp()
    }

    /// The power law of segment `i` (between points `i - 1` and `i`),
    /// clamped to the end segments.
    fn law(&self, i: usize) -> Law {
        let i = i.clamp(1, self.points.len() - 1);
        Law::through(self.points[i - 1], self.points[i])
    }

    /// The parts of the mean annual frequency of the limit state with
    /// fragility `f` (beta 0: a step at the median, `lambda(theta)`).
    pub fn parts(&self, f: &Fragility) -> Parts {
        let n = self.points.len();
        let (x0, xn) = (self.points[0].0.ln(), self.points[n - 1].0.ln());
        let mu = f.median.ln();
        if f.beta == 0.0 {
            let rate = self.rate(f.median);
            let mut p = Parts { below: 0.0, within: 0.0, above: 0.0 };
            *(if mu < x0 {
                &mut p.below
            } else if mu > xn {
                &mut p.above
            } else {
                &mut p.within
            }) = rate;
            return p;
        }
        let within =
            (1..n).map(|i| self.law(i).integral(mu, f.beta, self.points[i - 1].0.ln(), self.points[i].0.ln())).sum();
        Parts {
            below: self.law(1).integral(mu, f.beta, f64::NEG_INFINITY, x0),
            within,
            above: self.law(n - 1).integral(mu, f.beta, xn, f64::INFINITY),
        }
    }

    /// The mean annual frequency \[1/year\] of the limit state with
    /// fragility `f`: an error when it is beyond what a number holds.
    pub fn mean_annual_frequency(&self, f: &Fragility) -> Result<f64, FragilityError> {
        if !(f.median.is_finite() && f.median > 0.0 && f.beta.is_finite() && f.beta >= 0.0) {
            return Err(FragilityError::Undetermined(format!(
                "median {} and beta {}: a fragility needs a positive median and a beta of 0 or more",
                f.median, f.beta
            )));
        }
        let total = self.parts(f).total();
        if !total.is_finite() {
            return Err(FragilityError::Undetermined(format!(
                "the annual frequency of median {} and beta {} on this hazard curve is beyond 1e308 per year: the \
                 fragility rests on the curve's continuation far below its lowest intensity",
                f.median, f.beta
            )));
        }
        Ok(total)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fragility(median: f64, beta: f64) -> Fragility {
        Fragility { median, beta, log_likelihood: 0.0, se_ln_median: 0.0, se_beta: 0.0 }
    }

    /// Simpson's rule in `x = ln im` over a window about the integrand's
    /// peak, piece by piece between the curve's points (where its slope
    /// breaks), fine enough to be exact to 1e-12: the second method.
    fn simpson(h: &Hazard, f: &Fragility) -> f64 {
        let (mu, beta) = (f.median.ln(), f.beta);
        let peak = mu - h.law(0).k.max(h.law(h.points.len()).k) * beta * beta;
        let (a, b) = (peak.min(mu) - 40.0 * beta, peak.max(mu) + 40.0 * beta);
        let g = |x: f64| {
            let u = (x - mu) / beta;
            h.rate(x.exp()) * (-0.5 * u * u).exp() / (beta * (2.0 * std::f64::consts::PI).sqrt())
        };
        let mut cuts: Vec<f64> = h.points.iter().map(|p| p.0.ln()).filter(|&x| x > a && x < b).collect();
        cuts.insert(0, a);
        cuts.push(b);
        let m = 100_000;
        cuts.windows(2)
            .map(|w| {
                let step = (w[1] - w[0]) / m as f64;
                let inner: f64 = (1..m).map(|i| g(w[0] + i as f64 * step) * if i % 2 == 1 { 4.0 } else { 2.0 }).sum();
                (inner + g(w[0]) + g(w[1])) * step / 3.0
            })
            .sum()
    }

    #[test]
    fn a_power_law_gives_cornells_closed_form_however_far_out_the_integrand_peaks() {
        let (k0, k) = (1e-4, 2.5);
        let h = Hazard::new([0.05f64, 0.1, 0.3, 1.0].iter().map(|&x| (x, k0 * x.powf(-k))).collect()).unwrap();
        // k beta up to 10: the peak at u = -k beta, where a window [-10, 10]
        // in u missed 50 % at k beta = 10
        for (median, beta) in [(0.8, 0.3), (1.2, 0.6), (0.5, 2.5), (0.5, 4.0), (2.0, 6.0)] {
            let got = h.mean_annual_frequency(&fragility(median, beta)).unwrap();
            let exact = k0 * f64::powf(median, -k) * (k * k * beta * beta / 2.0).exp();
            assert!((got / exact - 1.0).abs() < 1e-12, "theta {median} beta {beta}: {got:e} against {exact:e}");
        }
    }

    #[test]
    fn a_curve_of_several_slopes_agrees_with_simpsons_rule() {
        let h = Hazard::new(vec![(0.05, 0.05), (0.1, 0.02), (0.3, 2e-3), (0.6, 3e-4), (1.2, 2e-5)]).unwrap();
        for (median, beta) in [(0.4, 0.3), (0.08, 0.5), (1.5, 0.4), (0.7, 1.2)] {
            let f = fragility(median, beta);
            let (got, second) = (h.mean_annual_frequency(&f).unwrap(), simpson(&h, &f));
            assert!((got / second - 1.0).abs() < 1e-11, "theta {median} beta {beta}: {got:e} against {second:e}");
        }
    }

    /// Below a power-law hazard `k0 im^-k`'s point `x1 = ln im1`, the part
    /// of `lambda` has a closed form (completing the square): `lambda
    /// Phi((x1 - mu + k beta^2) / beta)`; above `x2` the rest, `lambda (1 -
    /// Phi((x2 - mu + k beta^2) / beta))`.
    #[test]
    fn the_parts_beyond_a_power_laws_ends_are_their_closed_form() {
        let (k0, k) = (1e-4, 2.5);
        for (median, beta) in [(0.3, 0.4), (0.05, 0.8), (1.2, 0.2)] {
            let f = fragility(median, beta);
            let lambda = k0 * f64::powf(median, -k) * (k * k * beta * beta / 2.0).exp();
            let mu = f64::ln(median);
            for (im1, im2) in [(0.1, 1.0), (0.02, 2.0)] {
                let h = Hazard::new([im1, f64::sqrt(im1 * im2), im2].iter().map(|&x| (x, k0 * x.powf(-k))).collect())
                    .unwrap();
                let p = h.parts(&f);
                let (x1, x2) = (f64::ln(im1), f64::ln(im2));
                let below = lambda * phi_cdf((x1 - mu + k * beta * beta) / beta);
                let above = lambda * (1.0 - phi_cdf((x2 - mu + k * beta * beta) / beta));
                assert!((p.below - below).abs() < 1e-9 * lambda, "below {im1}: {} against {below}", p.below);
                assert!((p.above - above).abs() < 1e-9 * lambda, "above {im2}: {} against {above}", p.above);
            }
        }
    }

    #[test]
    fn beta_zero_is_the_hazard_at_the_median() {
        let h = Hazard::new(vec![(0.1, 1e-2), (1.0, 1e-4)]).unwrap();
        for m in [0.05, 0.3, 2.0] {
            let got = h.mean_annual_frequency(&fragility(m, 0.0)).unwrap();
            assert!((got / (1e-4 * f64::powf(m, -2.0)) - 1.0).abs() < 1e-12, "{m}: {got}");
        }
    }

    #[test]
    fn flat_rising_and_implausible_curves_are_refused() {
        let e = |p: Vec<(f64, f64)>| Hazard::new(p).unwrap_err().to_string();
        assert!(e(vec![(0.1, 1e-2), (0.5, 1e-2)]).contains("must decrease"));
        assert!(e(vec![(0.1, 1e-2), (0.05, 1e-3)]).contains("must increase"));
        // 10 % and 2 % in 50 years, read as annual frequencies
        assert!(e(vec![(0.2, 10.0), (0.5, 2.0)]).contains("-ln(1 - P) / T"));
        assert!(e(vec![(0.1, f64::NAN), (0.5, 2.0)]).contains("positive and finite"));
        // more than once a year below 0.05 g is possible
        assert!(Hazard::new(vec![(0.01, 3.0), (0.1, 0.1)]).is_ok());
    }

    #[test]
    fn an_integral_beyond_any_number_is_an_error_not_infinity() {
        let h = Hazard::new(vec![(0.1, 1e-2), (1.0, 1e-5)]).unwrap();
        assert!(h.mean_annual_frequency(&fragility(1.0, 30.0)).is_err());
        assert!(h.mean_annual_frequency(&fragility(1.0, 10.0)).is_ok());
    }
}
