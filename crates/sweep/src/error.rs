//! Errors of the orchestrator.

use std::path::Path;

use quakejoint_model::ModelError;
use quakejoint_motion::RecordError;
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
        Self { path: path.display().to_string(), message: in_words(&e.to_string()) }
    }
}

/// An HDF5 error in the user's words: a failed system call as the
/// operating system says it (`File too large (os error 27)`, `No space
/// left on device (os error 28)`), not the library's internals (buffer
/// addresses, `bytes actually written = 18446744073709551615`); other
/// messages as they are, after `HDF5: `.
fn in_words(text: &str) -> String {
    let errno =
        text.split("errno = ").nth(1).and_then(|r| r.split(',').next()).and_then(|n| n.trim().parse::<i32>().ok());
    let said = text.split("error message = '").nth(1).and_then(|r| r.split('\'').next());
    match (errno, said) {
        (Some(n), Some(m)) => {
            let action = if text.contains("write") { "writing" } else { "reading" };
            format!("{action} failed: {m} (os error {n})")
        }
        _ => format!("HDF5: {}", text.trim()),
    }
}

#[cfg(test)]
mod tests {
    use super::in_words;

    #[test]
    fn system_errors_are_said_as_the_system_says_them() {
        let e = "H5Fflush(): unable to flush file's cached information: file write failed: time = Thu Nov 26 \
                 14:57:59 2026\n, filename = 'r.h5.tmp', file descriptor = 3, errno = 28, error message = 'No space \
                 left on device', buf = 0x560e712aad46, total write size = 1498, bytes this sub-write = 1498, bytes \
                 actually written = 18446744073709551615, offset = 0";
        assert_eq!(in_words(e), "writing failed: No space left on device (os error 28)");
        assert_eq!(in_words("/spectrum/reduction is damaged"), "HDF5: /spectrum/reduction is damaged");
    }
}

/// Anything that stops a sweep (failed jobs do not: they are recorded).
#[derive(Debug, Error)]
pub enum SweepError {
    /// The `[sweep]` table is wrong.
    #[error("{field}: {message}")]
    Config {
        /// The key.
        field: String,
        /// What is wrong.
        message: String,
    },
    /// The base config is wrong.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A record cannot be read.
    #[error(transparent)]
    Record(#[from] RecordError),
    /// A file cannot be read or written.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// The operating system's message.
        message: String,
    },
    /// The HDF5 output cannot be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The journal cannot be used.
    #[error("{path}: {message}")]
    Journal {
        /// The journal file.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// Files to merge do not belong together.
    #[error("merge: {0}")]
    Merge(String),
    /// The merged result would be incomplete (and a partial one was not
    /// accepted): some jobs have no result.
    #[error(
        "merge: the result would be incomplete: {report}\nrun the missing shards (or continue them: `quakejoint \
         sweep <config> --shard K/N --output <shard file>`), or accept a partial result with --allow-partial"
    )]
    Incomplete {
        /// Which shards and jobs are missing, in words.
        report: String,
        /// The shards `(k, n)` to run or continue: those no input holds
        /// (when the inputs are shards of one split) and those with jobs
        /// not run.
        shards: Vec<(usize, usize)>,
    },
    /// Writing failed while jobs were running: the sweep stopped, the
    /// journal keeps every finished job.
    #[error(
        "{cause}; the sweep stopped, and the journal {journal} keeps every finished job: run the same command again \
         once the problem is fixed (it continues from the journal)"
    )]
    Stopped {
        /// What failed.
        cause: Box<SweepError>,
        /// The journal.
        journal: String,
    },
}

impl SweepError {
    /// Whether the error is caused by the input (exit code 2) rather than by
    /// the machine (a full disk, say).
    pub fn is_input_error(&self) -> bool {
        match self {
            SweepError::Config { .. }
            | SweepError::Record(_)
            | SweepError::Journal { .. }
            | SweepError::Merge(_)
            | SweepError::Incomplete { .. } => true,
            SweepError::Model(m) => m.is_input_error(),
            SweepError::Io { .. } | SweepError::Output(_) => false,
            SweepError::Stopped { cause, .. } => cause.is_input_error(),
        }
    }
}
