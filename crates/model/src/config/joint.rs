//! The joint's part of a config (`[joint]`): its beams, bearings,
//! bushings, friction, contacts and movement capacity.

use serde::{Deserialize, Serialize};

/// The swivel-joist joint.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct JointConfig {
    /// Whether the joint is part of the model (false: the bridge alone, still
    /// integrated by the multibody solver).
    pub enabled: bool,
    /// Number of center beams `Nc` [-].
    pub center_beams: usize,
    /// Reference pitch of the center beams `s0` \[m\]; the gap is `(Nc + 1) s0`.
    pub pitch: f64,
    /// Center beams.
    pub center_beam: CenterBeamConfig,
    /// Support beams (mass and inertia; the list of positions is `support_beams`).
    pub support_beam: SupportBeamConfig,
    /// Bearings.
    pub bearing: BearingConfig,
    /// The support beams: guide(s) and swivel joists.
    pub support_beams: Vec<SupportBeam>,
    /// Bushing between each bearing and its center beam.
    pub bushing: BushingConfig,
    /// Sliding friction between each bearing and its support beam.
    pub friction: FrictionConfig,
    /// Contact between neighbouring beams when a sub-gap closes (pounding).
    pub contact: ContactConfig,
    /// Movement capacity of the joint.
    pub capacity: CapacityConfig,
    /// How the joint is modelled: `"detailed"` (every beam, bearing and
    /// contact; the default) or `"link"` (the calibrated macro-element of
    /// `[joint.link]`, docs/link.md).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<JointKind>,
    /// The link element (`joint.model = "link"`; `quakejoint calibrate`
    /// writes it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub link: Option<LinkConfig>,
    /// A seismic fuse (`[joint.fuse]`, docs/model.md "Seismic fuse"); none
    /// by default.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fuse: Option<super::FuseConfig>,
}

/// How the joint is modelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum JointKind {
    /// Every center beam, support beam, bearing and contact.
    #[default]
    Detailed,
    /// The calibrated link element of `[joint.link]`.
    Link,
}

/// The joint as one link element between the deck and the abutment along
/// the bridge (docs/link.md): a spring in series with a Coulomb slider,
/// a mass moving with the deck, and a gap that closes when every cell has
/// closed. Its closing movement and capacity follow from the joint's
/// geometry (`(Nc + 1) (pitch - center_beam.width)` and
/// `(Nc + 1) (capacity.max_subgap - pitch + center_beam.width)`).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LinkConfig {
    /// Stiffness of the stuck joint, deck to abutment \[N/m\].
    pub stiffness: f64,
    /// Force at which it slides (its friction) \[N\].
    pub friction: f64,
    /// The joint's mass that moves with the deck \[kg\].
    pub mass: f64,
    /// Stiffness of the closed joint (every cell closed) \[N/m\].
    pub gap_stiffness: f64,
    /// The closed joint as a Hertz law `F = k d^1.5` \[N/m^1.5\] with the
    /// joint's restitution (`joint.contact`), which quakejoint uses in
    /// place of the linear `gap_stiffness` (still required: the exports
    /// keep the linear law): the cells' contacts in series, `2 k_h / (Nc +
    /// 1)^1.5`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap_hertz: Option<f64>,
    /// Damper in parallel with the spring \[N s/m\] (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<f64>,
    /// Regularisation velocity of the slider [m/s] (default
    /// [`LINK_V_EPS`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v_eps: Option<f64>,
    /// How far the narrowest cell lags behind the cells' average while the
    /// joint closes (the detailed joint's beams rack and lag on their
    /// bushings) \[m\] (default 0: the cells alike). The first cell closes
    /// once the deck has closed the joint by `(Nc + 1) (g0 -
    /// racking_closing)`; the closed joint's force still waits for the
    /// whole gap.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub racking_closing: Option<f64>,
    /// How far the widest cell leads the cells' average while the joint
    /// opens \[m\] (default 0): the cells reach their capacity once the
    /// deck has opened the joint by `(Nc + 1) (max_subgap - g0 -
    /// racking_opening)`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub racking_opening: Option<f64>,
}

impl LinkConfig {
    /// The racking `[closing, opening]` \[m\] (0 where not given).
    pub fn racking(&self) -> [f64; 2] {
        [self.racking_closing.unwrap_or(0.0), self.racking_opening.unwrap_or(0.0)]
    }

    /// The slider's regularisation velocity [m/s].
    pub fn v_eps(&self) -> f64 {
        self.v_eps.unwrap_or(LINK_V_EPS)
    }
}

