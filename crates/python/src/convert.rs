//! Conversions between Python values and the engine's inputs: record specs
//! from keyword arguments, TOML values from dicts and back, number
//! sequences.

use std::path::Path;

use numpy::{PyReadonlyArray1, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyComplex, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
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
    /// `channel` (its number in a COSMOS or CSMIP file).
    pub channel: Option<u32>,
    /// `azimuth` [degrees from north].
    pub azimuth: Option<f64>,
    /// `allow_vertical`.
    pub allow_vertical: bool,
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
    put("channel", fields.channel.map(|c| toml::Value::Integer(c as i64)));
    put("azimuth", fields.azimuth.map(toml::Value::Float));
    put("allow_vertical", fields.allow_vertical.then_some(toml::Value::Boolean(true)));
    let spec: RecordSpec = toml::Value::Table(t)
        .try_into()
        .map_err(|e: toml::de::Error| InputError::new_err(format!("{}: {}", path.display(), e.message())))?;
    spec.validate().map_err(crate::input_error)?;
    Ok(spec)
}

/// Deepest nesting of dicts and lists read into a config. The deepest
/// config key, `sweep.cases[i].joint.friction.mu`, is 6 levels down; a dict
/// nested 100,000 deep (or one that contains itself through an object the
/// cycle check does not see) is refused here, naming where, instead of
/// being followed until the stack runs out.
pub(crate) const MAX_DEPTH: usize = 32;

/// `obj` as Python's `str()` writes it, cut to a readable length: an
/// integer of hundreds of digits shows its first digits and how many there
/// are.
pub(crate) fn shown(obj: &Bound<'_, PyAny>) -> String {
    let text = obj.str().map(|s| s.to_string()).unwrap_or_else(|_| "?".into());
    if obj.is_instance_of::<PyInt>() && text.len() > 24 && text.is_ascii() {
        let digits = text.trim_start_matches('-').len();
        return format!("{}... ({digits} digits)", &text[..22]);
    }
    quakejoint_motion::excerpt(&text, 80)
}

/// An integer as a config shows it: as the model writes a number (`1e30`,
/// `-3`), else its first digits.
fn shown_int(obj: &Bound<'_, PyAny>) -> String {
    match obj.extract::<f64>() {
        Ok(x) if x.is_finite() => quakejoint_motion::number(x),
        _ => shown(obj),
    }
}

/// `field = value: must be within <range> <unit>`, as the model says it.
fn beyond_limit(field: &str, value: &str, unit: &str, bound: &quakejoint_model::limits::Bound) -> String {
    let unit = if unit == "1" { String::new() } else { format!(" {unit}") };
    format!("{field} = {value}: must be within {}{unit}", bound.describe())
}

/// The dtype kind of a numpy value (a scalar or an array): "c" complex,
/// "b" boolean, "f" float...; None for other objects.
fn numpy_kind(obj: &Bound<'_, PyAny>) -> Option<String> {
    obj.getattr("dtype").and_then(|d| d.getattr("kind")).and_then(|k| k.extract::<String>()).ok()
}

/// Whether `obj` is a complex number (Python's or numpy's).
fn is_complex(obj: &Bound<'_, PyAny>) -> bool {
    obj.is_instance_of::<PyComplex>() || numpy_kind(obj).as_deref() == Some("c")
}

/// A real number given as the argument `what` of `func` (`period`, `dt`,
/// `scale`): a Python or numpy float or integer, refused with an
/// `InputError` naming the argument when it is complex, a boolean, too
/// large for a float or not a number.
pub(crate) fn real(obj: &Bound<'_, PyAny>, func: &str, what: &str) -> PyResult<f64> {
    let refuse = |why: &str| InputError::new_err(format!("{func}: {what} = {}: {why}", shown(obj)));
    if is_complex(obj) {
        return Err(refuse("must be a real number, not complex"));
    }
    if obj.is_instance_of::<PyBool>() || numpy_kind(obj).as_deref() == Some("b") {
        return Err(refuse("must be a number, not a boolean"));
    }
    if obj.is_instance_of::<PyString>() {
        return Err(refuse("must be a number, not a string"));
    }
    match obj.extract::<f64>() {
        Ok(x) => Ok(x),
        Err(_) if obj.is_instance_of::<PyInt>() => Err(refuse("too large for a floating-point number")),
        Err(_) => Err(refuse("must be a real number")),
    }
}

