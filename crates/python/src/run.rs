//! `simulate()` and `service()`: one coupled earthquake run, or the joint
//! opened and closed kinematically, on a worker thread with the GIL
//! released; Ctrl-C (any Python signal handler that raises) stops the run
//! at its next step.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use crossbeam_channel::RecvTimeoutError;
use std::time::Duration;

use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use quakejoint_model::run::{Histories, RunOptions, RunResult};
use quakejoint_model::runspec::{Named, Overrides, RecordOverride, RunSpec};
use quakejoint_model::service::{service as run_service, ServiceResult};
use quakejoint_model::{Config, ModelError};
use quakejoint_motion::{LoadedRecord, G};

use crate::config::PyConfig;
use crate::convert::{real_opt, whole};
use crate::record::PyRecord;
use crate::{config_error, model_error};

/// How often the waiting thread looks for a pending Python signal.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Runs `work` on a worker thread with the GIL released, checking Python's
/// signal handlers meanwhile: when one raises (KeyboardInterrupt on
/// Ctrl-C), `cancel` is set, the worker is joined and the exception
/// returned.
fn run_detached<T: Send>(
    py: Python<'_>,
    cancel: &Arc<AtomicBool>,
    work: impl FnOnce() -> Result<T, ModelError> + Send,
) -> PyResult<T> {
    std::thread::scope(|s| {
        let (tx, rx) = crossbeam_channel::bounded(1);
        s.spawn(move || {
            // the receiver outlives the scope's threads
            let _ = tx.send(work());
        });
        loop {
            match py.detach(|| rx.recv_timeout(SIGNAL_POLL)) {
                Ok(result) => return result.map_err(model_error),
                Err(RecvTimeoutError::Timeout) => {
                    if let Err(e) = py.check_signals() {
                        cancel.store(true, Ordering::Relaxed);
                        // the run stops at its next step; wait for it
                        let _ = py.detach(|| rx.recv());
                        return Err(e);
                    }
                }
                Err(RecvTimeoutError::Disconnected) => {
                    return Err(crate::SimulationError::new_err("the run's thread ended without a result"))
                }
            }
        }
    })
}

/// The result of one earthquake run: scalars as attributes (SI units),
/// `history` (a dict of arrays, or None), `impacts_log`, validity.
#[pyclass(name = "RunResult", module = "quakejoint", frozen)]
pub struct PyRunResult {
    scalars: Py<PyDict>,
    /// Time histories at the output times (the record's sample times): a
    /// dict of numpy arrays, or None when not asked for.
    #[pyo3(get)]
    history: Option<Py<PyDict>>,
    /// Every contact onset: a list of dicts with time [s], gap, end and
    /// speed [m/s].
    #[pyo3(get)]
    impacts_log: Py<PyList>,
    /// Names of the validity flags set (empty: valid; ["not_checked"]
    /// without the joint).
    #[pyo3(get)]
    flags: Vec<&'static str>,
    /// What the flags found, when and where, one sentence each.
    #[pyo3(get)]
    findings: Vec<String>,
    /// Whether the run crossed a limit of the model (a flag other than
    /// not_checked is set): its numbers are outside what the model can
    /// stand behind.
    #[pyo3(get)]
    flagged: bool,
    /// A modal bridge's points (`[bridge.modal]`): a list of dicts with
    /// name, sd [m], sa [m/s^2], their times [s] and the bridge alone's
    /// sd_without_joint, sa_without_joint; empty on a single-DOF deck.
    #[pyo3(get)]
    points: Py<PyList>,
    /// Every joint of the run, in the order of `[[joints]]` (the one of
    /// `[joint]` alone; none for the bridge alone): a list of dicts with
    /// name, the deck point's sa, sd, sv, the joint's own demands
    /// (peak_joint_force, peak_abutment_force, peak_bushing_force,
    /// peak_friction_force, friction_energy, min/max_subgap, impacts, ...),
    /// validity and history (a dict of arrays; None for the first joint,
    /// whose series are the run's `history`).
    #[pyo3(get)]
    joints: Py<PyList>,
}

