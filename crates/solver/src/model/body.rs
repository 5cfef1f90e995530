//! Planar rigid bodies.

/// Index of a body in a [`crate::System`]. The ground is [`BodyId::GROUND`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BodyId(pub(crate) u32);

impl BodyId {
    /// The ground (inertial frame, fixed at the origin).
    pub const GROUND: BodyId = BodyId(0);

    /// Position of the body in the system's body list (the ground is 0).
    pub fn index(self) -> usize {
        self.0 as usize
    }

    /// Whether this id is the ground.
    pub fn is_ground(self) -> bool {
        self.0 == 0
    }
}

/// One of the three planar coordinates of a body.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Coord {
    /// x of the centre of mass \[m\].
    X = 0,
    /// y of the centre of mass \[m\].
    Y = 1,
    /// Rotation about the vertical axis, counter-clockwise \[rad\].
    Phi = 2,
}

impl Coord {
    /// All three coordinates in storage order.
    pub const ALL: [Coord; 3] = [Coord::X, Coord::Y, Coord::Phi];

    /// Slot index 0, 1, 2.
    pub fn slot(self) -> usize {
        self as usize
    }

    /// Name used in messages.
    pub fn name(self) -> &'static str {
        match self {
            Coord::X => "x",
            Coord::Y => "y",
            Coord::Phi => "phi",
        }
    }
}

/// A planar rigid body: centre-of-mass coordinates (x, y, phi).
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Name used in messages and reports.
    pub name: String,
    /// Mass \[kg\].
    pub mass: f64,
    /// Moment of inertia about the vertical axis through the centre of mass [kg m^2].
    pub inertia: f64,
    /// Initial pose (x \[m\], y \[m\], phi \[rad\]).
    pub pose: [f64; 3],
    /// Initial velocity (vx [m/s], vy [m/s], omega [rad/s]).
    pub velocity: [f64; 3],
    /// Which of (x, y, phi) are free; a locked coordinate keeps its initial
    /// value and zero velocity (the bridge deck, for example, moves only in x).
    pub free: [bool; 3],
    /// Factor on the integrator's absolute tolerances for this body's
    /// coordinates and velocities [-] (1: the tolerances as given; 10: an
    /// error ten times larger passes the error test). RADAU5's per-component
    /// `ATOL` (Hairer and Wanner, IV.8), set per body: a light body whose
    /// own motion matters little, and which would otherwise set the step
    /// size by its number, can be held less tightly.
    pub tolerance_scale: f64,
    /// The masses the ground's acceleration acts through \[kg\]: the
    /// base-excitation load on the body's x and y (rows) is
    /// `-m_b[i][j] a_g[j]` from the ground's x and y (columns); none: the
    /// body's mass on the diagonal. A modal coordinate (in x) takes its
    /// participation factors `Gamma_x`, `Gamma_y = phi^T M r` in its first
    /// row (in the units of its coordinate); a body turned half a turn,
    /// `-m` on the diagonal.
    pub base_mass: Option<[[f64; 2]; 2]>,
}

impl Body {
    /// A body free in x, y and phi, at rest at `pose`.
    pub fn new(name: impl Into<String>, mass: f64, inertia: f64, pose: [f64; 3]) -> Self {
        Self {
            name: name.into(),
            mass,
            inertia,
            pose,
            velocity: [0.0; 3],
            free: [true; 3],
            tolerance_scale: 1.0,
            base_mass: None,
        }
    }

    /// Sets the factor on the absolute tolerances ([`Body::tolerance_scale`]).
    pub fn with_tolerance_scale(mut self, scale: f64) -> Self {
        self.tolerance_scale = scale;
        self
    }

    /// Sets the masses the ground's acceleration acts on ([`Body::base_mass`]).
    pub fn with_base_mass(mut self, base_mass: [[f64; 2]; 2]) -> Self {
        self.base_mass = Some(base_mass);
        self
    }

    /// Sets the initial velocity.
    pub fn with_velocity(mut self, velocity: [f64; 3]) -> Self {
        self.velocity = velocity;
        self
    }

    /// Restricts the body to the listed coordinates.
    pub fn only(mut self, coords: &[Coord]) -> Self {
        self.free = [false; 3];
        for c in coords {
            self.free[c.slot()] = true;
        }
        self
    }

    /// Mass associated with a coordinate slot (mass for x and y, inertia for phi).
    pub fn slot_mass(&self, slot: usize) -> f64 {
        if slot == 2 {
            self.inertia
        } else {
            self.mass
        }
    }
}