/// [`real`] of an optional argument.
pub(crate) fn real_opt(obj: Option<&Bound<'_, PyAny>>, func: &str, what: &str) -> PyResult<Option<f64>> {
    obj.map(|o| real(o, func, what)).transpose()
}

/// A whole number from `min` to `max` given as the argument `what` of
/// `func` (`column`, `subdivisions`): a Python or numpy integer, refused
/// with an `InputError` naming the argument otherwise.
pub(crate) fn whole(obj: &Bound<'_, PyAny>, func: &str, what: &str, min: i64, max: i64) -> PyResult<i64> {
    let refuse =
        || InputError::new_err(format!("{func}: {what} = {}: must be a whole number from {min} to {max}", shown(obj)));
    if obj.is_instance_of::<PyBool>() || numpy_kind(obj).as_deref() == Some("b") {
        return Err(refuse());
    }
    let index = obj.call_method0("__index__").map_err(|_| refuse())?;
    let v: i64 = index.extract().map_err(|_| refuse())?;
    if (min..=max).contains(&v) {
        Ok(v)
    } else {
        Err(refuse())
    }
}

/// Real numbers given as the argument `what` of `func`: a number, a
/// sequence or an array of any shape, with that shape (`[]` for a number).
/// Complex numbers (Python's, numpy's, or an array of them) are refused
/// rather than their imaginary parts dropped, as are booleans, strings and
/// other objects, each with an `InputError` naming the argument.
pub(crate) struct Numbers {
    /// The values, in C order.
    pub values: Vec<f64>,
    /// The shape: `[]` for a single number.
    pub shape: Vec<usize>,
}

impl Numbers {
    /// Of `obj`, the argument `what` of `func`.
    pub(crate) fn of(obj: &Bound<'_, PyAny>, func: &str, what: &str) -> PyResult<Numbers> {
        // the common cases, without numpy's conversion
        if let Ok(a) = obj.extract::<PyReadonlyArray1<'_, f64>>() {
            return Ok(Numbers { shape: vec![a.len()], values: a.as_array().to_vec() });
        }
        if obj.is_instance_of::<PyFloat>() || obj.is_instance_of::<PyInt>() {
            return Ok(Numbers { values: vec![real(obj, func, what)?], shape: vec![] });
        }
        let refuse = |why: String| InputError::new_err(format!("{func}: `{what}` {why}"));
        let numpy = obj.py().import("numpy")?;
        let array = numpy
            .call_method1("asarray", (obj,))
            .map_err(|e| refuse(format!("cannot be read as an array of numbers ({e})")))?;
        let shape: Vec<usize> = array.getattr("shape")?.extract()?;
        let dtype = array.getattr("dtype")?;
        let kind: String = dtype.getattr("kind")?.extract()?;
        let dtype_name = dtype.str()?.to_string();
        let complex = || {
            refuse(format!(
                "is complex ({dtype_name}): the imaginary part would be dropped; pass real numbers (`.real`, if \
                 that is meant)"
            ))
        };
        if kind == "c" {
            return Err(complex());
        }
        if shape.is_empty() && kind != "O" {
            return Ok(Numbers { values: vec![real(obj, func, what)?], shape });
        }
        match kind.as_str() {
            "f" | "i" | "u" => {}
            "O" => {
                for item in array.getattr("flat")?.try_iter()? {
                    if is_complex(&item?) {
                        return Err(complex());
                    }
                }
                if shape.is_empty() {
                    return Ok(Numbers { values: vec![real(&array.call_method0("item")?, func, what)?], shape });
                }
            }
            _ => return Err(refuse(format!("must be real numbers, not an array of {dtype_name}"))),
        }
        let floats = array
            .call_method1("astype", (numpy.getattr("float64")?,))
            .map_err(|e| refuse(format!("must be real numbers ({e})")))?;
        let floats = floats.extract::<PyReadonlyArrayDyn<'_, f64>>()?;
        Ok(Numbers { values: floats.as_array().iter().copied().collect(), shape })
    }

    /// Of `obj`, which must be a number or a 1-D sequence (the `periods` or
    /// `damping` of a spectrum).
    pub(crate) fn at_most_1d(obj: &Bound<'_, PyAny>, func: &str, what: &str) -> PyResult<Numbers> {
        let n = Self::of(obj, func, what)?;
        if n.shape.len() > 1 {
            return Err(InputError::new_err(format!(
                "{func}: `{what}` must be a number or a 1-D sequence of numbers, not an array of shape {:?}",
                n.shape
            )));
        }
        Ok(n)
    }
}

