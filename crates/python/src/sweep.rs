//! Sweep files read by the command line's own reader
//! (`quakejoint_sweep::sweep_read`): every dataset and attribute read and
//! checked (checksums, what is derived against what it is derived from,
//! the fragility against the results), the same refusal for a damaged
//! file, then handed to Python as arrays (`python/quakejoint/sweep.py`
//! labels them).

use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use quakejoint_io::read::AttrValue;
use quakejoint_sweep::fragility::{count_arrays, curve_arrays, StoredFragility};
use quakejoint_sweep::results::{Results, FIELDS, JOINT_FIELDS, UNITS};
use quakejoint_sweep::statistics::Statistics;
use quakejoint_sweep::sweep_h5::SweepFile;

use crate::InputError;

/// An array of `values` with `shape`.
fn array<'py, T: numpy::Element + Clone>(
    py: Python<'py>,
    values: &[T],
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_slice(py, values).reshape(shape.to_vec())?.into_any())
}

/// Text with `shape`: (flat list, shape), which Python makes an object array.
fn texts<'py>(py: Python<'py>, values: &[String], shape: &[usize]) -> PyResult<Bound<'py, PyAny>> {
    Ok((PyList::new(py, values)?, shape.to_vec()).into_pyobject(py)?.into_any())
}

fn attr_value<'py>(py: Python<'py>, v: &AttrValue) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        AttrValue::Text(s) => s.into_pyobject(py)?.into_any(),
        AttrValue::Int(i) => i.into_pyobject(py)?.into_any(),
        AttrValue::UInt(u) => u.into_pyobject(py)?.into_any(),
        AttrValue::Float(x) => x.into_pyobject(py)?.into_any(),
    })
}

/// The results' arrays: with and without the joint, status, validity,
/// messages, findings, reduction, every joint of a modal bridge, the
/// statistics over the records.
fn results<'py>(py: Python<'py>, r: &Results, d: &Bound<'py, PyDict>) -> PyResult<()> {
    let dims = r.dims;
    let [nc, _, nz, nt] = dims;
    let with = PyDict::new(py);
    let units = PyDict::new(py);
    for ((name, unit), values) in FIELDS.iter().zip(UNITS.iter()).zip(&r.values) {
        with.set_item(name, array(py, values, &dims)?)?;
        units.set_item(name, unit)?;
    }
    let without = PyDict::new(py);
    let shape: Vec<usize> = if r.without_per_case { dims.to_vec() } else { dims[1..].to_vec() };
    for ((name, unit), values) in quakejoint_model::fields::SPECTRAL.iter().zip(&r.without) {
        without.set_item(name, array(py, values, &shape)?)?;
        units.set_item(name, unit)?;
    }
    let joints = PyDict::new(py);
    for joint in &r.joints {
        let j = PyDict::new(py);
        for ((name, unit), values) in JOINT_FIELDS.iter().zip(&joint.values) {
            j.set_item(name, array(py, values, &dims)?)?;
            units.set_item(format!("{}:{name}", joint.name), unit)?;
        }
        j.set_item("validity", array(py, &joint.validity, &dims)?)?;
        joints.set_item(&joint.name, j)?;
    }
    d.set_item("with_joint", with)?;
    d.set_item("without_joint", without)?;
    d.set_item("units", units)?;
    d.set_item("joints", joints)?;
    d.set_item("status", array(py, &r.status, &dims)?)?;
    d.set_item("validity", array(py, &r.validity, &dims)?)?;
    d.set_item("message", texts(py, &r.messages, &dims)?)?;
    d.set_item("findings", texts(py, &r.findings, &dims)?)?;
    d.set_item("reduction", array(py, &r.reduction(), &dims)?)?;
    let st = Statistics::of(r);
    let czt = [nc, nz, nt];
    let without_shape: &[usize] = if r.without_per_case { &czt } else { &czt[1..] };
    let group = |pairs: &[(&str, &[f64], &[usize])]| -> PyResult<Bound<'py, PyDict>> {
        let g = PyDict::new(py);
        for (name, values, shape) in pairs {
            g.set_item(name, array(py, values, shape)?)?;
        }
        Ok(g)
    };
    let s = PyDict::new(py);
    s.set_item(
        "with_joint",
        group(&[
            ("mean", &st.with_mean, &czt),
            ("median", &st.with_median, &czt),
            ("dispersion", &st.with_dispersion, &czt),
        ])?,
    )?;
    s.set_item(
        "without_joint",
        group(&[
            ("mean", &st.without_mean, without_shape),
            ("median", &st.without_median, without_shape),
            ("dispersion", &st.without_dispersion, without_shape),
        ])?,
    )?;
    s.set_item(
        "reduction",
        group(&[
            ("mean", &st.reduction_mean, &czt),
            ("median", &st.reduction_median, &czt),
            ("std", &st.reduction_std, &czt),
            ("of_mean", &st.reduction_of_mean, &czt),
        ])?,
    )?;
    s.set_item("count", array(py, &st.count, &czt)?)?;
    s.set_item("flagged", array(py, &st.flagged, &czt)?)?;
    d.set_item("statistics", s)
}