#[pymethods]
impl PyRunResult {
    fn __getattr__(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyAny>> {
        match self.scalars.bind(py).get_item(name)? {
            Some(v) => Ok(v.unbind()),
            None => Err(pyo3::exceptions::PyAttributeError::new_err(format!("RunResult has no attribute `{name}`"))),
        }
    }

    fn __dir__(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        let mut names: Vec<String> = self.scalars.bind(py).keys().extract()?;
        names.extend(
            ["history", "impacts_log", "flags", "findings", "flagged", "points", "joints", "as_dict"].map(String::from),
        );
        Ok(names)
    }

    /// The scalar results as a dict (one row of a table of runs).
    fn as_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.scalars.bind(py).copy()
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let d = self.scalars.bind(py);
        let get =
            |k: &str| -> PyResult<f64> { Ok(d.get_item(k)?.map(|v| v.extract()).transpose()?.unwrap_or(f64::NAN)) };
        Ok(format!(
            "RunResult(period={:.4} s, sa={:.5} m/s^2, joint={}, validity={})",
            get("period")?,
            get("sa")?,
            d.get_item("joint")?.map(|v| v.to_string()).unwrap_or_default(),
            if self.flags.is_empty() { "ok".into() } else { self.flags.join("+") }
        ))
    }
}

/// The scalar results of a run, named as in `quakejoint simulate --json`
/// and a run file's `/result` ([`RunResult::scalars`]).
fn scalars<'py>(py: Python<'py>, r: &RunResult, record: &LoadedRecord) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let rec = &record.record;
    d.set_item("record", &rec.name)?;
    d.set_item("record_file", &rec.source)?;
    d.set_item("record_scale", rec.user_scale)?;
    d.set_item("record_pga_g", rec.pga() / G)?;
    d.set_item("joint", !r.exact_linear)?;
    d.set_item("method", if r.exact_linear { "exact linear" } else { "multibody" })?;
    d.set_item("validity", r.validity.flags.0)?;
    d.set_item("validity_label", r.validity.flags.label())?;
    // the values of a run file's /result, with its names
    for (k, v, _units) in r.scalars() {
        d.set_item(k, v)?;
    }
    if let (Some(v), Some(w)) = (r.base_shear, r.base_shear_without) {
        d.set_item("base_shear", v)?;
        d.set_item("base_shear_without_joint", w)?;
    }
    if let Some((check, _)) = &r.mode_check {
        d.set_item("mass_ratio", check.mass_ratio.unwrap_or(f64::NAN))?;
    }
    Ok(d)
}

/// The histories as a dict of arrays.
fn history_dict<'py>(py: Python<'py>, h: &Histories, joint: bool) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    // (the series from the one list of them, history::SERIES: those the run
    // has, the joint's only with the joint)
    for series in quakejoint_model::history::SERIES {
        let x = (series.of)(h);
        let of_joint = matches!(series.name, "joint_force" | "friction_power");
        if x.is_empty() || (of_joint && !joint) {
            continue;
        }
        d.set_item(series.name, PyArray1::from_slice(py, x))?;
        if series.name == "friction_power" {
            d.set_item("friction_energy", PyArray1::from_vec(py, cumulative(&h.t, x)))?;
        }
    }
    let matrix = |m: &[Vec<f64>]| -> PyResult<Bound<'py, PyArray2<f64>>> {
        PyArray2::from_vec2(py, m).map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))
    };
    // (the tables, each (row, time), those the run has)
    for table in quakejoint_model::history::TABLES {
        let rows = (table.of)(h);
        if !rows.is_empty() {
            d.set_item(table.name, matrix(rows)?)?;
        }
    }
    Ok(d)
}

/// Running trapezoid integral of `y` over `t`.
fn cumulative(t: &[f64], y: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(y.len());
    let mut sum = 0.0;
    for i in 0..y.len() {
        if i > 0 {
            sum += 0.5 * (y[i] + y[i - 1]) * (t[i] - t[i - 1]);
        }
        out.push(sum);
    }
    out
}

