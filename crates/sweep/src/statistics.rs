//! Statistics of a sweep's spectral accelerations over its records (a
//! ground-motion suite): per case, damping ratio and period, the mean,
//! median and dispersion (standard deviation of ln Sa) with and without the
//! joint, and of the reduction 1 - Sa_with / Sa_without.
//!
//! A statistic over a suite stands for the suite only when every record's
//! job finished: where one failed or has not run it is NaN, and `count`
//! says how many did. Flagged jobs (outside the model's validity) are
//! counted in, and `flagged` says how many there are.

use crate::results::{status, Results};
use quakejoint_model::validity::Flags;

/// Mean, median and standard deviation of ln x of positive values
/// (dispersion), or of x itself (`log = false`); sample standard deviation
/// (n - 1), NaN for one value.
pub fn summary(values: &[f64], log: bool) -> (f64, f64, f64) {
    let n = values.len();
    // a value that is not a number (or not positive, for logarithms) makes
    // every statistic undefined rather than quietly left out
    if n == 0 || values.iter().any(|v| !v.is_finite() || (log && *v <= 0.0)) {
        return (f64::NAN, f64::NAN, f64::NAN);
    }
    let mean = values.iter().sum::<f64>() / n as f64;
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let median = if n % 2 == 1 { sorted[n / 2] } else { 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]) };
    let xs: Vec<f64> = if log { values.iter().map(|v| v.ln()).collect() } else { values.to_vec() };
    let m = xs.iter().sum::<f64>() / n as f64;
    let spread =
        if n > 1 { (xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1) as f64).sqrt() } else { f64::NAN };
    (mean, median, spread)
}

/// The statistics of a sweep; arrays over (case, damping, period), or
/// (damping, period) without the joint (over (case, damping, period) too
/// when the bridge alone differs between the cases,
/// [`Results::without_per_case`]), flat and row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct Statistics {
    /// Mean Sa with the joint [m/s^2].
    pub with_mean: Vec<f64>,
    /// Median Sa with the joint [m/s^2].
    pub with_median: Vec<f64>,
    /// Standard deviation of ln Sa with the joint [-].
    pub with_dispersion: Vec<f64>,
    /// Mean Sa without the joint [m/s^2].
    pub without_mean: Vec<f64>,
    /// Median Sa without the joint [m/s^2].
    pub without_median: Vec<f64>,
    /// Standard deviation of ln Sa without the joint [-].
    pub without_dispersion: Vec<f64>,
    /// Mean of the records' reductions [-].
    pub reduction_mean: Vec<f64>,
    /// Median of the records' reductions [-].
    pub reduction_median: Vec<f64>,
    /// Standard deviation of the records' reductions [-].
    pub reduction_std: Vec<f64>,
    /// `1 - mean with / mean without` [-].
    pub reduction_of_mean: Vec<f64>,
    /// Records whose job finished.
    pub count: Vec<u32>,
    /// Of them, flagged as outside the model's validity.
    pub flagged: Vec<u32>,
}

impl Statistics {
    /// Over the records of `r`.
    pub fn of(r: &Results) -> Self {
        let [nc, nr, nz, nt] = r.dims;
        let sa = &r.values[Results::field("sa")];
        let reduction = r.reduction();
        let n3 = nc * nz * nt;
        let nan = || vec![f64::NAN; n3];
        // the bridge alone's cases: one, or every case
        let ncw = if r.without_per_case { nc } else { 1 };
        let mut s = Statistics {
            with_mean: nan(),
            with_median: nan(),
            with_dispersion: nan(),
            without_mean: vec![f64::NAN; ncw * nz * nt],
            without_median: vec![f64::NAN; ncw * nz * nt],
            without_dispersion: vec![f64::NAN; ncw * nz * nt],
            reduction_mean: nan(),
            reduction_median: nan(),
            reduction_std: nan(),
            reduction_of_mean: nan(),
            count: vec![0; n3],
            flagged: vec![0; n3],
        };
        for cw in 0..ncw {
            for z in 0..nz {
                for t in 0..nt {
                    let without: Vec<f64> =
                        (0..nr).map(|rr| r.without[0][r.without_index(((cw * nr + rr) * nz + z) * nt + t)]).collect();
                    let k = (cw * nz + z) * nt + t;
                    (s.without_mean[k], s.without_median[k], s.without_dispersion[k]) = summary(&without, true);
                }
            }
        }
        for z in 0..nz {
            for t in 0..nt {
                for c in 0..nc {
                    let m = s.without_mean[((c % ncw) * nz + z) * nt + t];
                    let jobs: Vec<usize> = (0..nr).map(|rr| ((c * nr + rr) * nz + z) * nt + t).collect();
                    let done: Vec<usize> = jobs.iter().copied().filter(|&j| r.status[j] == status::OK).collect();
                    let i = (c * nz + z) * nt + t;
                    s.count[i] = done.len() as u32;
                    s.flagged[i] = done.iter().filter(|&&j| Flags(r.validity[j]).is_flagged()).count() as u32;
                    if done.len() < nr {
                        continue; // not the suite's statistic
                    }
                    let with: Vec<f64> = done.iter().map(|&j| sa[j]).collect();
                    (s.with_mean[i], s.with_median[i], s.with_dispersion[i]) = summary(&with, true);
                    let red: Vec<f64> = done.iter().map(|&j| reduction[j]).collect();
                    (s.reduction_mean[i], s.reduction_median[i], s.reduction_std[i]) = summary(&red, false);
                    s.reduction_of_mean[i] = 1.0 - s.with_mean[i] / m;
                }
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// By hand: 1, 2, 4 have mean 7/3, median 2 and ln values 0, ln 2,
    /// 2 ln 2 with mean ln 2 and sample standard deviation ln 2.
    #[test]
    fn summary_by_hand() {
        let (m, med, d) = summary(&[4.0, 1.0, 2.0], true);
        assert!((m - 7.0 / 3.0).abs() < 1e-15 && med == 2.0 && (d - 2f64.ln()).abs() < 1e-15);
        let (m, med, sd) = summary(&[0.1, -0.1, 0.3, 0.5], false);
        assert!((m - 0.2).abs() < 1e-15 && (med - 0.2).abs() < 1e-15);
        assert!((sd - (0.2f64 / 3.0).sqrt()).abs() < 1e-15);
    }

    #[test]
    fn a_missing_record_leaves_the_suites_statistic_undefined() {
        let mut r = Results::new([1, 3, 1, 2]);
        r.without[0] = vec![1.0, 2.0, 2.0, 4.0, 4.0, 8.0];
        let sa = Results::field("sa");
        for (j, v) in [0.9, 1.8, 1.8, 3.6, 3.6, 7.2].into_iter().enumerate() {
            if j == 5 {
                continue; // the last record's second period did not run
            }
            r.values[sa][j] = v;
            r.status[j] = status::OK;
            r.validity[j] = 0;
        }
        let s = Statistics::of(&r);
        assert_eq!(s.count, vec![3, 2]);
        assert!((s.with_mean[0] - 6.3 / 3.0).abs() < 1e-12 && s.with_mean[1].is_nan());
        assert!((s.reduction_mean[0] - 0.1).abs() < 1e-12 && s.reduction_std[0].abs() < 1e-12);
        assert!((s.reduction_of_mean[0] - 0.1).abs() < 1e-12);
        assert!((s.without_mean[1] - 14.0 / 3.0).abs() < 1e-12);
    }
}
