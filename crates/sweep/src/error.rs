//! Errors of the orchestrator.

use std::path::Path;

use thiserror::Error;

/// Writing an output file failed.
#[derive(Debug, Error)]
#[error("{path}: {message}")]
pub struct OutputError {
    /// The file.
    pub path: String,
    /// What went wrong.
    pub message: String,
}

impl OutputError {
    pub(crate) fn io(path: &Path, e: std::io::Error) -> Self {
        Self { path: path.display().to_string(), message: e.to_string() }
    }
    pub(crate) fn hdf5(path: &Path, e: hdf5::Error) -> Self {
        Self { path: path.display().to_string(), message: format!("HDF5: {e}") }
    }
}
