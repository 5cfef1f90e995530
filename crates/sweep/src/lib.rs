//! The spectrum orchestrator: sweeps of the joint model over bridge
//! periods, damping ratios, records and parameter cases, run on worker
//! threads, journalled for `--resume`, written to HDF5, shardable across
//! machines and merged back.

#![deny(missing_docs)]

pub mod error;
pub mod fault;
pub mod h5;
pub mod journal;
pub mod merge;
pub mod plan;
pub mod results;
pub mod runner;
pub mod sweep_h5;
pub mod time;

pub use error::{OutputError, SweepError};
pub use merge::{merge, MergeSummary};
pub use plan::{Job, Plan};
pub use results::{status, Results, FIELDS};
pub use runner::{run_sweep, Summary, SweepOptions};
