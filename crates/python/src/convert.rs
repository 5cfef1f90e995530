//! Conversions between Python values and the engine's inputs: record specs
//! from keyword arguments, TOML values from dicts and back, number
//! sequences.

use std::path::Path;

use numpy::PyReadonlyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use quakejoint_motion::RecordSpec;

use crate::InputError;

/// The optional fields of a record spec, as keyword arguments give them.
#[derive(Debug, Default)]
pub(crate) struct SpecFields {
    /// `format` ("auto", "at2", "esm", ...).
    pub format: Option<String>,
    /// `units` ("g", "m/s2", "cm/s2", "gal").
    pub units: Option<String>,
    /// `dt` [s].
    pub dt: Option<f64>,
    /// `column` (1-based).
    pub column: Option<usize>,
    /// `scale` [-].
    pub scale: Option<f64>,
    /// `target_pga_g` [g].
    pub target_pga_g: Option<f64>,
    /// `name`.
    pub name: Option<String>,
}

/// The spec of `path` with `fields`, read as a config's `[record]` table is
/// (the same names, values and messages).
pub(crate) fn record_spec(path: &Path, fields: SpecFields) -> PyResult<RecordSpec> {
    let mut t = toml::Table::new();
    t.insert("file".into(), toml::Value::String(path.display().to_string()));
    let mut put = |k: &str, v: Option<toml::Value>| {
        if let Some(v) = v {
            t.insert(k.into(), v);
        }
    };
    put("format", fields.format.map(toml::Value::String));
    put("units", fields.units.map(toml::Value::String));
    put("dt", fields.dt.map(toml::Value::Float));
    put("column", fields.column.map(|c| toml::Value::Integer(c as i64)));
    put("scale", fields.scale.map(toml::Value::Float));
    put("target_pga_g", fields.target_pga_g.map(toml::Value::Float));
    put("name", fields.name.map(toml::Value::String));
    let spec: RecordSpec = toml::Value::Table(t)
        .try_into()
        .map_err(|e: toml::de::Error| InputError::new_err(format!("{}: {}", path.display(), e.message())))?;
    spec.validate().map_err(crate::input_error)?;
    Ok(spec)
}

/// A number or a 1-D sequence of numbers as a vector (`what` names it in
/// messages).
pub(crate) fn array_or_scalar(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    if let Ok(x) = obj.extract::<f64>() {
        return Ok(vec![x]);
    }
    if let Ok(a) = obj.extract::<PyReadonlyArray1<'_, f64>>() {
        return Ok(a.as_array().to_vec());
    }
    obj.extract::<Vec<f64>>()
        .map_err(|_| InputError::new_err(format!("`{what}` must be a number or a 1-D sequence of numbers")))
}

/// A Python value (dict, list, str, int, float, bool) as a TOML value;
/// `at` is the dotted key, for messages.
pub(crate) fn to_toml(obj: &Bound<'_, PyAny>, at: &str) -> PyResult<toml::Value> {
    if obj.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(obj.extract()?));
    }
    if obj.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(obj.extract()?));
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(obj.extract()?));
    }
    if obj.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(obj.extract()?));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut t = toml::Table::new();
        for (k, v) in d.iter() {
            let key: String =
                k.extract().map_err(|_| InputError::new_err(format!("{at}: keys must be strings, not {k}")))?;
            let path = if at.is_empty() { key.clone() } else { format!("{at}.{key}") };
            if v.is_none() {
                continue; // None: leave the default
            }
            t.insert(key, to_toml(&v, &path)?);
        }
        return Ok(toml::Value::Table(t));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let items: Vec<Bound<'_, PyAny>> = obj.extract()?;
        return items.iter().map(|v| to_toml(v, at)).collect::<PyResult<Vec<_>>>().map(toml::Value::Array);
    }
    // numpy scalars and arrays
    if let Ok(x) = obj.extract::<f64>() {
        return Ok(toml::Value::Float(x));
    }
    if let Ok(v) = obj.extract::<Vec<f64>>() {
        return Ok(toml::Value::Array(v.into_iter().map(toml::Value::Float).collect()));
    }
    Err(InputError::new_err(format!(
        "{at}: a {} cannot be written in a config (numbers, strings, booleans, lists and dicts can)",
        obj.get_type().name().map(|n| n.to_string()).unwrap_or_default()
    )))
}

/// A TOML value as a Python value (tables as dicts).
pub(crate) fn from_toml<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::String(s) => s.into_pyobject(py)?.into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(x) => x.into_pyobject(py)?.into_any(),
        toml::Value::Boolean(b) => b.into_pyobject(py)?.to_owned().into_any(),
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
        toml::Value::Array(a) => {
            let items = a.iter().map(|x| from_toml(py, x)).collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, from_toml(py, x)?)?;
            }
            d.into_any()
        }
    })
}
