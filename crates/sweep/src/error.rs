//! Errors of the orchestrator.

use quakejoint_model::ModelError;
use quakejoint_motion::RecordError;
use thiserror::Error;

pub use quakejoint_io::OutputError;

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
