//! The system description: bodies, force elements, constraints and loads.

use super::body::{Body, BodyId};
use super::constraint::{Constraint, ConstraintId, Linear};
use super::force::{Excitation, ForceElement, ForceId};
use crate::error::BuildError;

/// A planar multibody system as the user describes it.
///
/// Body 0 is the ground. Elements refer to bodies by [`BodyId`]; the ids
/// returned by the `add_*` methods refer back to the elements.
#[derive(Debug, Clone, PartialEq)]
pub struct System {
    bodies: Vec<Body>,
    forces: Vec<(String, ForceElement)>,
    constraints: Vec<(String, Constraint)>,
    excitation: Excitation,
    /// Each body's group ([`System::set_group`]), [`NO_GROUP`] if none.
    groups: Vec<u32>,
    /// The group bodies join as they are added ([`System::add_to_group`]).
    adding_to: u32,
}

/// The group of a body in none ([`System::set_group`]).
pub const NO_GROUP: u32 = u32::MAX;

impl Default for System {
    fn default() -> Self {
        Self::new()
    }
}

impl System {
    /// An empty system holding only the ground.
    pub fn new() -> Self {
        let ground = Body {
            name: "ground".to_string(),
            mass: 0.0,
            inertia: 0.0,
            pose: [0.0; 3],
            velocity: [0.0; 3],
            free: [false; 3],
            tolerance_scale: 1.0,
            base_mass: None,
        };
        Self {
            bodies: vec![ground],
            forces: Vec::new(),
            constraints: Vec::new(),
            excitation: Excitation::default(),
            groups: vec![NO_GROUP],
            adding_to: NO_GROUP,
        }
    }

    /// Adds a body.
    pub fn add_body(&mut self, body: Body) -> BodyId {
        self.bodies.push(body);
        self.groups.push(self.adding_to);
        BodyId((self.bodies.len() - 1) as u32)
    }

    /// Puts `body` in `group` (a small number: 0, 1, ...): the friction an
    /// element dissipates and its peak forces are also reported per group,
    /// the group of its first body, else of its second
    /// ([`crate::Radau5::group_friction_energy`],
    /// [`crate::Assembly::force_extremes_by_group`]). A body is in no group
    /// unless put in one.
    pub fn set_group(&mut self, body: BodyId, group: u32) {
        if let Some(g) = self.groups.get_mut(body.index()) {
            *g = group;
        }
    }

    /// Puts the bodies added from now on in `group` (none: [`NO_GROUP`]),
    /// as [`System::set_group`] does one by one.
    pub fn add_to_group(&mut self, group: u32) {
        self.adding_to = group;
    }

    /// Each body's group, [`NO_GROUP`] if none (the ground first).
    pub fn groups(&self) -> &[u32] {
        &self.groups
    }

    /// Adds a force element named after its type and index.
    pub fn add_force(&mut self, element: ForceElement) -> ForceId {
        let name = format!("{} #{}", element.kind(), self.forces.len());
        self.add_force_named(name, element)
    }

    /// Adds a named force element.
    pub fn add_force_named(&mut self, name: impl Into<String>, element: ForceElement) -> ForceId {
        self.forces.push((name.into(), element));
        ForceId((self.forces.len() - 1) as u32)
    }

    /// A force element to change (a contact moved onto another base, in a
    /// system a run resumes in: [`crate::Radau5::resume`]).
    pub fn force_mut(&mut self, id: ForceId) -> &mut ForceElement {
        &mut self.forces[id.index()].1
    }

    /// Adds a constraint named after its type and index.
    pub fn add_constraint(&mut self, constraint: Constraint) -> ConstraintId {
        let name = format!("{} #{}", constraint.kind(), self.constraints.len());
        self.add_constraint_named(name, constraint)
    }

    /// Adds a named constraint.
    pub fn add_constraint_named(&mut self, name: impl Into<String>, constraint: Constraint) -> ConstraintId {
        self.constraints.push((name.into(), constraint));
        ConstraintId((self.constraints.len() - 1) as u32)
    }

    /// Sets gravity and base excitation.
    pub fn set_excitation(&mut self, excitation: Excitation) {
        self.excitation = excitation;
    }

    /// All bodies, the ground first.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// One body.
    pub fn body(&self, id: BodyId) -> &Body {
        &self.bodies[id.index()]
    }

    /// Mutable access to one body (to change its initial state, say).
    pub fn body_mut(&mut self, id: BodyId) -> &mut Body {
        &mut self.bodies[id.index()]
    }

    /// All force elements with their names.
    pub fn forces(&self) -> &[(String, ForceElement)] {
        &self.forces
    }

    /// All constraints with their names.
    pub fn constraints(&self) -> &[(String, Constraint)] {
        &self.constraints
    }

    /// The loads acting on every body.
    pub fn excitation(&self) -> &Excitation {
        &self.excitation
    }

    /// Number of bodies without the ground.
    pub fn body_count(&self) -> usize {
        self.bodies.len() - 1
    }

