//! Planar multibody dynamics for stiff, frictional, constrained systems.
//!
//! Build a [`System`] of rigid bodies, force elements (bushings, regularised
//! Coulomb friction, spring-dampers, coordinate springs, applied loads) and
//! constraints (revolute, prismatic, point-on-line, weld, coordinate
//! drivers), excite it with gravity and base acceleration, compile it into an
//! [`Assembly`] and integrate it with [`Radau5`]:
//!
//! ```
//! use std::sync::Arc;
//! use quakejoint_solver::*;
//!
//! // A 1 kg pendulum on a 1 m massless link, released from horizontal.
//! let mut sys = System::new();
//! let bob = sys.add_body(Body::new("bob", 1.0, 1e-6, [1.0, 0.0, 0.0]));
//! sys.add_constraint(Constraint::Revolute(Revolute {
//!     body_a: bob, point_a: [-1.0, 0.0], body_b: BodyId::GROUND, point_b: [0.0, 0.0],
//! }));
//! sys.set_excitation(Excitation { gravity: [0.0, -9.81], ..Default::default() });
//! let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).unwrap());
//! let mut sim = Radau5::new(asm, IntegratorOptions::default()).unwrap();
//! sim.run(0.5, &mut NoObserver).unwrap();
//! assert!(sim.energy().relative_error() < 1e-6);
//! ```
//!
//! An [`Observer`] sees every accepted step as a [`StepView`] with its dense
//! output: the state at any time within the step, at requested times
//! ([`OutputTimes`]) and the zeros of functions of the state
//! ([`RootTracker`]); see [`integrator::dense`] and `docs/solver.md`,
//! "Using the library".
//!
//! The crate is layered: [`model`] is what the user describes,
//! [`assembly`] what the solver linearises (kernels with analytic
//! derivatives scattered into a fixed sparse pattern), [`linalg`] the sparse
//! factorisations, [`integrator`] the time stepping. Nothing panics on user
//! input or on a singular matrix; see [`error`].

#![deny(missing_docs)]
// Numerical kernels index several parallel arrays with one loop variable;
// iterator chains would hide which entries go together.
#![allow(clippy::needless_range_loop)]

pub mod assembly;
pub mod error;
pub mod fd;
pub mod integrator;
pub mod isa;
pub mod linalg;
pub mod model;
pub mod reference;
pub mod timefn;

// The code of docs/solver.md ("Using the library") is compiled and run with
// the doc tests.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/solver.md")]
struct SolverGuide;

pub use assembly::{Assembly, AssemblyOptions, ContactValue, ForceExtremes, JacobianValues, Powers, Workspace};
pub use error::{BuildError, DenseOutputError, LinalgError, SolverError, StepFailure};
pub use integrator::events::{ContactEvent, ContactEventKind};
pub use integrator::radau5::ConstraintResiduals;
pub use integrator::{
    EnergyBalance, IntegratorOptions, JacobianMode, NoObserver, Observer, OutputTime, OutputTimes, Radau5, Root,
    RootTracker, StateBuffer, Stats, StepView,
};
pub use linalg::block_lu::BlockOrdering;
pub use linalg::LinearSolver;
pub use model::body::{Body, BodyId, Coord};
pub use model::constraint::{Constraint, ConstraintId, Driver, Linear, PointOnLine, Prismatic, Revolute, Weld};
pub use model::force::{
    AppliedLoad, BodyState, Bushing, Contact, ContactLaw, CoordinateSpring, CustomElement, CustomForce, Excitation,
    ForceElement, ForceId, Friction, FrictionLaw, HertzDamping, SpringDamper, MIN_APPROACH_SPEED,
};
pub use model::system::{System, NO_GROUP};
pub use timefn::{LaggedGround, SmoothTriangle, TimeFunction, TimeSeries};