fn suite<'py>(py: Python<'py>, f: &SweepFile) -> PyResult<Option<Bound<'py, PyDict>>> {
    let Some(s) = &f.suite else { return Ok(None) };
    let d = PyDict::new(py);
    d.set_item("target", &s.target)?;
    d.set_item("target_config", &s.target_config)?;
    d.set_item("rule", &s.rule)?;
    d.set_item("ec8_satisfied", s.ec8_satisfied)?;
    d.set_item("factor", PyArray1::from_slice(py, &s.factors))?;
    d.set_item("range", PyArray1::from_slice(py, &s.range))?;
    d.set_item("target_sa", PyArray1::from_slice(py, &s.target_sa))?;
    d.set_item("rule_factor", s.rule_factor)?;
    d.set_item("min_ratio", s.min_ratio[0])?;
    d.set_item("min_ratio_period", s.min_ratio[1])?;
    d.set_item("pga_ratio", s.pga_ratio)?;
    d.set_item("fit_period", PyArray1::from_slice(py, &s.fit_periods))?;
    d.set_item("fit_target", PyArray1::from_slice(py, &s.fit_target))?;
    d.set_item("fit_mean", PyArray1::from_slice(py, &s.fit_mean))?;
    Ok(Some(d))
}

fn fragility<'py>(py: Python<'py>, f: &StoredFragility, r: &Results) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let s = &f.stripes;
    d.set_item("measure", s.measure.key())?;
    d.set_item("measure_label", s.measure.label())?;
    let (period, damping) = match s.measure {
        quakejoint_sweep::plan::Measure::Sa { period, damping } => (Some(period), Some(damping)),
        quakejoint_sweep::plan::Measure::Pga => (None, None),
    };
    d.set_item("measure_period", period)?;
    d.set_item("measure_damping", damping)?;
    d.set_item("levels", PyArray1::from_slice(py, &s.levels))?;
    d.set_item("ground_records", s.ground.iter().map(|g| g.0.clone()).collect::<Vec<_>>())?;
    d.set_item("ground_intensity", PyArray1::from_vec(py, s.ground.iter().map(|g| g.1).collect()))?;
    d.set_item("record_ground", PyArray1::from_vec(py, s.runs.iter().map(|x| x.ground as u32).collect()))?;
    d.set_item("record_stripe", PyArray1::from_vec(py, s.runs.iter().map(|x| x.stripe as u32).collect()))?;
    d.set_item("record_factor", PyArray1::from_vec(py, s.runs.iter().map(|x| x.factor).collect()))?;
    d.set_item("failed", f.spec.failed.key())?;
    let hazard = f.spec.hazard.as_ref().map(|h| {
        let (i, q): (Vec<f64>, Vec<f64>) = h.curve.points().iter().copied().unzip();
        (PyArray1::from_vec(py, i), PyArray1::from_vec(py, q))
    });
    d.set_item("hazard", hazard)?;
    let [nc, _, nz, nt] = r.dims;
    let curve = [nc, nz, nt];
    let stripe = [nc, nz, nt, s.levels.len()];
    let states = PyList::empty(py);
    for (ls, res) in f.spec.limit_states.iter().zip(f.evaluate(r)) {
        let arrays = PyDict::new(py);
        arrays.set_item("outcome", array(py, &res.outcome, &r.dims)?)?;
        let (counts, boot) = count_arrays(&res);
        for (name, values) in counts {
            arrays.set_item(name, array(py, &values, &stripe)?)?;
        }
        for (name, values) in boot {
            arrays.set_item(name, array(py, &values, &curve)?)?;
        }
        for (name, _, values) in curve_arrays(&res) {
            arrays.set_item(name, array(py, &values, &curve)?)?;
        }
        let notes: Vec<String> = res.curves.iter().map(|c| c.note.clone()).collect();
        arrays.set_item("note", texts(py, &notes, &curve)?)?;
        let l = PyDict::new(py);
        l.set_item("key", &ls.key)?;
        l.set_item("name", &ls.name)?;
        l.set_item("kind", &ls.kind)?;
        l.set_item("definition", &ls.definition)?;
        l.set_item("arrays", arrays)?;
        states.append(l)?;
    }
    d.set_item("limit_states", states)?;
    Ok(d)
}

