//! Kinematic constraints as the user describes them. Their equations and
//! derivatives live in `assembly::constraints`.

use super::body::{BodyId, Coord};
use crate::timefn::TimeFunction;

/// Index of a constraint in a [`crate::System`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ConstraintId(pub(crate) u32);

impl ConstraintId {
    /// Position in the system's constraint list.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Revolute joint: a point of `body_a` coincides with a point of `body_b`
/// (2 equations). With `body_b` the ground, `point_b` is a fixed world point.
#[derive(Debug, Clone, PartialEq)]
pub struct Revolute {
    /// First body.
    pub body_a: BodyId,
    /// Joint point on `body_a`, in its frame \[m\].
    pub point_a: [f64; 2],
    /// Second body (may be the ground).
    pub body_b: BodyId,
    /// Joint point on `body_b`, in its frame \[m\] (world point for the ground).
    pub point_b: [f64; 2],
}

/// Prismatic joint: `slider` keeps its orientation relative to `base` and a
/// point of it stays on an axis of `base` (2 equations):
/// `phi_s - phi_b - (phi_s0 - phi_b0) = 0` and `n . (r_P - r_A) = 0`, with `n`
/// the axis normal.
#[derive(Debug, Clone, PartialEq)]
pub struct Prismatic {
    /// The sliding body.
    pub slider: BodyId,
    /// Point of the slider that stays on the axis, in its frame \[m\].
    pub point: [f64; 2],
    /// The body carrying the axis (may be the ground).
    pub base: BodyId,
    /// A point of the axis, in the base frame \[m\].
    pub axis_point: [f64; 2],
    /// Direction of the axis, in the base frame (need not be unit length).
    pub axis_direction: [f64; 2],
}

/// A point of `body` stays on an axis of `line_body` (1 equation). A body
/// restricted to x (the deck) can carry the point: its point moves with the
/// coordinate.
#[derive(Debug, Clone, PartialEq)]
pub struct PointOnLine {
    /// Body carrying the point.
    pub body: BodyId,
    /// The point, in the frame of `body` \[m\].
    pub point: [f64; 2],
    /// Body carrying the line (may be the ground).
    pub line_body: BodyId,
    /// A point of the line, in the frame of `line_body` \[m\].
    pub line_point: [f64; 2],
    /// Direction of the line, in the frame of `line_body`.
    pub line_direction: [f64; 2],
}

/// Weld: `body_a` is rigidly attached to `body_b` at the reference pose
/// (3 equations: point coincidence and relative angle).
#[derive(Debug, Clone, PartialEq)]
pub struct Weld {
    /// First body.
    pub body_a: BodyId,
    /// Reference point on `body_a`, in its frame \[m\].
    pub point_a: [f64; 2],
    /// Second body (may be the ground).
    pub body_b: BodyId,
    /// The coinciding point on `body_b`, in its frame \[m\].
    pub point_b: [f64; 2],
}

/// A coordinate prescribed as a function of time: `q(t) = f(t)` (1 equation).
#[derive(Debug, Clone, PartialEq)]
pub struct Driver {
    /// The driven body.
    pub body: BodyId,
    /// The driven coordinate (must be free).
    pub coord: Coord,
    /// The prescribed motion [m or rad].
    pub motion: TimeFunction,
}

/// A linear relation between coordinates of any number of bodies:
/// `sum_k c_k (q_k - q_k0) = 0`, with `q_k0` the coordinate in the bodies'
/// initial poses (1 equation). It ties a point of a linear structure given
/// by its modes to the modal coordinates (`u = sum_i phi_i eta_i`: the
/// point's coordinate with coefficient 1, each mode's with `-phi_i`), as
/// Exudyn's `CoordinateVectorConstraint` does; its multiplier is the force
/// on the coordinate of coefficient 1 [N or N m].
#[derive(Debug, Clone, PartialEq)]
pub struct Linear {
    /// `(body, coordinate, coefficient c_k)` of each term; every coordinate
    /// free, none twice; the coefficients \[-\] in the units that make the
    /// sum a length or an angle. The equation is paired, for the block
    /// elimination, with the first term's coordinate that no other equation
    /// has taken: put first a coordinate whose own mass is small (a point
    /// that only follows the others), so its block holds the equation.
    pub terms: Vec<(BodyId, Coord, f64)>,
}

/// Any constraint.
#[derive(Debug, Clone, PartialEq)]
pub enum Constraint {
    /// See [`Revolute`].
    Revolute(Revolute),
    /// See [`Prismatic`].
    Prismatic(Prismatic),
    /// See [`PointOnLine`].
    PointOnLine(PointOnLine),
    /// See [`Weld`].
    Weld(Weld),
    /// See [`Driver`].
    Driver(Driver),
    /// See [`Linear`].
    Linear(Linear),
}

impl Constraint {
    /// Number of scalar equations.
    pub fn equations(&self) -> usize {
        match self {
            Constraint::Revolute(_) | Constraint::Prismatic(_) => 2,
            Constraint::PointOnLine(_) | Constraint::Driver(_) | Constraint::Linear(_) => 1,
            Constraint::Weld(_) => 3,
        }
    }

    /// Short type name used in messages.
    pub fn kind(&self) -> &'static str {
        match self {
            Constraint::Revolute(_) => "revolute",
            Constraint::Prismatic(_) => "prismatic",
            Constraint::PointOnLine(_) => "point-on-line",
            Constraint::Weld(_) => "weld",
            Constraint::Driver(_) => "driver",
            Constraint::Linear(_) => "linear",
        }
    }

    /// The bodies involved (the ground for a driver's second; a linear
    /// constraint's in the order of its terms, each once).
    pub fn bodies(&self) -> Vec<BodyId> {
        match self {
            Constraint::Revolute(c) => vec![c.body_a, c.body_b],
            Constraint::Prismatic(c) => vec![c.slider, c.base],
            Constraint::PointOnLine(c) => vec![c.body, c.line_body],
            Constraint::Weld(c) => vec![c.body_a, c.body_b],
            Constraint::Driver(c) => vec![c.body, BodyId::GROUND],
            Constraint::Linear(c) => {
                let mut out: Vec<BodyId> = Vec::with_capacity(c.terms.len());
                for &(b, _, _) in &c.terms {
                    if !out.contains(&b) {
                        out.push(b);
                    }
                }
                out
            }
        }
    }
}
