//! `Record`, `Spectrum` and `spectrum()`: records from files or arrays and
//! their exact linear response spectra (the code of `quakejoint record` and
//! `quakejoint spectrum`).

use std::path::{Path, PathBuf};

use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{PyArray1, PyArrayDyn};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use quakejoint_motion::{
    load_record, load_record_from_samples, spectrum_samples, LoadedRecord, RecordStats, SpectrumOptions, SpectrumRow,
    MAX_SUBDIVISIONS,
};

use crate::convert::{real, real_opt, record_spec, whole, Numbers, SpecFields};
use crate::input_error;

/// A ground-motion record: acceleration in m/s^2 at a uniform time step,
/// with how it was read (format, units, scale) and its provenance.
#[pyclass(name = "Record", module = "quakejoint", frozen)]
pub struct PyRecord {
    pub(crate) loaded: LoadedRecord,
}

#[pymethods]
impl PyRecord {
    /// Reads a record file (PEER AT2, ESM, K-NET/KiK-net, COSMOS, CSMIP/DMG
    /// Volume 1/2 from CESMD, CSV or text; docs/ground-motions.md) as
    /// `quakejoint record` does. Units are never guessed: a file whose
    /// header does not state them needs `units` ("g", "m/s2", "cm/s2" or
    /// "gal"). `dt` [s] is for one-column and sequence files only, `column`
    /// (1-based) for text files; `channel` (its number) or `azimuth`
    /// [degrees from north] choose a channel of a COSMOS or CSMIP file that
    /// holds several, and `allow_vertical=True` reads a vertical one;
    /// `scale` [-] or `target_pga_g` [g] scale the record.
    #[staticmethod]
    #[pyo3(signature = (path, *, format=None, units=None, dt=None, column=None, scale=None, target_pga_g=None, name=None, channel=None, azimuth=None, allow_vertical=false))]
    #[allow(clippy::too_many_arguments)]
    fn read(
        py: Python<'_>,
        path: PathBuf,
        format: Option<String>,
        units: Option<String>,
        dt: Option<&Bound<'_, PyAny>>,
        column: Option<&Bound<'_, PyAny>>,
        scale: Option<&Bound<'_, PyAny>>,
        target_pga_g: Option<&Bound<'_, PyAny>>,
        name: Option<String>,
        channel: Option<&Bound<'_, PyAny>>,
        azimuth: Option<&Bound<'_, PyAny>>,
        allow_vertical: bool,
    ) -> PyResult<Self> {
        const F: &str = "Record.read";
        let column = column.map(|c| whole(c, F, "column", 1, u32::MAX as i64).map(|c| c as usize)).transpose()?;
        let channel = channel.map(|c| whole(c, F, "channel", 1, u32::MAX as i64).map(|c| c as u32)).transpose()?;
        let fields = SpecFields {
            format,
            units,
            dt: real_opt(dt, F, "dt")?,
            column,
            scale: real_opt(scale, F, "scale")?,
            target_pga_g: real_opt(target_pga_g, F, "target_pga_g")?,
            name,
            channel,
            azimuth: real_opt(azimuth, F, "azimuth")?,
            allow_vertical,
        };
        let spec = record_spec(&path, fields)?;
        let loaded = py.detach(|| load_record(&spec, Path::new(""))).map_err(input_error)?;
        Ok(PyRecord { loaded })
    }

    /// A record from an array of ground accelerations at time step `dt`
    /// [s], in `units` (required: an array cannot say its units; "g",
    /// "m/s2", "cm/s2" or "gal"), checked as a file's numbers are (real and
    /// finite, at most 5 g, dt from 1e-5 to 1 s).
    #[staticmethod]
    #[pyo3(signature = (acceleration, dt, *, units=None, scale=None, target_pga_g=None, name=None))]
    fn from_array(
        acceleration: &Bound<'_, PyAny>,
        dt: &Bound<'_, PyAny>,
        units: Option<String>,
        scale: Option<&Bound<'_, PyAny>>,
        target_pga_g: Option<&Bound<'_, PyAny>>,
        name: Option<String>,
    ) -> PyResult<Self> {
        const F: &str = "Record.from_array";
        let values = samples_of(acceleration, F, "acceleration")?;
        let dt = real(dt, F, "dt")?;
        let name = name.unwrap_or_else(|| "array".to_string());
        let fields = SpecFields {
            format: None,
            units,
            dt: None,
            column: None,
            scale: real_opt(scale, F, "scale")?,
            target_pga_g: real_opt(target_pga_g, F, "target_pga_g")?,
            name: Some(name),
            ..SpecFields::default()
        };
        let label = fields.name.clone().unwrap_or_default();
        let spec = record_spec(Path::new(&label), fields)?;
        let loaded = load_record_from_samples(&spec, dt, values).map_err(input_error)?;
        Ok(PyRecord { loaded })
    }

