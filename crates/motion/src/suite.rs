//! Scaling a suite of records to a target spectrum ([`crate::target`]).
//!
//! Each record gets the factor that fits its spectrum to the target over a
//! period range by least squares in logarithms, `ln f_i = mean_k ln(Se(T_k) /
//! Sa_i(T_k))` over 60 log-spaced periods `T_k` of the range: the geometric
//! mean of the target-to-record ratios, so that a record too strong at some
//! periods and too weak at others is fitted in proportion rather than by its
//! strongest ordinates. The suite is then checked against the Eurocode 8
//! rule (EN 1998-1:2004, 3.2.3.1.2 (4)c): over the range (0.2 T1 to 2 T1 in
//! the code) the mean of the scaled records' spectra must not fall below
//! 90 % of the target (at the target's damping, 5 % unless it says
//! otherwise); and (4)b, the mean PGA not below `a_g S`, is reported. With [`SuiteRule::Ec8`] the whole suite is scaled up
//! by the common factor that brings the mean's lowest ratio to 0.9 when it
//! falls short; with [`SuiteRule::Check`] it is only reported.

use serde::{Deserialize, Serialize};

use crate::error::SpectrumError;
use crate::record::Record;
use crate::spectrum::spectrum_samples;
use crate::target::TargetSpectrum;
use crate::SpectrumOptions;

/// Periods of the fit within the range.
pub const FIT_PERIODS: usize = 60;
/// The Eurocode 8 bound on the suite's mean over the target [-].
pub const EC8_MEAN_RATIO: f64 = 0.9;

/// What to do when the suite's mean falls below 90 % of the target.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SuiteRule {
    /// Scale the whole suite up until the mean is 90 % of the target at its
    /// lowest (Eurocode 8, 3.2.3.1.2 (4)c).
    #[default]
    Ec8,
    /// Report the check only.
    Check,
}

/// The scaling of a suite.
#[derive(Debug, Clone, PartialEq)]
pub struct SuiteScaling {
    /// Factor of each record [-], on top of its own scale, the rule's
    /// common factor included.
    pub factors: Vec<f64>,
    /// The rule's common factor [-] (1 when the fit alone satisfies it).
    pub rule_factor: f64,
    /// Periods of the fit \[s\].
    pub periods: Vec<f64>,
    /// The target at those periods [m/s^2].
    pub target: Vec<f64>,
    /// The mean of the scaled records' spectra there [m/s^2].
    pub mean: Vec<f64>,
    /// Lowest ratio of the mean to the target over the range [-], and the
    /// period where it is \[s\].
    pub min_ratio: (f64, f64),
    /// Whether the mean stays at or above 90 % of the target.
    pub ec8_satisfied: bool,
    /// The mean of the scaled records' PGA over the target at T = 0 [-]
    /// (Eurocode 8, 3.2.3.1.2 (4)b, asks for at least 1: the mean PGA not
    /// below `a_g S`; NaN for a table that does not reach T = 0).
    pub pga_ratio: f64,
    /// What a user should know (too few records for a mean, large factors).
    pub warnings: Vec<String>,
}