/// A Python value (dict, list, str, int, float, bool, numpy values) as a
/// TOML value; `at` is its dotted key, for messages. A dict or list that
/// contains itself, or nesting deeper than [`MAX_DEPTH`], is an
/// `InputError` naming where; so are whole numbers beyond the 64 bits of
/// TOML (with the key's range, when it has one) and complex numbers.
pub(crate) fn to_toml(obj: &Bound<'_, PyAny>, at: &str) -> PyResult<toml::Value> {
    let depth = if at.is_empty() { 0 } else { at.split('.').count() };
    Walk { ancestors: Vec::new() }.value(obj, at, depth)
}

/// `path: nested deeper than MAX_DEPTH levels`, the path cut to a readable
/// length.
pub(crate) fn too_deep(path: &str) -> String {
    format!(
        "{}: nested deeper than {MAX_DEPTH} levels (no config key is nested that deep)",
        quakejoint_motion::excerpt(path, 200)
    )
}

/// The walk of [`to_toml`]: the dicts and lists on the way down, to find
/// one that contains itself.
struct Walk {
    /// Address and dotted key of each container above the current value.
    ancestors: Vec<(usize, String)>,
}

impl Walk {
    fn value(&mut self, obj: &Bound<'_, PyAny>, at: &str, depth: usize) -> PyResult<toml::Value> {
        if obj.is_instance_of::<PyBool>() {
            return Ok(toml::Value::Boolean(obj.extract()?));
        }
        if obj.is_instance_of::<PyInt>() {
            return integer(obj, at);
        }
        if obj.is_instance_of::<PyFloat>() {
            return Ok(toml::Value::Float(obj.extract()?));
        }
        if obj.is_instance_of::<PyString>() {
            return Ok(toml::Value::String(obj.extract()?));
        }
        if obj.is_instance_of::<PyComplex>() {
            return Err(InputError::new_err(format!("{at} = {}: must be a real number, not complex", shown(obj))));
        }
        let is_dict = obj.is_instance_of::<PyDict>();
        if is_dict || obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
            let address = obj.as_ptr() as usize;
            if let Some((_, above)) = self.ancestors.iter().find(|(a, _)| *a == address) {
                let above = if above.is_empty() { "the whole config".to_string() } else { above.clone() };
                return Err(InputError::new_err(format!(
                    "{at}: refers back to {above} (a dict or list that contains itself); a config is a tree of \
                     dicts and lists"
                )));
            }
            if depth > MAX_DEPTH {
                return Err(InputError::new_err(too_deep(at)));
            }
            self.ancestors.push((address, at.to_string()));
            let value = if is_dict { self.table(obj, at, depth) } else { self.array(obj, at, depth) };
            self.ancestors.pop();
            return value;
        }
        // numpy scalars and arrays: as the Python values they hold
        if obj.hasattr("dtype")? && obj.hasattr("tolist")? {
            // one level deeper: an object whose tolist() gives itself back
            // (a 0-d object array holding itself) ends at MAX_DEPTH
            if depth > MAX_DEPTH {
                return Err(InputError::new_err(too_deep(at)));
            }
            return self.value(&obj.call_method0("tolist")?, at, depth + 1);
        }
        // other real numbers (fractions, decimals)
        if let Ok(x) = obj.extract::<f64>() {
            return Ok(toml::Value::Float(x));
        }
        Err(InputError::new_err(format!(
            "{at}: a {} cannot be written in a config (numbers, strings, booleans, lists and dicts can)",
            obj.get_type().name().map(|n| n.to_string()).unwrap_or_default()
        )))
    }

    fn table(&mut self, obj: &Bound<'_, PyAny>, at: &str, depth: usize) -> PyResult<toml::Value> {
        let d = obj.cast::<PyDict>()?;
        let mut t = toml::Table::new();
        for (k, v) in d.iter() {
            let key: String = k.extract().map_err(|_| {
                let place = if at.is_empty() { String::new() } else { format!("{at}: ") };
                InputError::new_err(format!("{place}keys must be strings, not {}", shown(&k)))
            })?;
            let path = if at.is_empty() { key.clone() } else { format!("{at}.{key}") };
            if v.is_none() {
                continue; // None: leave the default
            }
            t.insert(key, self.value(&v, &path, depth + 1)?);
        }
        Ok(toml::Value::Table(t))
    }

    fn array(&mut self, obj: &Bound<'_, PyAny>, at: &str, depth: usize) -> PyResult<toml::Value> {
        let items: Vec<Bound<'_, PyAny>> = obj.extract()?;
        let mut out = Vec::with_capacity(items.len());
        for (i, v) in items.iter().enumerate() {
            out.push(self.value(v, &format!("{at}[{i}]"), depth + 1)?);
        }
        Ok(toml::Value::Array(out))
    }
}

