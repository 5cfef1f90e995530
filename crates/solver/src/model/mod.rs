//! What the user describes: bodies, force elements, constraints and loads.
//!
//! Nothing here knows how the solver linearises the system; that is the job
//! of [`crate::assembly`].

pub mod body;
pub mod constraint;
pub mod force;
pub mod system;
