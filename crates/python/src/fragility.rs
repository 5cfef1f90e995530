//! Fragility functions (`quakejoint_model::fragility`): the lognormal fit of
//! stripe counts, its bootstrap over records, and the mean annual frequency
//! of a limit state over a hazard curve.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use quakejoint_model::fragility::{bootstrap_risk, fit, mean_annual_frequency, Fragility, Stripe};

use crate::convert::{real, Numbers};
use crate::InputError;

fn counts(obj: &Bound<'_, PyAny>, func: &str, what: &str) -> PyResult<Vec<u32>> {
    Numbers::at_most_1d(obj, func, what)?
        .values
        .into_iter()
        .map(|v| {
            if v.fract() == 0.0 && (0.0..=u32::MAX as f64).contains(&v) {
                Ok(v as u32)
            } else {
                Err(InputError::new_err(format!("{func}: {what} = {v}: must be whole numbers from 0")))
            }
        })
        .collect()
}

fn fragility_error(e: quakejoint_model::fragility::FragilityError) -> PyErr {
    InputError::new_err(e.to_string())
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
    let im = Numbers::at_most_1d(intensities, "fit_fragility", "intensities")?.values;
    let (n, z) = (counts(runs, "fit_fragility", "runs")?, counts(exceeded, "fit_fragility", "exceeded")?);
    if n.len() != im.len() || z.len() != im.len() {
        return Err(InputError::new_err("fit_fragility: intensities, runs and exceeded must have one value a stripe"));
    }
    let stripes: Vec<Stripe> = im
        .iter()
        .zip(n.iter().zip(&z))
        .map(|(&intensity, (&runs, &exceeded))| Stripe { intensity, runs, exceeded })
        .collect();
    let f = fit(&stripes).map_err(fragility_error)?;
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

/// Percentile intervals of the fragility's median and beta by the bootstrap
/// over records: `outcomes[r][s]` is record r's outcome at stripe s (1
/// exceeded, 0 not, -1 a run that does not count), `samples` resamples from
/// `seed` (the same seed, the same intervals), at `level`. Returns a dict:
/// median and beta (each [low, high]), undetermined (resamples left out:
/// every run survived or every one exceeded), separated (resamples whose
/// counts are separated, entered with beta = 0 and the median in the gap)
/// and, with a hazard curve (`hazard_intensity`, `hazard_frequency`, as
/// `limit_state_frequency` takes it), annual_frequency ([low, high] over
/// the same resamples).
#[pyfunction]
#[pyo3(signature = (outcomes, intensities, samples=1000, seed=0, level=0.9, hazard_intensity=None, hazard_frequency=None))]
#[allow(clippy::too_many_arguments)]
fn bootstrap_fragility<'py>(
    py: Python<'py>,
    outcomes: Vec<Vec<i64>>,
    intensities: &Bound<'py, PyAny>,
    samples: usize,
    seed: u64,
    level: f64,
    hazard_intensity: Option<&Bound<'py, PyAny>>,
    hazard_frequency: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let func = "bootstrap_fragility";
    let hazard: Option<Vec<(f64, f64)>> = match (hazard_intensity, hazard_frequency) {
        (Some(x), Some(y)) => {
            let x = Numbers::at_most_1d(x, func, "hazard_intensity")?.values;
            let y = Numbers::at_most_1d(y, func, "hazard_frequency")?.values;
            if x.len() != y.len() {
                return Err(InputError::new_err(format!(
                    "{func}: hazard_intensity and hazard_frequency differ in length"
                )));
            }
            Some(x.into_iter().zip(y).collect())
        }
        (None, None) => None,
        _ => {
            return Err(InputError::new_err(format!(
                "{func}: give both hazard_intensity and hazard_frequency, or neither"
            )))
        }
    };
    let im = Numbers::at_most_1d(intensities, "bootstrap_fragility", "intensities")?.values;
    let outcomes: Vec<Vec<Option<bool>>> = outcomes
        .iter()
        .map(|r| {
            if r.len() != im.len() {
                return Err(InputError::new_err("bootstrap_fragility: every record needs one outcome a stripe"));
            }
            r.iter()
                .map(|&o| match o {
                    1 => Ok(Some(true)),
                    0 => Ok(Some(false)),
                    -1 => Ok(None),
                    v => Err(InputError::new_err(format!("bootstrap_fragility: outcome {v}: must be 1, 0 or -1"))),
                })
                .collect()
        })
        .collect::<PyResult<_>>()?;
    if !(level > 0.0 && level < 1.0) {
        return Err(InputError::new_err(format!("bootstrap_fragility: level = {level}: must be between 0 and 1")));
    }
    let i = py
        .detach(|| bootstrap_risk(&outcomes, &im, samples, seed, level, hazard.as_deref()))
        .map_err(fragility_error)?;
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
/// (`median`, `beta`) at a site whose hazard curve gives the annual
/// frequency `hazard_frequency[i]` of exceeding `hazard_intensity[i]`
/// (joined straight in log-log, continued by its end segments).
#[pyfunction]
#[pyo3(signature = (median, beta, hazard_intensity, hazard_frequency))]
fn limit_state_frequency(
    median: &Bound<'_, PyAny>,
    beta: &Bound<'_, PyAny>,
    hazard_intensity: &Bound<'_, PyAny>,
    hazard_frequency: &Bound<'_, PyAny>,
) -> PyResult<f64> {
    let func = "limit_state_frequency";
    let (median, beta) = (real(median, func, "median")?, real(beta, func, "beta")?);
    if !(median > 0.0 && beta > 0.0 && median.is_finite() && beta.is_finite()) {
        return Err(InputError::new_err(format!("{func}: median and beta must be positive")));
    }
    let x = Numbers::at_most_1d(hazard_intensity, func, "hazard_intensity")?.values;
    let y = Numbers::at_most_1d(hazard_frequency, func, "hazard_frequency")?.values;
    if x.len() != y.len() {
        return Err(InputError::new_err(format!("{func}: hazard_intensity and hazard_frequency differ in length")));
    }
    let f = Fragility { median, beta, log_likelihood: f64::NAN, se_ln_median: f64::NAN, se_beta: f64::NAN };
    let hazard: Vec<(f64, f64)> = x.into_iter().zip(y).collect();
    mean_annual_frequency(&f, &hazard).map_err(fragility_error)
}

/// Adds the fragility functions to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(fit_fragility, m)?)?;
    m.add_function(wrap_pyfunction!(bootstrap_fragility, m)?)?;
    m.add_function(wrap_pyfunction!(limit_state_frequency, m)?)?;
    Ok(())
}
