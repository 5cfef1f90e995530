//! Fragility functions (`quakejoint_model::fragility`): the lognormal fit of
//! stripe counts, its bootstrap over records, and the mean annual frequency
//! of a limit state over a hazard curve. Every argument is checked with the
//! ranges of `[sweep.fragility]` and refused with an `InputError` naming it.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict};
use quakejoint_model::fragility::{bootstrap_risk, fit, Fragility, Hazard, Stripe, MAX_BETA, MAX_SAMPLES};

use crate::convert::{real, shown, whole, Numbers};
use crate::InputError;

/// Whole numbers from 0 to `u32::MAX` (counts of runs).
fn counts(obj: &Bound<'_, PyAny>, func: &str, what: &str) -> PyResult<Vec<u32>> {
    Numbers::at_most_1d(obj, func, what)?
        .values
        .into_iter()
        .enumerate()
        .map(|(i, v)| {
            if v.fract() == 0.0 && (0.0..=u32::MAX as f64).contains(&v) {
                Ok(v as u32)
            } else {
                Err(InputError::new_err(format!(
                    "{func}: {what}[{i}] = {v}: counts are whole numbers from 0 to {}",
                    u32::MAX
                )))
            }
        })
        .collect()
}

fn fragility_error(func: &str, e: quakejoint_model::fragility::FragilityError) -> PyErr {
    InputError::new_err(format!("{func}: {e}"))
}

/// The stripes of `intensities`, `runs` and `exceeded`.
fn stripes(
    func: &str,
    intensities: &Bound<'_, PyAny>,
    runs: &Bound<'_, PyAny>,
    exceeded: &Bound<'_, PyAny>,
) -> PyResult<Vec<Stripe>> {
    let im = Numbers::at_most_1d(intensities, func, "intensities")?.values;
    let (n, z) = (counts(runs, func, "runs")?, counts(exceeded, func, "exceeded")?);
    if n.len() != im.len() || z.len() != im.len() {
        return Err(InputError::new_err(format!(
            "{func}: intensities, runs and exceeded must have one value a stripe ({}, {} and {} given)",
            im.len(),
            n.len(),
            z.len()
        )));
    }
    Ok(im
        .iter()
        .zip(n.iter().zip(&z))
        .map(|(&intensity, (&runs, &exceeded))| Stripe { intensity, runs, exceeded })
        .collect())
}

/// The hazard curve of `hazard_intensity` and `hazard_frequency`.
fn hazard(func: &str, x: &Bound<'_, PyAny>, y: &Bound<'_, PyAny>) -> PyResult<Hazard> {
    let x = Numbers::at_most_1d(x, func, "hazard_intensity")?.values;
    let y = Numbers::at_most_1d(y, func, "hazard_frequency")?.values;
    if x.len() != y.len() {
        return Err(InputError::new_err(format!(
            "{func}: hazard_intensity and hazard_frequency differ in length ({} and {})",
            x.len(),
            y.len()
        )));
    }
    Hazard::new(x.into_iter().zip(y).collect()).map_err(|e| match e {
        quakejoint_model::fragility::FragilityError::Hazard { index, reason } => {
            InputError::new_err(format!("{func}: hazard_intensity[{index}] and hazard_frequency[{index}]: {reason}"))
        }
        e => fragility_error(func, e),
    })
}

/// The lognormal fragility `Phi(ln(im / median) / beta)` by maximum
/// likelihood on stripe counts: at each intensity `intensities[s]`,
/// `exceeded[s]` of `runs[s]` runs exceeded the limit state. Returns a dict:
/// median, beta, log_likelihood, se_ln_median, se_beta.
#[pyfunction]
#[pyo3(signature = (intensities, runs, exceeded))]
fn fit_fragility<'py>(
    py: Python<'py>,
    intensities: &Bound<'py, PyAny>,
    runs: &Bound<'py, PyAny>,
    exceeded: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyDict>> {
    let func = "fit_fragility";
    let f = fit(&stripes(func, intensities, runs, exceeded)?).map_err(|e| fragility_error(func, e))?;
    let d = PyDict::new(py);
    for (k, v) in [
        ("median", f.median),
        ("beta", f.beta),
        ("log_likelihood", f.log_likelihood),
        ("se_ln_median", f.se_ln_median),
        ("se_beta", f.se_beta),
    ] {
        d.set_item(k, v)?;
    }
    Ok(d)
}

