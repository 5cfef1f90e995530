//! `Config`: a model config from a TOML file, TOML text or a dict, checked
//! as `quakejoint` checks a config file (the same ranges and messages).

use std::path::{Path, PathBuf};

use pyo3::prelude::*;
use pyo3::types::PyDict;
use quakejoint_model::config::base_dir;
use quakejoint_model::Config;

use crate::convert::{dict_error, from_toml, to_toml, too_deep, MAX_DEPTH};
use crate::{config_error, InputError};

/// A validated config. Relative record paths are read from `base_dir` (the
/// config file's directory, made absolute when the config is made, so that
/// changing the working directory later does not lose them).
#[pyclass(name = "Config", module = "quakejoint", frozen)]
#[derive(Clone)]
pub struct PyConfig {
    pub(crate) config: Config,
    pub(crate) base_dir: PathBuf,
    /// What the config was read from, for messages.
    pub(crate) source: String,
}

impl PyConfig {
    /// Parses and validates TOML text.
    fn parse(text: &str, source: &str, base_dir: PathBuf) -> PyResult<Self> {
        let mut config = Config::from_toml(text, source).map_err(|e| config_error(e, source))?;
        config.load_modes(&base_dir).map_err(|e| config_error(e, source))?;
        check_geometry(&config, source)?;
        Self::check_sweep(text, source, &base_dir)?;
        Ok(PyConfig { config, base_dir, source: source.into() })
    }

    /// Validates the tables of a dict (`Config(d)`, `replace`): read
    /// without a text in between, so that a message names the key, not a
    /// line of text the user never wrote.
    fn from_tables(table: toml::Table, source: &str, base_dir: PathBuf) -> PyResult<Self> {
        let text = toml::to_string(&table).unwrap_or_default();
        let config: Config = toml::Value::Table(table)
            .try_into()
            .map_err(|e: toml::de::Error| InputError::new_err(format!("{source}: {}", dict_error(&e))))?;
        config.validate().map_err(|e| config_error(e, source))?;
        let mut config = config;
        config.load_modes(&base_dir).map_err(|e| config_error(e, source))?;
        check_geometry(&config, source)?;
        Self::check_sweep(&text, source, &base_dir)?;
        Ok(PyConfig { config, base_dir, source: source.into() })
    }

    /// The config's `[sweep]` table, checked as the command line checks it.
    fn check_sweep(text: &str, source: &str, base_dir: &Path) -> PyResult<()> {
        quakejoint_sweep::plan::check_sweep(text, source, base_dir).map_err(|e| {
            let message = crate::message(&e);
            let message = if message.contains(source) { message } else { format!("{source}: {message}") };
            if e.is_input_error() {
                InputError::new_err(message)
            } else {
                crate::SimulationError::new_err(message)
            }
        })
    }

    /// The config as a TOML table.
    fn table(&self) -> PyResult<toml::Table> {
        toml::Table::try_from(&self.config).map_err(|e| InputError::new_err(format!("{}: {e}", self.source)))
    }
}

/// `path` made absolute against the current directory (as it is now).
fn absolute(path: PathBuf) -> PathBuf {
    std::path::absolute(&path).unwrap_or(path)
}

/// Whether the joint's geometry can work (beams fit their pitch, joists
/// reach their boxes), as building the model checks it: a config that
/// cannot be built is refused when it is made, not when it is run.
fn check_geometry(config: &Config, source: &str) -> PyResult<()> {
    if config.joint.enabled {
        quakejoint_model::geometry::Geometry::new(config).map_err(|e| config_error(e, source))?;
    }
    Ok(())
}

/// An `InputError` about a dict's value, prefixed with what the config is
/// read from (`config (dict)`); other errors (a KeyboardInterrupt, say) as
/// they are.
fn named(py: Python<'_>, e: PyErr, source: &str) -> PyErr {
    if e.is_instance_of::<InputError>(py) {
        InputError::new_err(format!("{source}: {}", e.value(py)))
    } else {
        e
    }
}

/// Sets `value` at the dotted `key` of `table`, merging dicts into tables.
fn set_dotted(table: &mut toml::Table, key: &str, value: toml::Value) {
    let (head, rest) = match key.split_once('.') {
        Some((h, r)) => (h, Some(r)),
        None => (key, None),
    };
    match rest {
        Some(rest) => {
            let entry = table.entry(head.to_string()).or_insert_with(|| toml::Value::Table(toml::Table::new()));
            if !entry.is_table() {
                *entry = toml::Value::Table(toml::Table::new());
            }
            if let toml::Value::Table(t) = entry {
                set_dotted(t, rest, value);
            }
        }
        None => match (table.get_mut(head), value) {
            (Some(toml::Value::Table(old)), toml::Value::Table(new)) => {
                for (k, v) in new {
                    set_dotted(old, &k, v);
                }
            }
            (_, value) => {
                table.insert(head.to_string(), value);
            }
        },
    }
}

