//! The spectrum orchestrator: runs of the joint model on worker threads,
//! a crash-safe journal and HDF5 output.

#![deny(missing_docs)]

pub mod error;
pub mod h5;
pub mod time;

pub use error::OutputError;