    /// Ground acceleration [m/s^2] at t = i dt (a copy).
    #[getter]
    fn acceleration<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.loaded.record.acceleration)
    }

    /// Sample times [s], from 0.
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let r = &self.loaded.record;
        PyArray1::from_vec(py, (0..r.acceleration.len()).map(|i| r.time(i)).collect())
    }

    /// Time step [s].
    #[getter]
    fn dt(&self) -> f64 {
        self.loaded.record.dt
    }

    /// Label (the `name` given, else the file stem).
    #[getter]
    fn name(&self) -> &str {
        &self.loaded.record.name
    }

    /// The file as given ("array" names for arrays).
    #[getter]
    fn source(&self) -> &str {
        &self.loaded.record.source
    }

    /// Units of the numbers in the file ("g", "m/s2" or "cm/s2").
    #[getter]
    fn units(&self) -> &'static str {
        self.loaded.record.units.name()
    }

    /// The format the file was read as ("at2", "esm", "knet", ...).
    #[getter]
    fn format(&self) -> &'static str {
        self.loaded.format.name()
    }

    /// The user's scale factor [-] (`scale`, or the factor that gives
    /// `target_pga_g`).
    #[getter]
    #[allow(clippy::misnamed_getters)] // `scale` is the user's factor, as in the config
    fn scale(&self) -> f64 {
        self.loaded.record.user_scale
    }

    /// Factor from the file's numbers to `acceleration` [m/s^2 per file
    /// unit]: unit conversion times `scale`.
    #[getter]
    fn total_scale(&self) -> f64 {
        self.loaded.record.scale
    }

    /// SHA-256 of the file's bytes (of the samples' little-endian bytes
    /// for an array).
    #[getter]
    fn sha256(&self) -> &str {
        &self.loaded.sha256
    }

    /// What reading the record raised (a record that does not start near
    /// zero, say), each naming the file.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.loaded.warnings.clone()
    }

    /// The file's header lines (AT2, ESM, K-NET, COSMOS).
    #[getter]
    fn header(&self) -> Vec<String> {
        self.loaded.record.header.clone()
    }

    /// The channel read, where the format says which: a dict with
    /// `number` (as the file gives it), `of` (channels in the file) and
    /// `orientation` ({"kind": "azimuth", "degrees": 90.0}, {"kind":
    /// "vertical", "label": "Up"}, {"kind": "axis", "label": "Long"} or
    /// {"kind": "unknown"}); None for text, which cannot say.
    #[getter]
    fn channel<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let Some(c) = &self.loaded.channel else { return Ok(None) };
        let d = pyo3::types::PyDict::new(py);
        d.set_item("number", c.number)?;
        d.set_item("of", c.of)?;
        let o = pyo3::types::PyDict::new(py);
        match &c.orientation {
            quakejoint_motion::Orientation::Azimuth { degrees } => {
                o.set_item("kind", "azimuth")?;
                o.set_item("degrees", degrees)?;
            }
            quakejoint_motion::Orientation::Vertical { label } => {
                o.set_item("kind", "vertical")?;
                o.set_item("label", label)?;
            }
            quakejoint_motion::Orientation::Axis { label } => {
                o.set_item("kind", "axis")?;
                o.set_item("label", label)?;
            }
            quakejoint_motion::Orientation::Unknown => o.set_item("kind", "unknown")?,
        }
        d.set_item("orientation", o)?;
        d.set_item("description", c.describe())?;
        Ok(Some(d.into_any()))
    }

    /// Duration (n - 1) dt [s], from the first sample to the last (a
    /// header's record length is n dt).
    #[getter]
    fn duration(&self) -> f64 {
        self.loaded.record.duration()
    }

    /// Peak ground acceleration [m/s^2].
    #[getter]
    fn pga(&self) -> f64 {
        self.loaded.record.pga()
    }

    /// Statistics in SI units, as `quakejoint record` prints them: dt [s],
    /// samples, duration [s], pga [m/s^2], pgv [m/s], pgd [m] with their
    /// times t_pga, t_pgv, t_pgd [s], arias [m/s], d5_95, t5, t95 [s].
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = RecordStats::of(&self.loaded.record);
        let d = PyDict::new(py);
        d.set_item("dt", s.dt)?;
        d.set_item("samples", s.samples)?;
        for (k, v) in [
            ("duration", s.duration),
            ("pga", s.pga),
            ("t_pga", s.t_pga),
            ("pgv", s.pgv),
            ("t_pgv", s.t_pgv),
            ("pgd", s.pgd),
            ("t_pgd", s.t_pgd),
            ("arias", s.arias),
            ("d5_95", s.d5_95),
            ("t5", s.t5),
            ("t95", s.t95),
        ] {
            d.set_item(k, v)?;
        }
        Ok(d)
    }

    /// The exact linear response spectrum of this record (see
    /// `quakejoint.spectrum`; the same shapes).
    #[pyo3(signature = (periods, damping=None, *, subdivisions=None))]
    fn spectrum(
        &self,
        py: Python<'_>,
        periods: &Bound<'_, PyAny>,
        damping: Option<&Bound<'_, PyAny>>,
        subdivisions: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PySpectrum> {
        let r = &self.loaded.record;
        compute(py, "Record.spectrum", &r.acceleration, r.dt, periods, damping, subdivisions)
    }

    fn __len__(&self) -> usize {
        self.loaded.record.acceleration.len()
    }

    fn __repr__(&self) -> String {
        let r = &self.loaded.record;
        format!(
            "Record(name={:?}, dt={} s, samples={}, duration={:.3} s, pga={:.4} g, units read={:?}, scale={})",
            r.name,
            r.dt,
            r.acceleration.len(),
            r.duration(),
            r.pga() / quakejoint_motion::G,
            r.units.name(),
            r.user_scale
        )
    }
}