#[pymethods]
impl PyConfig {
    /// A config from a dict of the TOML file's tables (`{"bridge": {"mass":
    /// 2e8}}`; omitted keys take their defaults), or every default (the
    /// reference model under the built-in Corralitos record) without one.
    /// Relative record paths are taken from `base_dir`. A dict that
    /// contains itself or is nested deeper than 32 levels, a whole number
    /// beyond its field's range and a complex number are InputErrors
    /// naming the key.
    #[new]
    #[pyo3(signature = (tables=None, *, base_dir=PathBuf::from(".")))]
    fn new(tables: Option<&Bound<'_, PyDict>>, base_dir: PathBuf) -> PyResult<Self> {
        const SOURCE: &str = "config (dict)";
        let table = match tables {
            Some(d) => match to_toml(d.as_any(), "") {
                Ok(toml::Value::Table(t)) => t,
                Ok(_) => unreachable!("a dict converts to a table"),
                Err(e) => return Err(named(d.py(), e, SOURCE)),
            },
            None => toml::Table::new(),
        };
        Self::from_tables(table, SOURCE, absolute(base_dir))
    }

    /// Reads a config file (as `quakejoint simulate <config>` does).
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Self> {
        let source = path.display().to_string();
        let text = quakejoint_motion::read_input_text(&path, quakejoint_motion::MAX_CONFIG_BYTES)
            .map_err(|e| InputError::new_err(format!("{source}: cannot read the config: {e}")))?;
        // absolute: a later os.chdir must not lose the config's records
        Self::parse(&text, &source, absolute(base_dir(&path)))
    }

    /// Parses TOML text; `source` names it in messages.
    #[staticmethod]
    #[pyo3(signature = (text, *, base_dir=PathBuf::from("."), source="config (text)".to_string()))]
    fn from_toml(text: &str, base_dir: PathBuf, source: String) -> PyResult<Self> {
        Self::parse(text, &source, absolute(base_dir))
    }

    /// A copy with some values changed and validated again: dotted keys
    /// (`{"bridge.mass": 2e8, "joint.friction.mu": 0.1}`) or nested dicts.
    fn replace(&self, changes: &Bound<'_, PyDict>) -> PyResult<Self> {
        let source = if self.source.ends_with(" (replaced)") {
            self.source.clone()
        } else {
            format!("{} (replaced)", self.source)
        };
        let mut table = self.table()?;
        for (k, v) in changes.iter() {
            let key: String =
                k.extract().map_err(|_| InputError::new_err(format!("replace: key {k} is not a string")))?;
            if key.split('.').count() > MAX_DEPTH {
                return Err(InputError::new_err(format!("replace: {}", too_deep(&key))));
            }
            let value = to_toml(&v, &key).map_err(|e| named(changes.py(), e, &source))?;
            set_dotted(&mut table, &key, value);
        }
        Self::from_tables(table, &source, self.base_dir.clone())
    }

    /// Every value, defaults filled in, as nested dicts (SI units).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        from_toml(py, &toml::Value::Table(self.table()?))
    }

    /// Every value, defaults filled in, as TOML text.
    fn to_toml(&self) -> PyResult<String> {
        toml::to_string(&self.config).map_err(|e| InputError::new_err(format!("{}: {e}", self.source)))
    }

    /// Directory against which relative record paths are read.
    #[getter]
    fn base_dir(&self) -> &Path {
        &self.base_dir
    }

    /// What the config was read from.
    #[getter]
    fn source(&self) -> &str {
        &self.source
    }

    /// The bridge's natural period [s].
    #[getter]
    fn period(&self) -> f64 {
        self.config.bridge.natural_period()
    }

    /// Whether the joint is part of the model.
    #[getter]
    fn joint(&self) -> bool {
        self.config.joint.enabled
    }

    fn __repr__(&self) -> String {
        format!(
            "Config(source={:?}, center_beams={}, bridge period={:.4} s, joint={})",
            self.source,
            self.config.joint.center_beams,
            self.config.bridge.natural_period(),
            self.config.joint.enabled
        )
    }
}

/// Adds the config class to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyConfig>()
}