/// The outcomes `outcomes[r][s]`: 1, 0 or -1 each, one per stripe.
fn outcomes(obj: &Bound<'_, PyAny>, func: &str, stripes: usize) -> PyResult<Vec<Vec<Option<bool>>>> {
    let n = Numbers::of(obj, func, "outcomes")?;
    let records = match n.shape[..] {
        [r, s] if s == stripes => r,
        [_, s] => {
            return Err(InputError::new_err(format!(
                "{func}: outcomes has {s} values a record, intensities {stripes}: one outcome a stripe"
            )))
        }
        _ => {
            return Err(InputError::new_err(format!(
                "{func}: outcomes must be a 2-D array (record, stripe), not of shape {:?}",
                n.shape
            )))
        }
    };
    (0..records)
        .map(|r| {
            (0..stripes)
                .map(|s| match n.values[r * stripes + s] {
                    1.0 => Ok(Some(true)),
                    0.0 => Ok(Some(false)),
                    -1.0 => Ok(None),
                    v => Err(InputError::new_err(format!(
                        "{func}: outcomes[{r}][{s}] = {v}: 1 (exceeded), 0 (not) or -1 (a run that does not count)"
                    ))),
                })
                .collect()
        })
        .collect()
}

/// A seed: a whole number from 0 to 2**64 - 1.
fn seed(obj: &Bound<'_, PyAny>, func: &str) -> PyResult<u64> {
    let refuse = || InputError::new_err(format!("{func}: seed = {}: a whole number from 0 to 2**64 - 1", shown(obj)));
    if obj.is_instance_of::<PyBool>() {
        return Err(refuse());
    }
    obj.call_method0("__index__").and_then(|i| i.extract::<u64>()).map_err(|_| refuse())
}

/// Percentile intervals of the fragility's median and beta by the bootstrap
/// over records: `outcomes[r][s]` is record r's outcome at stripe s (1
/// exceeded, 0 not, -1 a run that does not count), `samples` resamples (1
/// to 100000; 1000 if not given) from `seed` (0 to 2**64 - 1, 0 if not
/// given; the same seed, the same intervals), at `level` (0.9 if not
/// given). The counts must determine a fit
/// (`fit_fragility`); it raises what `fit_fragility` raises otherwise.
/// Returns a dict: median and beta (each [low, high]), undetermined
/// (resamples left out: every run survived or every one exceeded),
/// separated (resamples whose counts are separated, entered with beta = 0
/// and the median in the gap) and, with a hazard curve
/// (`hazard_intensity`, `hazard_frequency`, as `limit_state_frequency`
/// takes it), annual_frequency ([low, high] over the same resamples).
#[pyfunction]
#[pyo3(signature = (outcomes, intensities, samples=None, seed=None, level=None, hazard_intensity=None, hazard_frequency=None))]
#[allow(clippy::too_many_arguments)]
fn bootstrap_fragility<'py>(
    py: Python<'py>,
    outcomes: &Bound<'py, PyAny>,
    intensities: &Bound<'py, PyAny>,
    samples: Option<&Bound<'py, PyAny>>,
    seed: Option<&Bound<'py, PyAny>>,
    level: Option<&Bound<'py, PyAny>>,
    hazard_intensity: Option<&Bound<'py, PyAny>>,
    hazard_frequency: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let func = "bootstrap_fragility";
    let curve = match (hazard_intensity, hazard_frequency) {
        (Some(x), Some(y)) => Some(hazard(func, x, y)?),
        (None, None) => None,
        _ => {
            return Err(InputError::new_err(format!(
                "{func}: give both hazard_intensity and hazard_frequency, or neither"
            )))
        }
    };
    let im = Numbers::at_most_1d(intensities, func, "intensities")?.values;
    let outcomes = self::outcomes(outcomes, func, im.len())?;
    let samples = samples.map_or(Ok(1000), |s| whole(s, func, "samples", 1, MAX_SAMPLES as i64))? as usize;
    let seed = seed.map_or(Ok(0), |s| self::seed(s, func))?;
    let level = level.map_or(Ok(0.9), |l| real(l, func, "level"))?;
    if !(level > 0.0 && level < 1.0) {
        return Err(InputError::new_err(format!("{func}: level = {level}: between 0 and 1 (0.9: 5 % to 95 %)")));
    }
    // the intervals of a fit: counts that determine none are refused as
    // fit_fragility refuses them
    let stripes: Vec<Stripe> = im
        .iter()
        .enumerate()
        .map(|(s, &intensity)| {
            let counted = outcomes.iter().filter_map(|r| r[s]);
            let (runs, exceeded) = counted.fold((0u32, 0u32), |(n, z), e| (n + 1, z + u32::from(e)));
            Stripe { intensity, runs, exceeded }
        })
        .collect();
    fit(&stripes).map_err(|e| fragility_error(func, e))?;
    let i = py
        .detach(|| bootstrap_risk(&outcomes, &im, samples, seed, level, curve.as_ref()))
        .map_err(|e| fragility_error(func, e))?;
    let d = PyDict::new(py);
    d.set_item("median", i.median.to_vec())?;
    d.set_item("beta", i.beta.to_vec())?;
    d.set_item("level", i.level)?;
    d.set_item("undetermined", i.undetermined)?;
    d.set_item("separated", i.separated)?;
    if let Some(a) = i.annual_frequency {
        d.set_item("annual_frequency", a.to_vec())?;
    }
    Ok(d)
}

