//! The extension module `quakejoint._quakejoint` of the Python package
//! `quakejoint` (python/quakejoint): the engine on numpy arrays.
//!
//! - `record`: records read from files or built from arrays, their
//!   statistics and exact linear spectra;
//! - `config`: configs from TOML files, text or dicts, validated as the
//!   command line validates them;
//! - `run`: coupled earthquake runs and service loops, with the GIL
//!   released and Ctrl-C honoured;
//! - `calibrate`: the joint's link element and its exports;
//! - `fragility`: lognormal fragility fits, their bootstrap, and the mean
//!   annual frequency of a limit state;
//! - `sweep`: sweep files read and checked by the command line's reader.
//!
//! Errors are Python exceptions with the command line's messages:
//! `InputError` where the command line exits with 2 (bad input),
//! `SimulationError` where it exits with 1.

#![deny(missing_docs)]

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

mod calibrate;
mod config;
mod convert;
mod fragility;
mod record;
mod run;
mod sweep;

create_exception!(_quakejoint, Error, PyException, "Base class of the errors of quakejoint.");
create_exception!(
    _quakejoint,
    InputError,
    Error,
    "Bad input: a file, field or value the model cannot take (the command line's exit code 2). The message \
     names the file, field or value."
);
create_exception!(
    _quakejoint,
    SimulationError,
    Error,
    "A run that failed: the solver could not continue, or a limit of time or steps was reached (the command \
     line's exit code 1)."
);

/// The error and its causes, each cause once (the library errors quote
/// their source in their own message), as the command line prints them.
pub(crate) fn message(err: &dyn std::error::Error) -> String {
    let mut text = String::new();
    let mut cause = Some(err);
    while let Some(c) = cause {
        let part = c.to_string();
        if !text.contains(&part) {
            if !text.is_empty() {
                text.push_str(": ");
            }
            text.push_str(&part);
        }
        cause = c.source();
    }
    text
}

/// A model error as the Python exception of its kind.
pub(crate) fn model_error(err: quakejoint_model::ModelError) -> PyErr {
    if err.is_input_error() {
        InputError::new_err(message(&err))
    } else {
        SimulationError::new_err(message(&err))
    }
}

/// A model error about the config read from `source`: an input error
/// that does not name the config yet is prefixed with it, as the command
/// line does, so that the message says which file to fix.
pub(crate) fn config_error(err: quakejoint_model::ModelError, source: &str) -> PyErr {
    let text = message(&err);
    if err.is_input_error() && !text.contains(source) {
        InputError::new_err(format!("{source}: {text}"))
    } else {
        model_error(err)
    }
}

/// A record or spectrum error (always bad input).
pub(crate) fn input_error(err: impl std::error::Error) -> PyErr {
    InputError::new_err(message(&err))
}

/// The extension module.
#[pymodule]
fn _quakejoint(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("Error", py.get_type::<Error>())?;
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("SimulationError", py.get_type::<SimulationError>())?;
    m.add("G", quakejoint_motion::G)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    record::register(m)?;
    config::register(m)?;
    run::register(m)?;
    calibrate::register(m)?;
    fragility::register(m)?;
    sweep::register(m)?;
    Ok(())
}
