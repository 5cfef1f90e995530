//! The HDF5 output files of quakejoint, written and read by one layer that
//! every command uses (`docs/hdf5-layout.md`):
//!
//! - [`h5`]: writing datasets under checksums (Fletcher32 chunks,
//!   fixed-length text, compact scalars in the HDF5 1.10 format), each
//!   file under a temporary name renamed into place when complete;
//! - [`read`]: reading them back, the damaged object named;
//! - [`run_h5`]: the provenance every file carries and the files of single
//!   runs (`simulate`, `service`, `model --sparsity`);
//! - [`files`]: which file is which, so that no output overwrites an input;
//! - [`time`]: the UTC time stamps of the files.
//!
//! The sweep's file (`quakejoint-sweep`'s `sweep_h5`) is written and read
//! with these.

#![deny(missing_docs)]

pub mod error;
pub mod files;
pub mod h5;
pub mod read;
pub mod run_h5;
pub mod time;

pub use error::OutputError;