    /// Number of free coordinates.
    pub fn coordinate_count(&self) -> usize {
        self.bodies.iter().map(|b| b.free.iter().filter(|&&f| f).count()).sum()
    }

    /// Number of scalar constraint equations.
    pub fn equation_count(&self) -> usize {
        self.constraints.iter().map(|(_, c)| c.equations()).sum()
    }

    /// Checks every parameter and reference; called when the system is compiled.
    pub fn validate(&self) -> Result<(), BuildError> {
        for (i, b) in self.bodies.iter().enumerate().skip(1) {
            validate_body(i, b)?;
        }
        for (name, f) in &self.forces {
            self.validate_force(name, f)?;
        }
        for (name, c) in &self.constraints {
            self.validate_constraint(name, c)?;
        }
        let what = "excitation";
        for (name, v) in [("gravity x", self.excitation.gravity[0]), ("gravity y", self.excitation.gravity[1])] {
            finite(what, name, v)?;
        }
        if let Some(f) = &self.excitation.ground_x {
            f.validate("ground acceleration x")?;
        }
        if let Some(f) = &self.excitation.ground_y {
            f.validate("ground acceleration y")?;
        }
        Ok(())
    }

    fn check_body(&self, what: &str, id: BodyId) -> Result<(), BuildError> {
        if id.index() >= self.bodies.len() {
            return Err(BuildError::UnknownBody { what: what.to_string(), id: id.index(), count: self.bodies.len() });
        }
        Ok(())
    }

    fn check_pair(&self, what: &str, a: BodyId, b: BodyId) -> Result<(), BuildError> {
        self.check_body(what, a)?;
        self.check_body(what, b)?;
        if a == b {
            return Err(BuildError::SelfConnection {
                what: what.to_string(),
                body: self.bodies[a.index()].name.clone(),
            });
        }
        Ok(())
    }

    fn validate_force(&self, name: &str, f: &ForceElement) -> Result<(), BuildError> {
        let what = format!("{} \"{name}\"", f.kind());
        let (a, b) = f.bodies();
        match f {
            ForceElement::Bushing(e) => {
                self.check_pair(&what, a, b)?;
                for (n, v) in
                    [("kx", e.stiffness[0]), ("ky", e.stiffness[1]), ("cx", e.damping[0]), ("cy", e.damping[1])]
                {
                    non_negative(&what, n, v)?;
                }
                finite_all(&what, "point", &[e.point[0], e.point[1], e.frame_point[0], e.frame_point[1]])?;
                finite_all(&what, "rest", &e.rest)?;
            }
            ForceElement::Friction(e) => {
                self.check_pair(&what, a, b)?;
                non_negative(&what, "mu", e.mu)?;
                non_negative(&what, "normal_force", e.normal_force)?;
                non_negative(&what, "surfaces", e.surfaces)?;
                positive(&what, "v_eps", e.v_eps)?;
                finite_all(&what, "point", &e.point)?;
            }
            ForceElement::SpringDamper(e) => {
                self.check_pair(&what, a, b)?;
                non_negative(&what, "stiffness", e.stiffness)?;
                non_negative(&what, "damping", e.damping)?;
                non_negative(&what, "rest_length", e.rest_length)?;
                finite_all(&what, "point", &[e.point_a[0], e.point_a[1], e.point_b[0], e.point_b[1]])?;
            }
            ForceElement::CoordinateSpring(e) => {
                self.check_body(&what, e.body)?;
                non_negative(&what, "stiffness", e.stiffness)?;
                non_negative(&what, "damping", e.damping)?;
                finite(&what, "rest", e.rest)?;
                self.check_free(&what, e.body, e.coord.slot())?;
            }
            ForceElement::AppliedLoad(e) => {
                self.check_body(&what, e.body)?;
                finite_all(&what, "point", &e.point)?;
                e.fx.validate(&what)?;
                e.fy.validate(&what)?;
                e.torque.validate(&what)?;
            }
            ForceElement::Custom(_) => self.check_pair(&what, a, b)?,
            ForceElement::Contact(e) => {
                self.check_pair(&what, a, b)?;
                finite_all(&what, "point", &[e.point[0], e.point[1], e.edge_point[0], e.edge_point[1]])?;
                direction(&what, "edge_normal", e.edge_normal)?;
                let (k, r) = match e.law {
                    crate::model::force::ContactLaw::Linear { stiffness, restitution } => (stiffness, restitution),
                    crate::model::force::ContactLaw::Hertz { stiffness, restitution, .. } => (stiffness, restitution),
                };
                positive(&what, "stiffness", k)?;
                if let Some(m) = e.reduced_mass {
                    positive(&what, "reduced_mass", m)?;
                }
                if !(r > 0.0 && r <= 1.0) {
                    return Err(BuildError::InvalidParameter {
                        what,
                        name: "restitution",
                        value: r,
                        reason: "must be above 0 and at most 1",
                    });
                }
            }
        }
        Ok(())
    }

    fn check_free(&self, what: &str, body: BodyId, slot: usize) -> Result<(), BuildError> {
        let b = &self.bodies[body.index()];
        if body.is_ground() || !b.free[slot] {
            return Err(BuildError::NoFreeCoordinate {
                what: what.to_string(),
                detail: format!("coordinate {} of body \"{}\" is not free", ["x", "y", "phi"][slot], b.name),
            });
        }
        Ok(())
    }