/// The link's slider regularisation velocity by default [m/s]: a stuck
/// slider creeps at most at this speed, 0.3 mm over a 30 s record, so that
/// it sticks as OpenSees' `ElasticPP` of the exports does (under Sylmar 360,
/// 0.086 g, the friction energy of the reference joint's link on a 1e6 kg
/// deck at 1 s: 3114 J at 1e-3 m/s, 2921 J at 1e-5 m/s, OpenSees 2910 J;
/// docs/link.md).
pub const LINK_V_EPS: f64 = 1e-5;

impl JointConfig {
    /// Whether the joint is the link element.
    pub fn is_link(&self) -> bool {
        self.model == Some(JointKind::Link)
    }

    /// The cells (sub-gaps) of the joint, `Nc + 1`.
    pub fn cells(&self) -> usize {
        self.center_beams + 1
    }

    /// The clear sub-gap at rest, `pitch - center_beam.width` \[m\].
    pub fn clear_subgap(&self) -> f64 {
        self.pitch - self.center_beam.width
    }
}

impl Default for JointConfig {
    fn default() -> Self {
        let mut support_beams = vec![SupportBeam { kind: SupportKind::Guide, y: -7.2, angle_deg: 0.0 }];
        // pivots at -5.6 + 1.4 j m (j = 0..8), written out so they are the decimal values
        let pivots = [-5.6, -4.2, -2.8, -1.4, 0.0, 1.4, 2.8, 4.2, 5.6];
        let angles = [-20.0, -17.0, -13.0, -13.0, 13.0, 13.0, 13.0, 17.0, 20.0];
        for (&y, &angle_deg) in pivots.iter().zip(&angles) {
            support_beams.push(SupportBeam { kind: SupportKind::Joist, y, angle_deg });
        }
        Self {
            enabled: true,
            center_beams: 27,
            pitch: 0.13,
            center_beam: CenterBeamConfig::default(),
            support_beam: SupportBeamConfig::default(),
            bearing: BearingConfig::default(),
            support_beams,
            bushing: BushingConfig::default(),
            friction: FrictionConfig::default(),
            contact: ContactConfig::default(),
            capacity: CapacityConfig::default(),
            model: None,
            link: None,
            fuse: None,
        }
    }
}

/// Center beam properties.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct CenterBeamConfig {
    /// Length along y, centred on y = 0 \[m\].
    pub length: f64,
    /// Width in x, used only for the clear sub-gaps \[m\].
    pub width: f64,
    /// Mass \[kg\].
    pub mass: f64,
    /// Moment of inertia about z [kg m^2]; default `mass * length^2 / 12`.
    pub inertia: Option<f64>,
}

impl CenterBeamConfig {
    /// The moment of inertia: given, or `mass * length^2 / 12` [kg m^2].
    pub fn inertia(&self) -> f64 {
        self.inertia.unwrap_or(self.mass * self.length * self.length / 12.0)
    }
}

impl Default for CenterBeamConfig {
    fn default() -> Self {
        Self { length: 15.0, width: 0.09, mass: 900.0, inertia: None }
    }
}

/// Support beam (guide and joist) properties.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct SupportBeamConfig {
    /// Length, for the default inertia only \[m\].
    pub length: f64,
    /// Mass \[kg\].
    pub mass: f64,
    /// Moment of inertia about z [kg m^2]; default `mass * length^2 / 12`.
    pub inertia: Option<f64>,
}

impl SupportBeamConfig {
    /// The moment of inertia: given, or `mass * length^2 / 12` [kg m^2].
    pub fn inertia(&self) -> f64 {
        self.inertia.unwrap_or(self.mass * self.length * self.length / 12.0)
    }
}

impl Default for SupportBeamConfig {
    fn default() -> Self {
        Self { length: 7.5, mass: 600.0, inertia: None }
    }
}

/// Bearing properties.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct BearingConfig {
    /// Mass \[kg\].
    pub mass: f64,
    /// Moment of inertia about z [kg m^2].
    pub inertia: f64,
}

impl Default for BearingConfig {
    fn default() -> Self {
        Self { mass: 20.0, inertia: 0.3 }
    }
}

/// A guide or a swivel joist.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SupportKind {
    /// Welded to the abutment; its bearings slide along it.
    Guide,
    /// Pivots on the abutment and slides through a joist box on the deck.
    Joist,
}

/// One support beam.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SupportBeam {
    /// Guide or joist.
    pub kind: SupportKind,
    /// Transverse position: of the guide's axis, or of a joist's pivot on the abutment \[m\].
    pub y: f64,
    /// Angle of the axis to the x axis, counter-clockwise \[deg\].
    #[serde(default)]
    pub angle_deg: f64,
}

