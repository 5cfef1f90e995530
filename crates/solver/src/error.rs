//! Typed errors of the solver crate.
//!
//! Nothing in this crate panics on user input or on a singular matrix: model
//! building returns [`BuildError`], linear algebra returns [`LinalgError`],
//! time integration returns [`SolverError`], which carries the time and the
//! cause of a failure, and a request the dense output cannot answer returns
//! [`DenseOutputError`].

use thiserror::Error;

/// A system description that cannot be turned into a solvable model.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum BuildError {
    /// A parameter is outside its admissible range.
    #[error("{what}: {name} = {value} is invalid ({reason})")]
    InvalidParameter {
        /// The item the parameter belongs to (for example `body "beam 3"`).
        what: String,
        /// Parameter name.
        name: &'static str,
        /// Offending value.
        value: f64,
        /// Why it is rejected.
        reason: &'static str,
    },
    /// An element refers to a body id that does not exist.
    #[error("{what} refers to body id {id}, but the system has only {count} bodies")]
    UnknownBody {
        /// The element that holds the reference.
        what: String,
        /// The offending id.
        id: usize,
        /// Number of bodies in the system (the ground included).
        count: usize,
    },
    /// An element connects a body to itself.
    #[error("{what} connects body \"{body}\" to itself")]
    SelfConnection {
        /// The element.
        what: String,
        /// Name of the body.
        body: String,
    },
    /// An element acts only on coordinates that are locked or on the ground.
    #[error("{what} acts on no free coordinate ({detail})")]
    NoFreeCoordinate {
        /// The element.
        what: String,
        /// Which coordinate(s) it needs.
        detail: String,
    },
    /// More independent constraint equations than coordinates can carry.
    #[error(
        "constraint {constraint} cannot be matched to a free coordinate: the constraints are redundant \
         or over-determine the bodies they act on ({detail})"
    )]
    RedundantConstraints {
        /// Name of a constraint that could not be matched.
        constraint: String,
        /// Extra detail.
        detail: String,
    },
    /// The initial positions violate the constraints by more than the tolerance.
    #[error(
        "initial state violates constraint {constraint} by {residual:.3e} (tolerance {tolerance:.1e}); \
         fix the initial positions"
    )]
    InconsistentInitialState {
        /// Name of the worst constraint.
        constraint: String,
        /// Its residual |g|.
        residual: f64,
        /// Admissible residual.
        tolerance: f64,
    },
    /// The system has no free coordinate at all.
    #[error("the system has no free coordinate")]
    EmptySystem,
    /// A run cannot be resumed in a system that does not extend its own
    /// ([`crate::Radau5::resume`]).
    #[error("a run cannot be resumed in this system: {detail}")]
    NotAnExtension {
        /// What differs.
        detail: String,
    },
}

/// Failure of a linear solve.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LinalgError {
    /// A pivot block is (numerically) singular.
    #[error("singular iteration matrix at {location} (pivot {pivot:.3e}, block scale {scale:.3e})")]
    Singular {
        /// Where the elimination broke down (a body name or an unknown index).
        location: String,
        /// The largest pivot candidate that was found.
        pivot: f64,
        /// The magnitude it was compared with.
        scale: f64,
    },
    /// The solution contained NaN or infinity.
    #[error("linear solve produced a non-finite value")]
    NonFinite,
    /// faer reported an error.
    #[error("sparse LU (faer) failed: {0}")]
    Faer(String),
}

/// Why a step could not be completed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum StepFailure {
    /// Newton's method diverged or did not converge within its iteration limit.
    #[error("Newton iteration did not converge (contraction rate {rate:.3})")]
    Newton {
        /// Last estimated contraction rate.
        rate: f64,
    },
    /// The iteration matrix was singular.
    #[error("{0}")]
    Linalg(#[from] LinalgError),
    /// A force or constraint evaluated to NaN or infinity.
    #[error("non-finite residual (a force or constraint evaluated to NaN or infinity)")]
    NonFinite,
    /// Contacts kept changing mode at the same instant (opening and closing
    /// without the time advancing).
    #[error("contacts changed mode repeatedly without the time advancing (chattering)")]
    Chattering,
    /// The local error could not be brought below the tolerance.
    #[error("local error test failed repeatedly (error norm {error:.3e})")]
    ErrorTest {
        /// Last weighted error norm (1 is the tolerance).
        error: f64,
    },
    /// The step size fell below the minimum.
    #[error("step size {h:.3e} s fell below the minimum {h_min:.3e} s")]
    StepTooSmall {
        /// The step size.
        h: f64,
        /// The minimum allowed.
        h_min: f64,
    },
}

/// A failed time integration.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SolverError {
    /// The model could not be built.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// The integration stopped at time `time`.
    #[error("integration failed at t = {time:.6} s after {attempts} attempts (last step {h:.3e} s): {cause}")]
    StepFailed {
        /// Time of the last accepted state \[s\].
        time: f64,
        /// Step size of the last attempt \[s\].
        h: f64,
        /// Number of consecutive failed attempts.
        attempts: u32,
        /// The last cause.
        cause: StepFailure,
    },
    /// The step limit in the options was reached.
    #[error("step limit of {limit} steps reached at t = {time:.6} s")]
    StepLimit {
        /// The limit.
        limit: u64,
        /// Time reached \[s\].
        time: f64,
    },
    /// The wall-clock limit in the options was reached.
    #[error("time limit of {limit_s} s wall clock reached at t = {time:.6} s")]
    WallClockLimit {
        /// The limit \[s\].
        limit_s: f64,
        /// Simulated time reached \[s\].
        time: f64,
    },
    /// The consistent initial state could not be computed.
    #[error("consistent initial state: {0}")]
    Initialisation(LinalgError),
    /// The requested end time lies before the current time.
    #[error("end time {t_end} lies before the current time {t}")]
    EndBeforeStart {
        /// Requested end time.
        t_end: f64,
        /// Current time.
        t: f64,
    },
}

/// A request that the dense output of a step cannot answer
/// ([`crate::StepView::interpolate`], [`crate::OutputTimes`],
/// [`crate::RootTracker`]).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum DenseOutputError {
    /// The time lies outside the step (by more than a few units in the last
    /// place of its ends): the collocation polynomial would be extrapolated.
    #[error("t = {t} s lies outside the step from {start} s to {end} s")]
    OutsideStep {
        /// The requested time \[s\].
        t: f64,
        /// Start of the step \[s\].
        start: f64,
        /// End of the step \[s\].
        end: f64,
    },
    /// A slice to be written has the wrong length.
    #[error("{what} has {len} entries, the system has {expected}")]
    WrongLength {
        /// Which slice (`q`, `v` or `lambda`).
        what: &'static str,
        /// Its length.
        len: usize,
        /// The number of coordinates (`q`, `v`) or constraint equations (`lambda`).
        expected: usize,
    },
    /// An argument is out of its range (a tolerance, a time step, a list of
    /// times that does not increase).
    #[error("{name} = {value} is invalid ({reason})")]
    InvalidArgument {
        /// The argument.
        name: &'static str,
        /// Its value.
        value: f64,
        /// Why it is refused.
        reason: &'static str,
    },
}