/// Runs the bridge with the joint (or alone, exactly, with `joint=False`)
/// under the config's record, or under `record` (a `quakejoint.Record`)
/// in its place, at the config's bridge period or at `period` [s]. With
/// `history` (default True) the result holds the time histories: t, ag, u,
/// v, a_abs, a_abs_without_joint (the bridge alone over the same window),
/// joint_force, friction_power, friction_energy (its running trapezoid
/// integral at the output times; the run's exact total is
/// `friction_energy` of the result), center_beam_dx, subgaps (at the
/// narrower end of each cell: pounding), subgaps_wide (at the wider end:
/// the capacity) and contact_force; on a bridge given by its modes also
/// points_u, points_a_abs and their `_without_joint` (point, time): every
/// point of the modes file. The GIL is released while the run goes on; Ctrl-C stops
/// it (KeyboardInterrupt).
#[pyfunction]
#[pyo3(signature = (config=None, *, period=None, record=None, joint=true, history=true))]
fn simulate(
    py: Python<'_>,
    config: Option<&PyConfig>,
    period: Option<&Bound<'_, PyAny>>,
    record: Option<&PyRecord>,
    joint: bool,
    history: bool,
) -> PyResult<PyRunResult> {
    let overrides = Overrides {
        period: real_opt(period, "simulate", "period")?.map(|t| Named::new(t, "period")),
        alone: !joint,
        record: record.map(|r| RecordOverride::Loaded(Box::new(r.loaded.clone()))),
        ..Overrides::default()
    };
    let Spec { spec, base, source } = Spec::new(config, &overrides)?;
    let (lx, ly) = spec.records(&base).map_err(|e| config_error(e, &source))?;
    let cancel = Arc::new(AtomicBool::new(false));
    let options = RunOptions { histories: history, cancel: Some(cancel.clone()), ..Default::default() };
    let (rx, ry) = (&lx.record, ly.as_ref().map(|l| &l.record));
    let result = run_detached(py, &cancel, || spec.run(rx, ry, &options))?;
    let history = match &result.histories {
        Some(h) => Some(history_dict(py, h, joint)?.unbind()),
        _ => None,
    };
    let impacts = PyList::empty(py);
    for i in result.histories.iter().flat_map(|h| &h.impacts) {
        let d = PyDict::new(py);
        d.set_item("time", i.time)?;
        d.set_item("gap", i.place.gap)?;
        d.set_item("end", i.place.end)?;
        d.set_item("speed", i.speed)?;
        impacts.append(d)?;
    }
    let points = PyList::empty(py);
    for p in &result.points {
        let d = PyDict::new(py);
        d.set_item("name", &p.name)?;
        for (k, v, _) in p.scalars() {
            d.set_item(k, v)?;
        }
        points.append(d)?;
    }
    let joints = PyList::empty(py);
    for j in &result.joints {
        let d = PyDict::new(py);
        d.set_item("name", &j.name)?;
        // (its scalars from the one list of them, JointResult::scalars)
        for (k, v, _) in j.scalars() {
            d.set_item(k, v)?;
        }
        d.set_item("impacts", j.pounding.impacts)?;
        d.set_item("flags", j.validity.flags.names())?;
        d.set_item("findings", j.validity.findings.clone())?;
        d.set_item("history", j.histories.as_ref().map(|h| history_dict(py, h, true)).transpose()?)?;
        joints.append(d)?;
    }
    let flags = result.validity.flags;
    Ok(PyRunResult {
        points: points.unbind(),
        joints: joints.unbind(),
        scalars: scalars(py, &result, &lx)?.unbind(),
        history,
        impacts_log: impacts.unbind(),
        flags: flags.names(),
        findings: result.validity.findings.clone(),
        flagged: flags.is_flagged(),
    })
}

/// A run defined by a config (the defaults without one) and a front end's
/// overrides, with the folder its records are read against and the name
/// its errors give the config.
pub(crate) struct Spec {
    pub(crate) spec: RunSpec,
    pub(crate) base: std::path::PathBuf,
    pub(crate) source: String,
}

