//! Force elements as the user describes them. Their force laws and analytic
//! derivatives live in `assembly::forces`, `assembly::friction` and
//! `assembly::contact`, each behind the assembly's `ForceKernel` trait.

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
    /// Attachment point on `frame_body`, in its body frame \[m\].
    pub frame_point: [f64; 2],
    /// The other body.
    pub body: BodyId,
    /// Attachment point on `body`, in its body frame \[m\].
    pub point: [f64; 2],
    /// Stiffness (kx, ky) along the frame body's axes [N/m].
    pub stiffness: [f64; 2],
    /// Viscous damping (cx, cy) along the frame body's axes [N s/m].
    pub damping: [f64; 2],
    /// Deflection at which the bushing is unloaded, in the frame body's axes \[m\].
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
    /// Contact point on the slider, in its frame \[m\].
    pub point: [f64; 2],
    /// The body it slides on (may be the ground).
    pub base: BodyId,
    /// Friction coefficient [-].
    pub mu: f64,
    /// Normal force per sliding surface \[N\].
    pub normal_force: f64,
    /// Number of sliding surfaces [-].
    pub surfaces: f64,
    /// Regularisation velocity [m/s].
    pub v_eps: f64,
    /// Regularised law.
    pub law: FrictionLaw,
}

impl Friction {
    /// Magnitude of the sliding force `mu * surfaces * normal_force` \[N\].
    pub fn sliding_force(&self) -> f64 {
        self.mu * self.surfaces * self.normal_force
    }
}

/// Smallest approach velocity entering the Hertz damping `D = f(e) / v0`
/// [m/s]: a grazing or quasi-static contact would otherwise get a damping
/// that outgrows its spring at the first mm/s of separation (`1 + D delta'`
/// changes sign at `delta' = -v0 / f`), and the law was derived for
/// impacts, not resting contact. Impacts slower than this restitute more
/// than the nominal `e` (as slow impacts do).
pub const MIN_APPROACH_SPEED: f64 = 0.05;

/// How the damping of a Hertz contact follows from the coefficient of
/// restitution `e` and the approach velocity `v0` at onset:
/// `F = k delta^1.5 (1 + D delta')` with `D = factor(e) / max(v0,`
/// [`MIN_APPROACH_SPEED`]`)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum HertzDamping {
    /// `D = 3 (1 - e^2) / (4 v0)`: H. M. Lankarani and P. E. Nikravesh, "A
    /// contact force model with hysteresis damping for impact analysis of
    /// multibody systems", J. Mech. Des. 112 (1990) 369-376; the form of the
    /// Hertz-damp model of S. Muthukumar and R. DesRoches, Earthquake Engng
    /// Struct. Dyn. 35 (2006) 811-828. Exact as `e -> 1`; gives too much
    /// restitution for the `e` of structural pounding (0.5 to 0.8).
    LankaraniNikravesh,
    /// `D = 8 (1 - e) / (5 e v0)`: K. Ye, L. Li and H. Zhu, "A note on the
    /// Hertz contact model with nonlinear damping for pounding simulation",
    /// Earthquake Engng Struct. Dyn. 38 (2009) 1135-1142 (derived for the
    /// restitution range of pounding).
    #[default]
    YeLiZhu,
}

impl HertzDamping {
    /// `v0 D` for a coefficient of restitution `e` [-].
    pub fn factor(self, e: f64) -> f64 {
        match self {
            HertzDamping::LankaraniNikravesh => 0.75 * (1.0 - e * e),
            HertzDamping::YeLiZhu => 1.6 * (1.0 - e) / e,
        }
    }
}

/// The force law of a [`Contact`] along its normal, `delta` the penetration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactLaw {
    /// Linear spring and dashpot (S. A. Anagnostopoulos, "Pounding of
    /// buildings in series during earthquakes", Earthquake Engng Struct.
    /// Dyn. 16 (1988) 443-456): `F = k delta + c delta'` with
    /// `c = 2 zeta sqrt(k m)`, `zeta = -ln e / sqrt(pi^2 + ln^2 e)`, `m` the
    /// reduced mass of the two bodies.
    Linear {
        /// Stiffness `k` [N/m].
        stiffness: f64,
        /// Coefficient of restitution `e`, 0 < e <= 1 [-].
        restitution: f64,
    },
    /// Hertz contact with nonlinear damping (Hunt-Crossley):
    /// `F = k delta^1.5 (1 + D delta')`, `D` from `e` and the approach
    /// velocity at onset ([`HertzDamping`]).
    Hertz {
        /// Stiffness `k` [N/m^1.5].
        stiffness: f64,
        /// Coefficient of restitution `e`, 0 < e <= 1 [-].
        restitution: f64,
        /// How `D` follows from `e`.
        damping: HertzDamping,
    },
}

/// Compliant unilateral contact of a point of `body` against a straight
/// edge of `base` (a line through `edge_point` with outward normal
/// `edge_normal`, both in the base's frame; the base may be the ground or a
/// body restricted to some coordinates). The penetration is
/// `delta = -n . (p - e)` with `p` the point and `e` the edge point in the
/// world, `n` the normal; while the contact is closed the force
/// `F(delta, delta')` of the [`ContactLaw`] pushes the point out along `n`
/// and the base back, at the point. The integrator closes the contact when
/// `delta` rises through zero and opens it when `delta` or `F` falls
/// through zero (no tension), each at an event located on the dense output:
/// no step crosses an onset or a release.
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    /// The body whose point touches the edge.
    pub body: BodyId,
    /// The contact point on `body`, in its frame \[m\].
    pub point: [f64; 2],
    /// The body carrying the edge.
    pub base: BodyId,
    /// A point of the edge, in the base's frame \[m\].
    pub edge_point: [f64; 2],
    /// Outward normal of the edge (toward the free side), in the base's
    /// frame [-] (normalised when compiled).
    pub edge_normal: [f64; 2],
    /// The force law.
    pub law: ContactLaw,
    /// The mass the law's restitution is set for \[kg\]; none: the reduced
    /// mass of the two bodies (the ground's counts as infinite). A body that
    /// stands for a point of a larger structure (a modal bridge's deck end)
    /// has a mass that is not the one the impact meets.
    pub reduced_mass: Option<f64>,
}

/// Spring and damper acting along the line between two points.
#[derive(Debug, Clone, PartialEq)]
pub struct SpringDamper {
    /// First body.
    pub body_a: BodyId,
    /// Point on the first body, in its frame \[m\].
    pub point_a: [f64; 2],
    /// Second body.
    pub body_b: BodyId,
    /// Point on the second body, in its frame \[m\].
    pub point_b: [f64; 2],
    /// Axial stiffness [N/m].
    pub stiffness: f64,
    /// Axial damping [N s/m].
    pub damping: f64,
    /// Unstretched length \[m\].
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
    /// Point of application, in the body frame \[m\].
    pub point: [f64; 2],
    /// Force x component \[N\].
    pub fx: TimeFunction,
    /// Force y component \[N\].
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
    /// See [`Contact`].
    Contact(Contact),
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
            ForceElement::Contact(_) => "contact",
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
            ForceElement::Contact(e) => (e.body, e.base),
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
