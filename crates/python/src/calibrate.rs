//! `calibrate`: the joint's link element from the detailed joint, with its
//! exports (docs/link.md), as `quakejoint calibrate` gives them.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use quakejoint_model::calibrate::{calibrate as run_calibration, export, CalibrationOptions};
use quakejoint_model::run::run_window;
use quakejoint_model::runspec::{Overrides, RecordOverride};

use crate::config::PyConfig;
use crate::convert::{real_opt, Numbers};
use crate::record::PyRecord;
use crate::run::Spec;
use crate::{config_error, model_error};

/// Calibrates the link element of the config's (detailed) joint: service
/// loops at `amplitudes` [m] (default 0.002 to 0.1 m) at `speed` [m/s]
/// (default 0.02) for the spring and the slider, and, with `earthquake`
/// (default True), runs of the config's bridge under `record` (a
/// `quakejoint.Record` or a list of them, the calibration suite; default
/// the config's record) for the mass (the damper is the bushings').
/// Returns a dict: stiffness [N/m], friction [N], hand_friction [N], mass
/// and kinetic_mass [kg], damping [N s/m], gap [m], gap_stiffness [N/m],
/// gap_hertz [N/m^1.5] (None for a joint with the linear contact law),
/// capacity [m], cells, fit_rms [N], speed [m/s] and contact_force [N] (the
/// force of the exports' closing secant), racking_closing and
/// racking_opening [m] (the link's: docs/link.md, "Racking"), loops (one
/// dict per amplitude: amplitude, energy, link_energy [J], peak_force [N],
/// damping_joint, damping_bridge, racking_closing, racking_opening [m],
/// and the arrays t, u, force), suite (per record of the
/// calibration suite: record, rms, peak_link, peak_detailed [N],
/// friction_link, friction_detailed [J], own_mass [kg] (the mass that
/// record alone calls for), closed_detailed [N] (the detailed joint's
/// closed-joint force on the deck), racking_closing (NaN where a cell
/// closed) and racking_opening [m]; empty without earthquake) and exports (the texts of link.toml, link.tcl,
/// link_opensees.py and link_sap2000.txt by those names), warnings (what
/// the calibration cannot stand behind: loops left out, a poor fit, a
/// flagged calibration record, a mass at the edge of the search, a record
/// under which the link's peak force stays more than 5 % below the
/// detailed joint's). GIL released.
#[pyfunction]
#[pyo3(signature = (config=None, *, amplitudes=None, speed=None, contact_force=None, record=None, earthquake=true))]
fn calibrate<'py>(
    py: Python<'py>,
    config: Option<&PyConfig>,
    amplitudes: Option<&Bound<'py, PyAny>>,
    speed: Option<&Bound<'py, PyAny>>,
    contact_force: Option<&Bound<'py, PyAny>>,
    record: Option<&Bound<'py, PyAny>>,
    earthquake: bool,
) -> PyResult<Bound<'py, PyDict>> {
    // one Record or a list of them; none: the config's
    let records: Vec<Option<RecordOverride>> = match record {
        None => vec![None],
        Some(r) => match r.extract::<PyRef<PyRecord>>() {
            Ok(one) => vec![Some(RecordOverride::Loaded(Box::new(one.loaded.clone())))],
            Err(_) => {
                let list: Vec<PyRef<PyRecord>> = r.extract().map_err(|_| {
                    pyo3::exceptions::PyTypeError::new_err(
                        "calibrate: record must be a quakejoint.Record or a list of them",
                    )
                })?;
                if list.is_empty() {
                    return Err(pyo3::exceptions::PyValueError::new_err(
                        "calibrate: record = []: give at least one record, or earthquake=False",
                    ));
                }
                list.iter().map(|one| Some(RecordOverride::Loaded(Box::new(one.loaded.clone())))).collect()
            }
        },
    };
    let mut specs = Vec::with_capacity(records.len());
    for record in records {
        specs.push(Spec::new(config, &Overrides { record, ..Overrides::default() })?);
    }
    let Spec { spec, source, .. } = &specs[0];
    let mut options = CalibrationOptions::default();
    if let Some(a) = amplitudes {
        options.amplitudes = Numbers::at_most_1d(a, "calibrate", "amplitudes")?.values;
    }
    if let Some(s) = real_opt(speed, "calibrate", "speed")? {
        options.speed = s;
    }
    if let Some(f) = real_opt(contact_force, "calibrate", "contact_force")? {
        options.contact_force = Some(f);
    }
    options.check(|k| k.to_string()).map_err(model_error)?;
    if earthquake {
        for s in &specs {
            let (loaded, _) = s.spec.records(&s.base).map_err(|e| config_error(e, &s.source))?;
            options.records.push(run_window(spec.config(), &loaded.record));
        }
    }
    let c = py.detach(|| run_calibration(&spec.scenario, &options)).map_err(model_error)?;
    let d = PyDict::new(py);
    // (the numbers from the one list of them, Calibration::scalars, as the
    // command line's JSON)
    for (k, v, _) in c.scalars() {
        d.set_item(k, v)?;
    }
    d.set_item("cells", c.cells)?;
    d.set_item("gap_hertz", c.link.gap_hertz)?;
    d.set_item("warnings", c.warnings.clone())?;
    let loops = PyList::empty(py);
    for p in &c.loops {
        let e = PyDict::new(py);
        for (k, v, _) in p.scalars() {
            e.set_item(k, v)?;
        }
        e.set_item("t", PyArray1::from_slice(py, &p.t))?;
        e.set_item("u", PyArray1::from_slice(py, &p.u))?;
        e.set_item("force", PyArray1::from_slice(py, &p.force))?;
        loops.append(e)?;
    }
    d.set_item("loops", loops)?;
    let suite = PyList::empty(py);
    for f in &c.dynamic {
        let e = PyDict::new(py);
        e.set_item("record", f.record.clone())?;
        for (k, v, _) in f.scalars() {
            e.set_item(k, v)?;
        }
        suite.append(e)?;
    }
    d.set_item("suite", suite)?;
    let exports = PyDict::new(py);
    exports.set_item("link.toml", export::toml(&c, source))?;
    exports.set_item("link.tcl", export::opensees_tcl(&c, source))?;
    exports.set_item("link_opensees.py", export::opensees_py(&c, source))?;
    exports.set_item("link_sap2000.txt", export::sap2000(&c, source))?;
    d.set_item("exports", exports)?;
    Ok(d)
}

/// Adds `calibrate` to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(calibrate, m)?)
}