/// Scales `records` (each acting alone, in m/s^2) to `target` over the
/// periods `range` \[s\].
pub fn scale_suite(
    records: &[&Record],
    target: &TargetSpectrum,
    range: (f64, f64),
    rule: SuiteRule,
) -> Result<SuiteScaling, SpectrumError> {
    target.validate()?;
    let (lo, hi) = range;
    if !(lo.is_finite() && hi.is_finite() && 0.0 < lo && lo < hi && hi <= 10.0) {
        return Err(SpectrumError::Suite(format!("range [{lo}, {hi}] s: needs 0 < from < to <= 10 s")));
    }
    let (d0, d1) = target.domain();
    if lo < d0 || hi > d1 {
        return Err(SpectrumError::Suite(format!(
            "range [{lo}, {hi}] s is outside the target table's periods ({d0} to {d1} s)"
        )));
    }
    if records.is_empty() {
        return Err(SpectrumError::Suite("no records".into()));
    }
    let periods = crate::period_range(lo, hi, FIT_PERIODS, true)?;
    let target_sa: Vec<f64> = periods.iter().map(|&t| target.sa(t)).collect();
    let damping = [target.damping()];
    let mut spectra = Vec::with_capacity(records.len());
    let mut factors = Vec::with_capacity(records.len());
    for r in records {
        let rows = spectrum_samples(&r.acceleration, r.dt, &periods, &damping, SpectrumOptions::default())?;
        let sa: Vec<f64> = rows.iter().map(|row| row.peaks.sa).collect();
        if let Some(k) = sa.iter().position(|s| s.is_nan() || *s <= 0.0) {
            return Err(SpectrumError::Suite(format!(
                "record {:?} has no response at T = {} s: it cannot be scaled to a spectrum",
                r.name, periods[k]
            )));
        }
        let log_ratio = sa.iter().zip(&target_sa).map(|(s, t)| (t / s).ln()).sum::<f64>() / sa.len() as f64;
        factors.push(log_ratio.exp());
        spectra.push(sa);
    }
    let mean_of = |factors: &[f64]| -> Vec<f64> {
        (0..periods.len())
            .map(|k| spectra.iter().zip(factors).map(|(s, f)| f * s[k]).sum::<f64>() / spectra.len() as f64)
            .collect()
    };
    let lowest = |mean: &[f64]| {
        let (k, ratio) = mean
            .iter()
            .zip(&target_sa)
            .map(|(m, t)| m / t)
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .expect("periods not empty");
        (ratio, periods[k])
    };
    let mut mean = mean_of(&factors);
    let mut min_ratio = lowest(&mean);
    let mut rule_factor = 1.0;
    if rule == SuiteRule::Ec8 && min_ratio.0 < EC8_MEAN_RATIO {
        rule_factor = EC8_MEAN_RATIO / min_ratio.0;
        factors.iter_mut().for_each(|f| *f *= rule_factor);
        mean = mean_of(&factors);
        min_ratio = lowest(&mean);
    }
    let mean_pga = records.iter().zip(&factors).map(|(r, f)| f * r.pga()).sum::<f64>() / records.len() as f64;
    let pga_ratio = mean_pga / target.sa(0.0);
    let mut warnings = Vec::new();
    if matches!(target, TargetSpectrum::Ec8 { .. }) && pga_ratio < 1.0 {
        warnings.push(format!(
            "the scaled records' mean PGA is {:.1} % of a_g S: Eurocode 8 asks for at least a_g S (EN 1998-1, \
             3.2.3.1.2 (4)b)",
            100.0 * pga_ratio
        ));
    }
    if records.len() < 3 {
        warnings
            .push(format!("{} record(s): Eurocode 8 asks for at least 3 (EN 1998-1, 3.2.3.1.2 (4)a)", records.len()));
    } else if records.len() < 7 {
        warnings.push(format!(
            "{} records: with fewer than 7, Eurocode 8 designs for the largest response, not the mean (EN 1998-1, \
             4.3.3.4.3 (3)); the mean and dispersion are reported as for any suite",
            records.len()
        ));
    }
    for (r, f) in records.iter().zip(&factors) {
        if !(0.25..=4.0).contains(f) {
            warnings.push(format!(
                "record {:?} is scaled by {f:.3}: factors beyond 0.25 to 4 change a record's character (its \
                 magnitude and distance no longer match its intensity)",
                r.name
            ));
        }
    }
    Ok(SuiteScaling {
        factors,
        rule_factor,
        periods,
        target: target_sa,
        mean,
        min_ratio,
        ec8_satisfied: min_ratio.0 >= EC8_MEAN_RATIO * (1.0 - 1e-12),
        pga_ratio,
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::target::TargetSpectrum;
    use crate::G;

    /// A broadband record: a sum of sines with a slowly varying envelope.
    fn record(name: &str, scale: f64) -> Record {
        let dt = 0.01;
        let a: Vec<f64> = (0..2000)
            .map(|i| {
                let t = i as f64 * dt;
                let env = (std::f64::consts::PI * t / 20.0).sin().powi(2);
                scale
                    * env
                    * [0.7, 1.3, 2.9, 5.3].iter().map(|f| (2.0 * std::f64::consts::PI * f * t).sin()).sum::<f64>()
            })
            .collect();
        Record::new(name, dt, a).unwrap()
    }

    /// The target is the base record's own spectrum (a table); a suite of the
    /// same record scaled by known factors must come back with their
    /// inverses, and its mean on the target.
    #[test]
    fn a_suite_of_one_record_scaled_by_known_factors_recovers_them() {
        let base = record("base", 1.0);
        let periods = crate::period_range(0.1, 3.0, 200, true).unwrap();
        let rows = crate::spectrum(&base, &periods, &[0.05], SpectrumOptions::default()).unwrap();
        let points: Vec<[f64; 2]> = rows.iter().map(|r| [r.period, r.peaks.sa / G]).collect();
        let target = TargetSpectrum::Table { points, damping: 0.05 };
        let known = [0.5, 2.0, 3.0];
        let suite: Vec<Record> = known.iter().map(|&k| record(&format!("x{k}"), k)).collect();
        let refs: Vec<&Record> = suite.iter().collect();
        // the fit periods fall between the table's: log-log interpolation of
        // a smooth spectrum, so the factors agree to the interpolation error
        let s = scale_suite(&refs, &target, (0.2, 2.0), SuiteRule::Check).unwrap();
        for (f, k) in s.factors.iter().zip(known) {
            assert!((f * k - 1.0).abs() < 2e-3, "factor {f} for a record scaled by {k}");
        }
        // pointwise, the table's interpolation error shows (0.6 % at its worst)
        assert!((s.min_ratio.0 - 1.0).abs() < 1e-2 && s.ec8_satisfied && s.rule_factor == 1.0, "{:?}", s.min_ratio);
    }

    /// Exactly: with a table through the fit periods themselves, the
    /// recovered factors are exact to rounding.
    #[test]
    fn factors_are_exact_on_the_fit_periods() {
        let base = record("base", 1.0);
        let periods = crate::period_range(0.2, 2.0, FIT_PERIODS, true).unwrap();
        let rows = crate::spectrum(&base, &periods, &[0.05], SpectrumOptions::default()).unwrap();
        let points: Vec<[f64; 2]> = rows.iter().map(|r| [r.period, r.peaks.sa / G]).collect();
        let target = TargetSpectrum::Table { points, damping: 0.05 };
        let suite = [record("a", 0.25), record("b", 4.0)];
        let s = scale_suite(&[&suite[0], &suite[1]], &target, (0.2, 2.0), SuiteRule::Ec8).unwrap();
        assert!((s.factors[0] - 4.0).abs() < 1e-9 && (s.factors[1] - 0.25).abs() < 1e-9, "{:?}", s.factors);
    }

    /// A suite whose mean dips below 90 % somewhere is scaled up by the
    /// rule until its lowest ratio is 0.9, and only reported without it.
    #[test]
    fn the_eurocode_8_rule_scales_the_suite_up() {
        let target =
            TargetSpectrum::Ec8 { kind: crate::target::Ec8Type::One, ground: "C".into(), ag_g: 0.3, damping: 0.05 };
        let suite = [record("a", 1.0), record("b", 0.5)];
        let refs = [&suite[0], &suite[1]];
        let checked = scale_suite(&refs, &target, (0.2, 2.0), SuiteRule::Check).unwrap();
        assert!(checked.min_ratio.0 < 0.9 && !checked.ec8_satisfied, "{:?}", checked.min_ratio);
        let ruled = scale_suite(&refs, &target, (0.2, 2.0), SuiteRule::Ec8).unwrap();
        assert!((ruled.min_ratio.0 - 0.9).abs() < 1e-12 && ruled.ec8_satisfied);
        assert!((ruled.rule_factor - 0.9 / checked.min_ratio.0).abs() < 1e-12);
        for (r, c) in ruled.factors.iter().zip(&checked.factors) {
            assert!((r / c - ruled.rule_factor).abs() < 1e-12);
        }
        assert!(ruled.warnings.iter().any(|w| w.contains("at least 3")));
    }

    #[test]
    fn bad_ranges_are_refused() {
        let target = TargetSpectrum::Asce7 { sds_g: 1.0, sd1_g: 0.6, tl: 8.0 };
        let r = record("a", 1.0);
        for range in [(0.0, 1.0), (2.0, 1.0), (0.1, 20.0)] {
            assert!(scale_suite(&[&r], &target, range, SuiteRule::Ec8).is_err());
        }
        let table = TargetSpectrum::Table { points: vec![[0.5, 1.0], [1.0, 0.5]], damping: 0.05 };
        let e = scale_suite(&[&r], &table, (0.2, 1.0), SuiteRule::Ec8).unwrap_err().to_string();
        assert!(e.contains("outside the target table"), "{e}");
    }
}