/// An exact linear response spectrum, SI units. Each array has the shape
/// `np.shape(damping) + np.shape(periods)` of the arguments: a number has
/// no axis, a sequence (of one, or of none) has one. So a number of damping
/// gives arrays of shape (len(periods),), a list of dampings
/// (len(damping), len(periods)).
#[pyclass(name = "Spectrum", module = "quakejoint", frozen)]
pub struct PySpectrum {
    periods: Vec<f64>,
    dampings: Vec<f64>,
    rows: Vec<SpectrumRow>,
    /// The arrays' shape.
    shape: Vec<usize>,
}

impl PySpectrum {
    fn field<'py>(&self, py: Python<'py>, f: impl Fn(&SpectrumRow) -> f64) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        // rows are damping-major: the values in C order of (damping, period)
        let values: Vec<f64> = self.rows.iter().map(f).collect();
        let array = ArrayD::from_shape_vec(IxDyn(&self.shape), values)
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
        Ok(PyArrayDyn::from_owned_array(py, array))
    }
}

#[pymethods]
impl PySpectrum {
    /// Periods T [s].
    #[getter]
    fn periods<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.periods)
    }

    /// Damping ratios [-].
    #[getter]
    fn damping<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.dampings)
    }

    /// Spectral acceleration: peak absolute acceleration [m/s^2].
    #[getter]
    fn sa<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        self.field(py, |r| r.peaks.sa)
    }

    /// Pseudo-spectral acceleration w^2 Sd [m/s^2].
    #[getter]
    fn psa<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        self.field(py, |r| r.peaks.psa)
    }

    /// Spectral displacement: peak relative displacement [m].
    #[getter]
    fn sd<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        self.field(py, |r| r.peaks.sd)
    }

    /// Spectral velocity: peak relative velocity [m/s].
    #[getter]
    fn sv<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        self.field(py, |r| r.peaks.sv)
    }

    /// Pseudo-spectral velocity w Sd [m/s].
    #[getter]
    fn psv<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        self.field(py, |r| r.peaks.psv)
    }

    /// Time of Sa [s].
    #[getter]
    fn t_sa<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        self.field(py, |r| r.peaks.t_sa)
    }

    /// Time of Sd [s].
    #[getter]
    fn t_sd<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        self.field(py, |r| r.peaks.t_sd)
    }

    /// Time of Sv [s].
    #[getter]
    fn t_sv<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        self.field(py, |r| r.peaks.t_sv)
    }

    fn __repr__(&self) -> String {
        format!(
            "Spectrum({} periods x {} damping ratios, arrays of shape {:?})",
            self.periods.len(),
            self.dampings.len(),
            self.shape
        )
    }
}

