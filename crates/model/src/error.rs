//! Errors of the model crate.

use quakejoint_motion::RecordError;
use quakejoint_solver::{BuildError, SolverError};
use thiserror::Error;

/// Anything that stops a model from being built or run.
#[derive(Debug, Error)]
pub enum ModelError {
    /// The config file could not be read.
    #[error("{file}: {message}")]
    Io {
        /// The file.
        file: String,
        /// The operating system's message.
        message: String,
    },
    /// The config is not valid TOML or has unknown keys or wrong types.
    #[error("{file}: {message}")]
    Parse {
        /// The file.
        file: String,
        /// The parser's message (with line, column and key).
        message: String,
    },
    /// A value is out of range or inconsistent.
    #[error("{field} = {value}: {reason}")]
    Invalid {
        /// The key, e.g. `joint.pitch`.
        field: String,
        /// The offending value.
        value: String,
        /// What is wrong.
        reason: String,
    },
    /// A value a front end sets for one run (`--period`, Python's `period`,
    /// a sweep's grid) is out of range: named as the front end names it
    /// (`--period 100000: ...`, `period = 100000: ...`).
    #[error("{}: {reason}", if name.starts_with("--") { format!("{name} {value}") } else { format!("{name} = {value}") })]
    Override {
        /// How the front end names it.
        name: String,
        /// The offending value.
        value: String,
        /// What is wrong (the same words whatever the front end).
        reason: String,
    },
    /// The geometry cannot work (a bearing outside its center beam, crossing joists...).
    #[error("geometry: {0}")]
    Geometry(String),
    /// The record could not be read.
    #[error(transparent)]
    Record(#[from] RecordError),
    /// The solver refused the generated system.
    #[error("model: {0}")]
    Build(#[from] BuildError),
    /// The simulation failed.
    #[error("simulation: {0}")]
    Solver(#[from] SolverError),
    /// The run was stopped from outside ([`crate::run::RunOptions::cancel`]).
    #[error("interrupted at t = {time} s")]
    Interrupted {
        /// Simulated time reached \[s\].
        time: f64,
    },
}

impl ModelError {
    /// Whether the error is caused by the input (config, record, geometry)
    /// rather than by a failing simulation.
    pub fn is_input_error(&self) -> bool {
        !matches!(self, ModelError::Solver(_) | ModelError::Interrupted { .. })
    }
}