impl Spec {
    /// The config checked with `overrides` applied; an error about an
    /// override names the argument, not the config.
    pub(crate) fn new(config: Option<&PyConfig>, overrides: &Overrides) -> PyResult<Self> {
        let (cfg, base, source) = match config {
            Some(c) => (c.config.clone(), c.base_dir.clone(), c.source.clone()),
            None => (Config::default(), std::path::PathBuf::from("."), "config (defaults)".to_string()),
        };
        let spec = RunSpec::new(cfg, overrides).map_err(|e| match &e {
            ModelError::Override { .. } => model_error(e),
            _ => config_error(e, &source),
        })?;
        Ok(Spec { spec, base, source })
    }
}

/// The service case: the deck opens and closes the joint kinematically
/// (`[service]`: speed, amplitude, cycles). Returns a dict: the loop's
/// arrays t [s], u (deck opening) [m], joint_force [N], center_beam_dx,
/// center_beam_dy [m] and center_beam_dphi [rad] (beam, time); the work per
/// cycle [J] of friction, of the bushings' dampers, of impacts and of the
/// loop (its area), the hand calculation of the friction work and the
/// compliance deficit [J], peak_joint_force [N], min/max_subgap [m],
/// energy_error, warnings, flags and findings. GIL released; Ctrl-C
/// waits for the loop to end.
#[pyfunction]
#[pyo3(signature = (config=None, *, speed=None, amplitude=None, cycles=None))]
fn service<'py>(
    py: Python<'py>,
    config: Option<&PyConfig>,
    speed: Option<&Bound<'py, PyAny>>,
    amplitude: Option<&Bound<'py, PyAny>>,
    cycles: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    const F: &str = "service";
    let overrides = Overrides {
        service_speed: real_opt(speed, F, "speed")?.map(|s| Named::new(s, "speed")),
        service_amplitude: real_opt(amplitude, F, "amplitude")?.map(|x| Named::new(x, "amplitude")),
        service_cycles: cycles
            .map(|c| whole(c, F, "cycles", 1, i64::from(u32::MAX)).map(|c| Named::new(c as u32, "cycles")))
            .transpose()?,
        ..Overrides::default()
    };
    let Spec { spec, .. } = Spec::new(config, &overrides)?;
    let r: ServiceResult = py.detach(|| run_service(&spec.scenario)).map_err(model_error)?;
    let d = PyDict::new(py);
    d.set_item("t", PyArray1::from_slice(py, &r.t))?;
    d.set_item("u", PyArray1::from_slice(py, &r.u))?;
    d.set_item("joint_force", PyArray1::from_slice(py, &r.joint_force))?;
    let names = ["center_beam_dx", "center_beam_dy", "center_beam_dphi"];
    for (name, m) in names.iter().zip(&r.center_beams) {
        let a = PyArray2::from_vec2(py, m).map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
        d.set_item(*name, a)?;
    }
    let numbers = [
        ("period", r.period),
        ("friction_work_per_cycle", r.friction_work_per_cycle),
        ("loop_work_per_cycle", r.loop_work_per_cycle),
        ("damping_work_per_cycle", r.damping_work_per_cycle),
        ("contact_work_per_cycle", r.contact_work_per_cycle),
        ("hand_calculation", r.hand_calculation),
        ("compliance_deficit", r.compliance_deficit.unwrap_or(f64::NAN)),
        ("peak_joint_force", r.peak_joint_force),
        ("min_subgap", r.min_subgap),
        ("max_subgap", r.max_subgap),
        ("energy_error", r.energy_error),
        ("wall_time_s", r.wall_time_s),
    ];
    for (k, v) in numbers {
        d.set_item(k, v)?;
    }
    d.set_item("cycles", r.cycles)?;
    d.set_item("warnings", r.warnings.clone())?;
    d.set_item("flags", r.validity.flags.names())?;
    d.set_item("findings", r.validity.findings.clone())?;
    d.set_item("flagged", r.validity.flags.is_flagged())?;
    Ok(d)
}

/// Adds the run functions to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyRunResult>()?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(service, m)?)?;
    Ok(())
}