    fn validate_constraint(&self, name: &str, c: &Constraint) -> Result<(), BuildError> {
        let what = format!("{} \"{name}\"", c.kind());
        let bodies = c.bodies();
        let (a, b) = (bodies[0], *bodies.get(1).unwrap_or(&BodyId::GROUND));
        match c {
            Constraint::Revolute(j) => {
                self.check_pair(&what, a, b)?;
                finite_all(&what, "point", &[j.point_a[0], j.point_a[1], j.point_b[0], j.point_b[1]])?;
            }
            Constraint::Weld(j) => {
                self.check_pair(&what, a, b)?;
                finite_all(&what, "point", &[j.point_a[0], j.point_a[1], j.point_b[0], j.point_b[1]])?;
            }
            Constraint::Prismatic(j) => {
                self.check_pair(&what, a, b)?;
                direction(&what, "axis_direction", j.axis_direction)?;
                finite_all(&what, "point", &[j.point[0], j.point[1], j.axis_point[0], j.axis_point[1]])?;
            }
            Constraint::PointOnLine(j) => {
                self.check_pair(&what, a, b)?;
                direction(&what, "line_direction", j.line_direction)?;
                finite_all(&what, "point", &[j.point[0], j.point[1], j.line_point[0], j.line_point[1]])?;
            }
            Constraint::Driver(d) => {
                self.check_body(&what, d.body)?;
                self.check_free(&what, d.body, d.coord.slot())?;
                d.motion.validate(&what)?;
            }
            Constraint::Linear(l) => self.validate_linear(&what, l)?,
        }
        Ok(())
    }

    fn validate_linear(&self, what: &str, l: &Linear) -> Result<(), BuildError> {
        if l.terms.is_empty() {
            return Err(BuildError::NoFreeCoordinate { what: what.to_string(), detail: "it has no terms".to_string() });
        }
        for (k, &(body, coord, c)) in l.terms.iter().enumerate() {
            self.check_body(what, body)?;
            self.check_free(what, body, coord.slot())?;
            finite(what, "coefficient", c)?;
            if l.terms[..k].iter().any(|&(b, s, _)| b == body && s == coord) {
                return Err(BuildError::InvalidParameter {
                    what: what.to_string(),
                    name: "terms",
                    value: k as f64,
                    reason: "a coordinate appears twice (term number given as the value)",
                });
            }
        }
        if l.terms.iter().all(|&(_, _, c)| c == 0.0) {
            return Err(BuildError::InvalidParameter {
                what: what.to_string(),
                name: "coefficient",
                value: 0.0,
                reason: "every coefficient is zero",
            });
        }
        Ok(())
    }
}

fn validate_body(index: usize, b: &Body) -> Result<(), BuildError> {
    let what = format!("body \"{}\" (#{index})", b.name);
    positive(&what, "mass", b.mass)?;
    if b.free[2] {
        positive(&what, "inertia", b.inertia)?;
    } else {
        non_negative(&what, "inertia", b.inertia)?;
    }
    finite_all(&what, "pose", &b.pose)?;
    finite_all(&what, "velocity", &b.velocity)?;
    positive(&what, "tolerance_scale", b.tolerance_scale)?;
    if let Some(m) = b.base_mass {
        finite_all(&what, "base_mass", &[m[0][0], m[0][1], m[1][0], m[1][1]])?;
    }
    for (slot, free) in b.free.iter().enumerate() {
        if !free && b.velocity[slot] != 0.0 {
            return Err(BuildError::InvalidParameter {
                what,
                name: ["velocity x", "velocity y", "velocity phi"][slot],
                value: b.velocity[slot],
                reason: "a locked coordinate cannot move",
            });
        }
    }
    Ok(())
}

fn finite(what: &str, name: &'static str, v: f64) -> Result<(), BuildError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(BuildError::InvalidParameter { what: what.to_string(), name, value: v, reason: "must be finite" })
    }
}

fn finite_all(what: &str, name: &'static str, vs: &[f64]) -> Result<(), BuildError> {
    vs.iter().try_for_each(|&v| finite(what, name, v))
}

fn positive(what: &str, name: &'static str, v: f64) -> Result<(), BuildError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(BuildError::InvalidParameter { what: what.to_string(), name, value: v, reason: "must be positive" })
    }
}

fn non_negative(what: &str, name: &'static str, v: f64) -> Result<(), BuildError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(BuildError::InvalidParameter { what: what.to_string(), name, value: v, reason: "must be zero or positive" })
    }
}

fn direction(what: &str, name: &'static str, d: [f64; 2]) -> Result<(), BuildError> {
    let n = d[0].hypot(d[1]);
    if n.is_finite() && n > 0.0 {
        Ok(())
    } else {
        Err(BuildError::InvalidParameter {
            what: what.to_string(),
            name,
            value: n,
            reason: "must be a non-zero direction",
        })
    }
}
