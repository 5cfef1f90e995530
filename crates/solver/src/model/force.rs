//! Force elements as the user describes them. Their force laws and analytic
//! derivatives live in `assembly::forces`.

use std::fmt;
use std::sync::Arc;

use super::body::{BodyId, Coord};
use crate::timefn::TimeFunction;

/// Index of a force element in a [`crate::System`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ForceId(pub(crate) u32);

impl ForceId {
    /// Position in the system's force list.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Bushing between a point of `frame_body` and a point of `body`: translational
/// stiffness and damping resolved in the frame of `frame_body`, free rotation.
///
/// With `d = r_body + A(phi_body) point - r_frame - A(phi_frame) frame_point` and
/// `d_l = A(phi_frame)^T d - rest` (the deflection in the frame body's axes),
/// the elastic part derives from `V = 1/2 d_l^T diag(kx, ky) d_l` and the
/// damping force on `body` is `-A diag(cx, cy) A^T d'`.
#[derive(Debug, Clone, PartialEq)]
pub struct Bushing {
    /// Body whose axes resolve the stiffness (the center beam in the joint).
    pub frame_body: BodyId,
    /// Attachment point on `frame_body`, in its body frame [m].
    pub frame_point: [f64; 2],
    /// The other body.
    pub body: BodyId,
    /// Attachment point on `body`, in its body frame [m].
    pub point: [f64; 2],
    /// Stiffness (kx, ky) along the frame body's axes [N/m].
    pub stiffness: [f64; 2],
    /// Viscous damping (cx, cy) along the frame body's axes [N s/m].
    pub damping: [f64; 2],
    /// Deflection at which the bushing is unloaded, in the frame body's axes [m].
    pub rest: [f64; 2],
}

/// The regularisation of the Coulomb friction law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FrictionLaw {
    /// `F = -mu N v / max(|v|, v_eps)`: viscous below `v_eps`, Coulomb above.
    #[default]
    Linear,
    /// `F = -mu N v / sqrt(|v|^2 + v_eps^2)`: smooth everywhere.
    Smooth,
}

/// Regularised Coulomb friction between a point of `slider` and the material
/// point of `base` that coincides with it.
///
/// The relative velocity is that of the slider's point minus that of the base
/// body's material point at the same place. The force on the slider is
/// `-mu * surfaces * normal_force * phi(v_rel)` with `phi` from [`FrictionLaw`];
/// the reaction acts on `base` at the same point.
#[derive(Debug, Clone, PartialEq)]
pub struct Friction {
    /// The sliding body (the bearing).
    pub slider: BodyId,
    /// Contact point on the slider, in its frame [m].
    pub point: [f64; 2],
    /// The body it slides on (may be the ground).
    pub base: BodyId,
    /// Friction coefficient [-].
    pub mu: f64,
    /// Normal force per sliding surface [N].
    pub normal_force: f64,
    /// Number of sliding surfaces [-].
    pub surfaces: f64,
    /// Regularisation velocity [m/s].
    pub v_eps: f64,
    /// Regularised law.
    pub law: FrictionLaw,
}

impl Friction {
    /// Magnitude of the sliding force `mu * surfaces * normal_force` [N].
    pub fn sliding_force(&self) -> f64 {
        self.mu * self.surfaces * self.normal_force
    }
}

/// Spring and damper acting along the line between two points.
#[derive(Debug, Clone, PartialEq)]
pub struct SpringDamper {
    /// First body.
    pub body_a: BodyId,
    /// Point on the first body, in its frame [m].
    pub point_a: [f64; 2],
    /// Second body.
    pub body_b: BodyId,
    /// Point on the second body, in its frame [m].
    pub point_b: [f64; 2],
    /// Axial stiffness [N/m].
    pub stiffness: f64,
    /// Axial damping [N s/m].
    pub damping: f64,
    /// Unstretched length [m].
    pub rest_length: f64,
}