/// The exact linear response spectrum of a record, or of an array of
/// ground accelerations at time step `dt` [s] in `units` (required for an
/// array), for `periods` [s] and `damping` ratios [-] (each a number or a
/// sequence; damping default 0.05). The arrays have the shape
/// `np.shape(damping) + np.shape(periods)`: a number has no axis, a
/// sequence (of one, or of none) has one. The oscillator step is exact for
/// ground acceleration linear between samples (Nigam and Jennings 1969),
/// the code of `quakejoint spectrum`; peaks at the sample times, or at
/// `subdivisions` points per interval.
#[pyfunction]
#[pyo3(signature = (record, periods, damping=None, *, dt=None, units=None, subdivisions=None))]
fn spectrum(
    py: Python<'_>,
    record: &Bound<'_, PyAny>,
    periods: &Bound<'_, PyAny>,
    damping: Option<&Bound<'_, PyAny>>,
    dt: Option<&Bound<'_, PyAny>>,
    units: Option<String>,
    subdivisions: Option<&Bound<'_, PyAny>>,
) -> PyResult<PySpectrum> {
    const F: &str = "spectrum";
    if let Ok(r) = record.cast::<PyRecord>() {
        if dt.is_some() || units.is_some() {
            return Err(crate::InputError::new_err(
                "spectrum: `dt` and `units` are for an array; a Record carries its own",
            ));
        }
        let r = &r.get().loaded.record;
        return compute(py, F, &r.acceleration, r.dt, periods, damping, subdivisions);
    }
    let samples = samples_of(record, F, "record")?;
    let Some(dt) = real_opt(dt, F, "dt")? else {
        return Err(crate::InputError::new_err("spectrum: an array needs its time step `dt` [s]"));
    };
    let fields = SpecFields { units, ..SpecFields::default() };
    let spec = record_spec(Path::new("array"), fields)?;
    let loaded = load_record_from_samples(&spec, dt, samples).map_err(input_error)?;
    let r = &loaded.record;
    compute(py, F, &r.acceleration, r.dt, periods, damping, subdivisions)
}

/// Ground-acceleration samples, the argument `what` of `func`: a 1-D array
/// or sequence of real numbers.
fn samples_of(obj: &Bound<'_, PyAny>, func: &str, what: &str) -> PyResult<Vec<f64>> {
    let expected = if what == "record" { "a Record or a 1-D array of samples" } else { "a 1-D array of samples" };
    let refuse =
        |found: String| crate::InputError::new_err(format!("{func}: `{what}` must be {expected}, not {found}"));
    if obj.is_instance_of::<PyString>() {
        return Err(refuse("a string".into()));
    }
    let n = Numbers::of(obj, func, what)?;
    match n.shape.len() {
        1 => Ok(n.values),
        0 => Err(refuse("a single number".into())),
        _ => Err(refuse(format!("an array of shape {:?}", n.shape))),
    }
}

/// The spectrum of samples [m/s^2], GIL released.
fn compute(
    py: Python<'_>,
    func: &str,
    accel: &[f64],
    dt: f64,
    periods: &Bound<'_, PyAny>,
    damping: Option<&Bound<'_, PyAny>>,
    subdivisions: Option<&Bound<'_, PyAny>>,
) -> PyResult<PySpectrum> {
    let periods = Numbers::at_most_1d(periods, func, "periods")?;
    let dampings = match damping {
        Some(d) => Numbers::at_most_1d(d, func, "damping")?,
        None => Numbers { values: vec![0.05], shape: vec![] },
    };
    let subdivisions = match subdivisions {
        Some(s) => whole(s, func, "subdivisions", 0, MAX_SUBDIVISIONS as i64)? as u32,
        None => 0,
    };
    let shape = [dampings.shape.as_slice(), periods.shape.as_slice()].concat();
    let (periods, dampings) = (periods.values, dampings.values);
    let options = SpectrumOptions { subdivisions };
    let rows = py.detach(|| spectrum_samples(accel, dt, &periods, &dampings, options)).map_err(input_error)?;
    Ok(PySpectrum { periods, dampings, rows, shape })
}

/// Adds the record classes and functions to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyRecord>()?;
    m.add_class::<PySpectrum>()?;
    m.add_function(wrap_pyfunction!(spectrum, m)?)?;
    Ok(())
}
