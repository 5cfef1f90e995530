//! The spectrum orchestrator: sweeps of the joint model over bridge
//! periods (a bridge given by its modes: a factor on every period of its
//! modes), damping ratios, records and parameter cases, run on worker
//! threads, journalled so that a sweep can be continued, written to HDF5, shardable across
//! machines and merged back.

#![deny(missing_docs)]

pub mod compare;
pub mod error;
pub mod fault;
pub mod fragility;
pub mod journal;
pub mod lock;
pub mod merge;
pub mod plan;
pub mod progress;
pub mod results;
pub mod runner;
pub mod statistics;
pub mod suite_h5;
pub mod sweep_h5;
pub mod sweep_read;

pub use error::{OutputError, SweepError};
pub use merge::{merge, MergeOptions, MergeSummary};
pub use plan::{Job, Plan};
pub use progress::Progress;
pub use results::{status, Results, FIELDS};
pub use runner::{run_sweep, Summary, SweepOptions};
