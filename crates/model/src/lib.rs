//! The swivel-joist modular expansion joint on a single-DOF bridge.
//!
//! [`Config`] describes the joint, the bridge, the record and the solver
//! options (TOML, every parameter defaulted to the reference model of
//! `docs/model.md`). [`generator::build`] turns it into a solver system;
//! [`run::simulate`] runs one earthquake and reports the bridge's spectral
//! values and the joint's demands; [`linear`] gives the same spectral values
//! for the bridge alone, exactly; [`service`] drives the deck through
//! opening and closing cycles and measures the friction work.

#![deny(missing_docs)]

pub mod bridge;
pub mod calibrate;
mod cells;
pub mod config;
pub mod described;
pub mod error;
pub mod fields;
pub mod fragility;
pub mod fuse;
pub mod generator;
pub mod geometry;
pub mod history;
pub mod limits;
pub mod linear;
pub mod link;
pub mod modal;
pub mod placement;
pub mod pounding;
pub mod resources;
pub mod run;
pub mod runspec;
pub mod scenario;
pub mod service;
pub mod validity;
pub mod verification;
mod watch;

pub use config::Config;
pub use error::ModelError;