/// Bushing between bearing and center beam.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct BushingConfig {
    /// Stiffness along the center beam's x axis [N/m].
    pub kx: f64,
    /// Stiffness along the center beam's y axis [N/m].
    pub ky: f64,
    /// Damping along x [N s/m].
    pub cx: f64,
    /// Damping along y [N s/m].
    pub cy: f64,
}

impl Default for BushingConfig {
    fn default() -> Self {
        Self { kx: 1.0e7, ky: 1.0e7, cx: 2.0e3, cy: 2.0e3 }
    }
}

/// Regularisation of the Coulomb law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LawConfig {
    /// `v / max(|v|, v_eps)`.
    #[default]
    Linear,
    /// `v / sqrt(|v|^2 + v_eps^2)`.
    Smooth,
}

/// Sliding friction of the bearings.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct FrictionConfig {
    /// Friction coefficient [-].
    pub mu: f64,
    /// Normal force per sliding surface (preload) \[N\].
    pub normal_force: f64,
    /// Sliding surfaces per bearing [-].
    pub surfaces: f64,
    /// Regularisation velocity [m/s].
    pub v_eps: f64,
    /// Regularised law.
    pub law: LawConfig,
}

impl Default for FrictionConfig {
    fn default() -> Self {
        Self { mu: 0.05, normal_force: 20.0e3, surfaces: 2.0, v_eps: 1.0e-3, law: LawConfig::Linear }
    }
}

/// The force law of the contact between beams.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactLawConfig {
    /// Hertz with Hunt-Crossley damping, `F = k delta^1.5 (1 + D delta')`.
    #[default]
    Hertz,
    /// Linear spring and dashpot (Anagnostopoulos), `F = k delta + c delta'`.
    Linear,
}

/// How the damping of the Hertz law follows from the restitution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum HertzDampingConfig {
    /// `D = 8 (1 - e) / (5 e v0)` (Ye, Li and Zhu 2009).
    #[default]
    YeLiZhu,
    /// `D = 3 (1 - e^2) / (4 v0)` (Lankarani and Nikravesh 1990).
    LankaraniNikravesh,
}

/// Hertz stiffness of the contact at one beam end by default [N/m^1.5]
/// (docs/model.md, "Pounding"): Muthukumar and DesRoches' value for bridge
/// decks, 2.75e10 N/m^1.5.
pub const DEFAULT_HERTZ_STIFFNESS: f64 = 2.75e10;
/// Linear stiffness of the contact at one beam end by default [N/m]: the
/// Hertz default's secant at 2.5 mm, `0.75 k_h sqrt(2.5 mm)`, rounded.
pub const DEFAULT_LINEAR_STIFFNESS: f64 = 1.0e9;

/// Contact between neighbouring beams (center beams, and the outer ones
/// with the edge beams of the abutment and the deck), at both ends of each
/// center beam, once a clear sub-gap closes.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct ContactConfig {
    /// Whether the beams touch (false: they pass through each other, and a
    /// closed sub-gap is flagged `collision`).
    pub enabled: bool,
    /// The force law.
    pub law: ContactLawConfig,
    /// Stiffness of the Hertz law at one beam end [N/m^1.5].
    pub hertz_stiffness: f64,
    /// Stiffness of the linear law at one beam end [N/m].
    pub linear_stiffness: f64,
    /// Coefficient of restitution of one impact [-].
    pub restitution: f64,
    /// How the Hertz law's damping follows from the restitution.
    pub damping: HertzDampingConfig,
    /// Deepest penetration the contact stands for \[m\]: deeper, the beams
    /// would be crushed, not touching, and the run is flagged.
    pub max_penetration: f64,
}

impl Default for ContactConfig {
    fn default() -> Self {
        Self {
            enabled: true,
            law: ContactLawConfig::Hertz,
            hertz_stiffness: DEFAULT_HERTZ_STIFFNESS,
            linear_stiffness: DEFAULT_LINEAR_STIFFNESS,
            restitution: 0.65,
            damping: HertzDampingConfig::YeLiZhu,
            max_penetration: 0.005,
        }
    }
}

/// Movement capacity of the joint.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct CapacityConfig {
    /// Largest clear opening of one sub-gap \[m\] (80 mm: the usual limit per
    /// cell of modular joints); the joint's range of opening is `(Nc + 1)`
    /// times it, less the clear sub-gaps at rest.
    pub max_subgap: f64,
}

impl Default for CapacityConfig {
    fn default() -> Self {
        Self { max_subgap: 0.08 }
    }
}