/// Spring and damper on one coordinate of a body, to the ground:
/// generalised force `-k (q - rest) - c q'`.
#[derive(Debug, Clone, PartialEq)]
pub struct CoordinateSpring {
    /// The body.
    pub body: BodyId,
    /// The coordinate (must be free).
    pub coord: Coord,
    /// Stiffness [N/m or N m/rad].
    pub stiffness: f64,
    /// Damping [N s/m or N m s/rad].
    pub damping: f64,
    /// Unstretched value of the coordinate [m or rad].
    pub rest: f64,
}

/// A force (fixed world direction) at a body point and a torque, given as
/// functions of time.
#[derive(Debug, Clone, PartialEq)]
pub struct AppliedLoad {
    /// The loaded body.
    pub body: BodyId,
    /// Point of application, in the body frame [m].
    pub point: [f64; 2],
    /// Force x component [N].
    pub fx: TimeFunction,
    /// Force y component [N].
    pub fy: TimeFunction,
    /// Torque [N m].
    pub torque: TimeFunction,
}

/// State of one body as seen by a [`CustomForce`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyState {
    /// Pose (x, y, phi).
    pub pose: [f64; 3],
    /// Velocity (vx, vy, omega).
    pub velocity: [f64; 3],
}

/// A force law supplied by the user without analytic derivatives; its
/// Jacobian is computed by finite differences.
pub trait CustomForce: Send + Sync {
    /// The two bodies it acts on (either may be the ground).
    fn bodies(&self) -> (BodyId, BodyId);
    /// Generalised forces (fx, fy, torque about the centre of mass) on the two
    /// bodies at time `t`.
    fn force(&self, t: f64, a: &BodyState, b: &BodyState) -> ([f64; 3], [f64; 3]);
}

/// A user force law, shared between systems.
#[derive(Clone)]
pub struct CustomElement(pub Arc<dyn CustomForce>);

impl fmt::Debug for CustomElement {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (a, b) = self.0.bodies();
        write!(f, "CustomElement({a:?}, {b:?})")
    }
}

impl PartialEq for CustomElement {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// Any force element.
#[derive(Debug, Clone, PartialEq)]
pub enum ForceElement {
    /// See [`Bushing`].
    Bushing(Bushing),
    /// See [`Friction`].
    Friction(Friction),
    /// See [`SpringDamper`].
    SpringDamper(SpringDamper),
    /// See [`CoordinateSpring`].
    CoordinateSpring(CoordinateSpring),
    /// See [`AppliedLoad`].
    AppliedLoad(AppliedLoad),
    /// See [`CustomForce`].
    Custom(CustomElement),
}

impl ForceElement {
    /// Short type name used in messages.
    pub fn kind(&self) -> &'static str {
        match self {
            ForceElement::Bushing(_) => "bushing",
            ForceElement::Friction(_) => "friction",
            ForceElement::SpringDamper(_) => "spring-damper",
            ForceElement::CoordinateSpring(_) => "coordinate spring",
            ForceElement::AppliedLoad(_) => "applied load",
            ForceElement::Custom(_) => "custom force",
        }
    }

    /// The bodies the element acts on.
    pub fn bodies(&self) -> (BodyId, BodyId) {
        match self {
            ForceElement::Bushing(e) => (e.frame_body, e.body),
            ForceElement::Friction(e) => (e.slider, e.base),
            ForceElement::SpringDamper(e) => (e.body_a, e.body_b),
            ForceElement::CoordinateSpring(e) => (e.body, BodyId::GROUND),
            ForceElement::AppliedLoad(e) => (e.body, BodyId::GROUND),
            ForceElement::Custom(e) => e.0.bodies(),
        }
    }
}

/// Loads acting on every body: gravity and uniform base excitation.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Excitation {
    /// Gravitational acceleration (x, y) [m/s^2]; in plan view usually zero.
    pub gravity: [f64; 2],
    /// Ground acceleration in x [m/s^2]: every body gets `-m a_gx(t)`.
    pub ground_x: Option<TimeFunction>,
    /// Ground acceleration in y [m/s^2]: every body gets `-m a_gy(t)`.
    pub ground_y: Option<TimeFunction>,
}