/// A Python integer as a TOML integer: one beyond TOML's 64 bits is an
/// `InputError` naming the key, with the key's range when it has one.
fn integer(obj: &Bound<'_, PyAny>, at: &str) -> PyResult<toml::Value> {
    if let Ok(v) = obj.extract::<i64>() {
        return Ok(toml::Value::Integer(v));
    }
    let value = shown_int(obj);
    Err(InputError::new_err(match quakejoint_model::limits::limit(at) {
        Some((unit, bound)) => beyond_limit(at, &value, unit, &bound),
        None => {
            format!("{at} = {value}: out of range (a config holds whole numbers from {} to {})", i64::MIN, i64::MAX)
        }
    }))
}

/// The message of a TOML error met while reading a config from a dict:
/// `key = value: why`. The keys of a dict's config are no lines of a file,
/// so the error names them; whole numbers a field cannot hold (`-1` steps,
/// `1e5` of a count) are said in words, with the key's range when it has
/// one.
pub(crate) fn dict_error(e: &toml::de::Error) -> String {
    let message = e.message().trim();
    let text = e.to_string();
    let Some(path) = text.lines().rev().find_map(|l| l.strip_prefix("in `").and_then(|l| l.strip_suffix('`'))) else {
        return message.to_string();
    };
    let unsigned_max = |ty: &str| match ty {
        "u8" => Some(u8::MAX as u64),
        "u16" => Some(u16::MAX as u64),
        "u32" => Some(u32::MAX as u64),
        "u64" | "usize" => Some(u64::MAX),
        _ => None,
    };
    if let Some((value, ty)) =
        message.strip_prefix("invalid value: integer `").and_then(|r| r.split_once("`, expected "))
    {
        if let Some(max) = unsigned_max(ty) {
            if let (Some((unit, bound)), Ok(v)) = (quakejoint_model::limits::limit(path), value.parse::<f64>()) {
                return beyond_limit(path, &quakejoint_motion::number(v), unit, &bound);
            }
            return if value.starts_with('-') {
                format!("{path} = {value}: must be a whole number >= 0")
            } else {
                format!("{path} = {value}: must be a whole number <= {max}")
            };
        }
    }
    if let Some((value, ty)) =
        message.strip_prefix("invalid type: floating point `").and_then(|r| r.split_once("`, expected "))
    {
        if unsigned_max(ty).is_some() || ty.starts_with('i') {
            return format!("{path} = {value}: must be a whole number");
        }
    }
    format!("{path}: {message}")
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