/// Reads and checks the sweep or merge file `path` as the command line
/// does (`quakejoint compare`, `sweep --check`) and returns its contents as
/// a dict of arrays (what `quakejoint.read_sweep` labels).
#[pyfunction]
fn read_sweep_file<'py>(py: Python<'py>, path: std::path::PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let refuse = |message: String| InputError::new_err(message);
    if !path.exists() {
        return Err(refuse(format!("{}: no such file", path.display())));
    }
    let (file, attrs) = py
        .detach(|| {
            let f = quakejoint_sweep::sweep_h5::read_sweep(&path)?;
            // the root's attributes (read and checked by read_sweep)
            let attrs = quakejoint_io::read::open(&path)
                .and_then(|h| quakejoint_io::read::attributes(&h))
                .map_err(|e| quakejoint_io::OutputError::hdf5(&path, e))?;
            Ok::<_, quakejoint_io::OutputError>((f, attrs))
        })
        .map_err(|e| refuse(quakejoint_sweep::sweep_read::refusal(&e)))?;
    let d = PyDict::new(py);
    d.set_item("cases", &file.cases)?;
    d.set_item("records", file.records.iter().map(|r| r.name.clone()).collect::<Vec<_>>())?;
    d.set_item("damping", PyArray1::from_slice(py, &file.damping))?;
    d.set_item("periods", PyArray1::from_slice(py, &file.periods))?;
    d.set_item("period_scales", file.modal.as_ref().map(|m| PyArray1::from_slice(py, &m.period_scales)))?;
    results(py, &file.results, &d)?;
    let flags: Vec<(u32, &str)> = quakejoint_model::validity::Flags::ALL.iter().map(|(f, n)| (f.0, *n)).collect();
    d.set_item("flag_names", flags)?;
    let a = PyDict::new(py);
    for (name, value) in &attrs {
        a.set_item(name, attr_value(py, value)?)?;
    }
    d.set_item("attrs", a)?;
    d.set_item("suite", suite(py, &file)?)?;
    d.set_item("fragility", file.fragility.as_ref().map(|f| fragility(py, f, &file.results)).transpose()?)?;
    d.set_item("design", design(py, &file)?)?;
    Ok(d)
}

/// The choice among the sweep's cases against its targets (empty without
/// targets): one dict per damping ratio and period.
fn design<'py>(py: Python<'py>, file: &quakejoint_sweep::sweep_h5::SweepFile) -> PyResult<Vec<Bound<'py, PyDict>>> {
    use quakejoint_sweep::fragility::design::{candidates_of, designs};
    let Some(f) = &file.fragility else { return Ok(Vec::new()) };
    let rows = quakejoint_sweep::fragility::rows(f, &file.results, &|_, _, _| String::new());
    let out = designs(f, &rows, &candidates_of(&file.cases, &file.case_configs));
    out.iter()
        .map(|dz| {
            let d = PyDict::new(py);
            d.set_item("damping", dz.at[0])?;
            d.set_item("period", dz.at[1])?;
            d.set_item("targets", dz.targets.iter().map(|t| (t.0.clone(), t.1.clone(), t.2)).collect::<Vec<_>>())?;
            d.set_item("candidates", dz.candidates.iter().map(|c| c.name.clone()).collect::<Vec<_>>())?;
            d.set_item("cells", dz.candidates.iter().map(|c| c.cells).collect::<Vec<_>>())?;
            d.set_item("fuse", dz.candidates.iter().map(|c| c.fuse.clone()).collect::<Vec<_>>())?;
            let grid = |f: fn(&quakejoint_sweep::fragility::design::Check) -> f64| -> Vec<Vec<f64>> {
                dz.checks.iter().map(|row| row.iter().map(f).collect()).collect()
            };
            d.set_item("annual_frequency", grid(|k| k.frequency))?;
            d.set_item("checked", grid(|k| k.upper))?;
            d.set_item(
                "passed",
                dz.checks.iter().map(|r| r.iter().map(|k| k.pass).collect()).collect::<Vec<Vec<bool>>>(),
            )?;
            d.set_item(
                "notes",
                dz.checks.iter().map(|r| r.iter().map(|k| k.note.clone()).collect()).collect::<Vec<Vec<String>>>(),
            )?;
            d.set_item("recommended", dz.recommended.map(|c| dz.candidates[c].name.clone()))?;
            d.set_item("margin", dz.recommended.map(|_| dz.margin.0))?;
            d.set_item("margin_on", dz.recommended.map(|_| dz.margin.1.clone()))?;
            Ok(d)
        })
        .collect()
}

/// Adds the sweep reader to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(read_sweep_file, m)?)?;
    Ok(())
}