/// The mean annual frequency [1/year] of a limit state with the fragility
/// (`median` [g], `beta`, at most 10 as `fit_fragility` gives it) at a site
/// whose hazard curve gives the annual frequency `hazard_frequency[i]`
/// (decreasing) of exceeding `hazard_intensity[i]` [g] (increasing), joined
/// straight in log-log and continued by its end segments: exact, in closed
/// form. A `UserWarning` says when more than 1 % of it comes from beyond
/// the curve's ends.
#[pyfunction]
#[pyo3(signature = (median, beta, hazard_intensity, hazard_frequency))]
fn limit_state_frequency(
    py: Python<'_>,
    median: &Bound<'_, PyAny>,
    beta: &Bound<'_, PyAny>,
    hazard_intensity: &Bound<'_, PyAny>,
    hazard_frequency: &Bound<'_, PyAny>,
) -> PyResult<f64> {
    let func = "limit_state_frequency";
    let (median, beta) = (real(median, func, "median")?, real(beta, func, "beta")?);
    if !(median > 0.0 && median.is_finite()) {
        return Err(InputError::new_err(format!("{func}: median = {median}: a positive intensity [g]")));
    }
    if !(beta > 0.0 && beta <= MAX_BETA) {
        return Err(InputError::new_err(format!(
            "{func}: beta = {beta}: above 0 and at most {MAX_BETA} (beyond it the limit state does not depend on the \
             intensity; fit_fragility gives no such fit)"
        )));
    }
    let curve = hazard(func, hazard_intensity, hazard_frequency)?;
    let f = Fragility { median, beta, log_likelihood: f64::NAN, se_ln_median: f64::NAN, se_beta: f64::NAN };
    let lambda = curve.mean_annual_frequency(&f).map_err(|e| fragility_error(func, e))?;
    let parts = curve.parts(&f);
    let beyond = (parts.below + parts.above) / lambda;
    if beyond > 0.01 {
        let warning = format!(
            "{func}: {:.0} % of the annual frequency comes from beyond the hazard curve's ends ({} to {} g), where it \
             is continued by its end segments' power laws: extend the curve",
            100.0 * beyond.min(1.0),
            curve.points()[0].0,
            curve.points()[curve.points().len() - 1].0
        );
        let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
        PyErr::warn(py, &category, &std::ffi::CString::new(warning)?, 1)?;
    }
    Ok(lambda)
}

/// Adds the fragility functions to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(fit_fragility, m)?)?;
    m.add_function(wrap_pyfunction!(bootstrap_fragility, m)?)?;
    m.add_function(wrap_pyfunction!(limit_state_frequency, m)?)?;
    Ok(())
}
