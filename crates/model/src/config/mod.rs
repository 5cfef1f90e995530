//! The TOML configuration of a joint, its bridge, the record and the solver.
//!
//! Every parameter of the reference model (`docs/model.md`) has its default,
//! so a config only names what differs; unknown keys are an error. Values are
//! checked by [`Config::validate`] with messages naming the key.

use std::path::PathBuf;

use quakejoint_motion::RecordSpec;
use serde::{Deserialize, Serialize};

use crate::error::ModelError;

mod fuse;
mod joint;
pub mod modes;

pub use fuse::*;
pub use joint::*;

/// A whole config file.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
#[derive(Default)]
pub struct Config {
    /// The expansion joint.
    pub joint: JointConfig,
    /// The bridge (single-DOF oscillator).
    pub bridge: BridgeConfig,
    /// Ground acceleration along the bridge axis (x); default the built-in
    /// Corralitos 090 record ([`quakejoint_motion::builtin`]).
    pub record: Option<RecordSpec>,
    /// Optional ground acceleration across the bridge (y), acting on the joint bodies.
    pub record_y: Option<RecordSpec>,
    /// Run length and solver options.
    pub simulation: SimulationConfig,
    /// The service case (deck driven kinematically).
    pub service: ServiceConfig,
    /// A spectrum sweep (used by `quakejoint sweep`).
    pub sweep: Option<toml::Table>,
    /// Several joints on a bridge given by its modes (`[[joints]]`,
    /// docs/bridge.md): each placed at points of the modes file; empty: the
    /// one joint of `[joint]` at `bridge.modal.joint_point` (or on the
    /// single-DOF deck).
    // (left out of a config written back when empty: a single-DOF config's
    // text, and so its sweep's identity, are what they were before)
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub joints: Vec<PlacedJointConfig>,
}

/// Which side of a placed joint the deck is on, along the bridge.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
pub enum DeckSide {
    /// The deck lies toward +x of the joint's abutment side (a joint at the
    /// bridge's start: the deck moving +x opens it).
    #[serde(rename = "+x")]
    PlusX,
    /// The deck lies toward -x (a joint at the bridge's end): the joint is
    /// the same joint turned half a turn about the vertical.
    #[serde(rename = "-x")]
    MinusX,
}

impl DeckSide {
    /// +1 or -1: the joint's own x along the bridge's.
    pub fn sign(self) -> f64 {
        match self {
            DeckSide::PlusX => 1.0,
            DeckSide::MinusX => -1.0,
        }
    }
}

/// One joint of `[[joints]]`.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PlacedJointConfig {
    /// Its name in the results (unique).
    pub name: String,
    /// The point of the modes file (along x) its deck side moves with.
    pub deck_point: String,
    /// The point of the modes file (across, direction "y") its deck side
    /// moves with across the bridge; none: the deck end does not move across.
    pub deck_point_y: Option<String>,
    /// Which side of the joint the deck is on.
    pub deck_side: DeckSide,
    /// The point of the modes file its abutment side moves with (a joint
    /// at an in-span hinge between two frames); none: the ground.
    pub abutment_point: Option<String>,
    /// How much later the ground motion reaches this joint's abutment than
    /// the bridge's other supports \[s\], 0 to 10 (wave passage: the
    /// abutment moves along x as the ground did that long before); none:
    /// 0, one motion everywhere. Not with `abutment_point`.
    pub abutment_lag: Option<f64>,
    /// The joint (`[joints.joint]`, the keys of `[joint]`); none: `[joint]`.
    pub joint: Option<JointConfig>,
}

/// The bridge deck as a single-DOF oscillator in x.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct BridgeConfig {
    /// Deck mass \[kg\].
    pub mass: f64,
    /// Natural circular frequency [rad/s] (give this or `period`; default 6.3).
    pub w0: Option<f64>,
    /// Natural period \[s\] (give this or `w0`).
    pub period: Option<f64>,
    /// Damping ratio [-].
    pub damping: f64,
    /// Natural period across the bridge (y) \[s\]: the deck then has a
    /// transverse degree of freedom of its own; none: the deck does not
    /// move across.
    pub transverse_period: Option<f64>,
    /// Damping ratio across the bridge [-] (default `damping`).
    pub transverse_damping: Option<f64>,
    /// An adjacent bridge segment on the abutment side (`[bridge.far]`): the
    /// joint then sits between two decks; none: between the abutment and
    /// the deck.
    pub far: Option<FarSegmentConfig>,
    /// The bridge given by its modes (`[bridge.modal]`, docs/bridge.md):
    /// the deck's single DOF is then replaced by the modes, and `mass`,
    /// `period` and `w0` are not used (`damping` is the modes' damping
    /// where the modes file gives none).
    pub modal: Option<ModalConfig>,
}

/// A bridge given by its modes (`[bridge.modal]`).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ModalConfig {
    /// The modes file (relative to the config's folder; docs/bridge.md,
    /// "The modes file").
    pub modes: String,
    /// The point of the modes file the joint's deck side moves with (along
    /// x); required without `[[joints]]`, not with them.
    pub joint_point: Option<String>,
    /// The point of the modes file (direction "y") the joint's deck side
    /// moves with across the bridge; none: it does not move across.
    pub joint_point_y: Option<String>,
    /// How many modes a run keeps, the longest periods first (default: all).
    pub modes_used: Option<usize>,
    /// A factor on every period of the bridge [-] (stiffness scaled, masses
    /// kept; default 1).
    pub period_scale: Option<f64>,
    /// Correct for the modes left out by their static response at the
    /// joints' points (the modes file's `[static]` table; docs/bridge.md,
    /// "The static correction"; default false).
    pub static_correction: Option<bool>,
    /// The modes file, read with the config ([`Config::from_file`],
    /// [`Config::load_modes`]).
    #[serde(skip)]
    pub loaded: Option<std::sync::Arc<modes::ModalBridge>>,
}

impl ModalConfig {
    /// The period factor [-].
    pub fn scale(&self) -> f64 {
        self.period_scale.unwrap_or(1.0)
    }

    /// Whether the static correction is on.
    pub fn corrected(&self) -> bool {
        self.static_correction.unwrap_or(false)
    }
}

/// The adjacent segment the joint's abutment side rests on: a single-DOF
/// oscillator along the bridge under the same ground motion.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FarSegmentConfig {
    /// Deck mass \[kg\] (default the near deck's `bridge.mass`).
    pub mass: Option<f64>,
    /// Natural period \[s\] (give this or `period_ratio`).
    pub period: Option<f64>,
    /// Natural period as a multiple of the near deck's [-] (follows the
    /// swept period in a sweep).
    pub period_ratio: Option<f64>,
    /// Damping ratio [-] (default `bridge.damping`).
    pub damping: Option<f64>,
}

impl Default for BridgeConfig {
    fn default() -> Self {
        Self {
            mass: 1.0e8,
            w0: None,
            period: None,
            damping: 0.05,
            transverse_period: None,
            transverse_damping: None,
            far: None,
            modal: None,
        }
    }
}

impl BridgeConfig {
    /// Circular frequency [rad/s].
    pub fn omega(&self) -> f64 {
        match (self.w0, self.period) {
            (Some(w), _) => w,
            (None, Some(t)) => 2.0 * std::f64::consts::PI / t,
            (None, None) => 6.3,
        }
    }

    /// Natural period \[s\].
    pub fn natural_period(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.omega()
    }

    /// Mass \[kg\], circular frequency [rad/s] and damping ratio [-] of the
    /// adjacent segment, for the near deck at `omega` [rad/s].
    pub fn far_segment(&self, omega: f64) -> Option<(f64, f64, f64)> {
        self.far.as_ref().map(|f| {
            let w = match (f.period, f.period_ratio) {
                (Some(t), _) => 2.0 * std::f64::consts::PI / t,
                (None, Some(r)) => omega / r,
                (None, None) => omega,
            };
            (f.mass.unwrap_or(self.mass), w, f.damping.unwrap_or(self.damping))
        })
    }

    /// Circular frequency and damping ratio across the bridge, when the
    /// deck moves across ([rad/s], [-]).
    pub fn transverse(&self) -> Option<(f64, f64)> {
        self.transverse_period
            .map(|t| (2.0 * std::f64::consts::PI / t, self.transverse_damping.unwrap_or(self.damping)))
    }
}

/// Which sparse LU the solver uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LinearSolverConfig {
    /// Block elimination with faer fallback.
    #[default]
    Block,
    /// faer's sparse LU throughout.
    Faer,
}

/// Run length and solver options.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct SimulationConfig {
    /// Free vibration after the end of the record \[s\].
    pub extra_time: f64,
    /// Simulated duration \[s\]; default: the record's duration plus `extra_time`.
    pub duration: Option<f64>,
    /// Relative tolerance of the local error [-].
    pub rtol: f64,
    /// Absolute tolerance of translations \[m\] and translational velocities [m/s].
    pub atol: f64,
    /// Absolute tolerance of rotations \[rad\] and angular velocities [rad/s].
    pub atol_rotation: f64,
    /// Factor on `atol` for the bearings' positions and velocities [-]: the
    /// 20 kg sliders are most of the coordinates, so they set the step size
    /// by their number, while their own errors hardly reach the deck
    /// (docs/performance.md, "The bearings' tolerance").
    pub bearing_atol_factor: f64,
    /// Largest step \[s\].
    pub h_max: Option<f64>,
    /// Wall-clock limit of one run \[s\].
    pub max_wall_time: Option<f64>,
    /// Step limit of one run.
    pub max_steps: Option<u64>,
    /// Sparse LU of the iteration matrices.
    pub linear_solver: LinearSolverConfig,
    /// Use the coloured finite-difference Jacobian instead of the analytic one.
    pub finite_difference_jacobian: bool,
}

impl Default for SimulationConfig {
    fn default() -> Self {
        Self {
            extra_time: 0.0,
            duration: None,
            rtol: 1e-6,
            atol: 1e-6,
            atol_rotation: 1e-6,
            bearing_atol_factor: 2.0,
            h_max: None,
            max_wall_time: None,
            max_steps: None,
            linear_solver: LinearSolverConfig::Block,
            finite_difference_jacobian: false,
        }
    }
}

/// The service case: the deck opens and closes the joint at constant speed.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct ServiceConfig {
    /// Opening speed [m/s].
    pub speed: f64,
    /// Amplitude of the triangle wave (peak opening and closing) \[m\].
    pub amplitude: f64,
    /// Number of cycles [-].
    pub cycles: u32,
    /// Time over which each reversal is rounded (constant deceleration) \[s\].
    pub blend: f64,
}

impl Default for ServiceConfig {
    fn default() -> Self {
        Self { speed: 0.2, amplitude: 0.2, cycles: 2, blend: 0.1 }
    }
}

impl Config {
    /// Parses TOML text; `source` names the file in messages.
    pub fn from_toml(text: &str, source: &str) -> Result<Self, ModelError> {
        let config: Config = toml::from_str(text).map_err(|e| parse_error(source, &e))?;
        config.validate()?;
        Ok(config)
    }

    /// Reads and parses a config file, and the modes file it names.
    pub fn from_file(path: &std::path::Path) -> Result<Self, ModelError> {
        let text = quakejoint_motion::read_input_text(path, quakejoint_motion::MAX_CONFIG_BYTES)
            .map_err(|e| ModelError::Io { file: path.display().to_string(), message: e.to_string() })?;
        let mut config = Self::from_toml(&text, &path.display().to_string())?;
        config.load_modes(&base_dir(path))?;
        Ok(config)
    }

    /// The files the config reads besides itself (its records and the
    /// modes file), resolved against `base_dir`: what no output may
    /// overwrite.
    pub fn input_files(&self, base_dir: &std::path::Path) -> Vec<std::path::PathBuf> {
        let mut files: Vec<std::path::PathBuf> =
            self.record.iter().chain(&self.record_y).map(|r| r.resolve_path(base_dir)).collect();
        files.extend(self.bridge.modal.iter().map(|m| base_dir.join(&m.modes)));
        files
    }

    /// Reads the modes file of `[bridge.modal]` (relative to `base_dir`)
    /// and checks the config's modal keys against it.
    pub fn load_modes(&mut self, base_dir: &std::path::Path) -> Result<(), ModelError> {
        let Some(m) = &self.bridge.modal else { return Ok(()) };
        let path = base_dir.join(&m.modes);
        let bridge = modes::ModalBridge::read(&path).map_err(|e| match e {
            ModelError::Io { file, message } => ModelError::Invalid {
                field: "bridge.modal.modes".to_string(),
                value: format!("\"{}\"", m.modes),
                reason: format!("cannot read {file}: {message}"),
            },
            other => other,
        })?;
        self.attach_modes(std::sync::Arc::new(bridge))
    }

    /// Gives `[bridge.modal]` a modes file already read (the one a sweep's
    /// cases share) and checks the config's points against it.
    pub fn attach_modes(&mut self, bridge: std::sync::Arc<modes::ModalBridge>) -> Result<(), ModelError> {
        let Some(m) = &mut self.bridge.modal else { return Ok(()) };
        if let Some(p) = &m.joint_point {
            bridge.point(p, modes::Direction::X, "bridge.modal.joint_point")?;
        }
        if let Some(p) = &m.joint_point_y {
            bridge.point(p, modes::Direction::Y, "bridge.modal.joint_point_y")?;
        }
        for (k, j) in self.joints.iter().enumerate() {
            bridge.point(&j.deck_point, modes::Direction::X, &format!("joints[{k}].deck_point"))?;
            if let Some(p) = &j.deck_point_y {
                bridge.point(p, modes::Direction::Y, &format!("joints[{k}].deck_point_y"))?;
            }
            if let Some(a) = &j.abutment_point {
                bridge.point(a, modes::Direction::X, &format!("joints[{k}].abutment_point"))?;
            }
        }
        if m.corrected() && bridge.static_response.as_ref().is_none_or(|s| s.flexibility.is_empty()) {
            return Err(ModelError::Invalid {
                field: "bridge.modal.static_correction".to_string(),
                value: "true".to_string(),
                reason: format!(
                    "the modes file \"{}\" has no [static] table with flexibility and ground_x (docs/bridge.md, \"The \
                     static correction\")",
                    m.modes
                ),
            });
        }
        m.loaded = Some(bridge);
        Ok(())
    }

    /// Checks every value against its admissible range
    /// ([`crate::limits::LIMITS`]) and the values against each other.
    pub fn validate(&self) -> Result<(), ModelError> {
        if self.joint.enabled {
            check_joint(&self.joint)?;
        }
        self.check_bridge()?;
        check_simulation(&self.simulation)?;
        check_service(&self.service)
    }

    /// Checks `[bridge]`.
    fn check_bridge(&self) -> Result<(), ModelError> {
        let b = &self.bridge;
        check("bridge.mass", b.mass)?;
        match (b.w0, b.period) {
            (Some(_), Some(_)) => {
                return Err(ModelError::Invalid {
                    field: "bridge.period".to_string(),
                    value: b.period.unwrap_or_default().to_string(),
                    reason: "give either bridge.w0 or bridge.period, not both".to_string(),
                })
            }
            (Some(w), None) => {
                check("bridge.w0", w)?;
                let t = 2.0 * std::f64::consts::PI / w;
                let (lo, hi) = crate::limits::PERIOD_RANGE;
                if !(lo..=hi).contains(&t) {
                    return Err(invalid(
                        "bridge.w0",
                        w,
                        &format!("is a period of {} s, outside {lo} to {hi} s", quakejoint_motion::number(t)),
                    ));
                }
            }
            (None, Some(t)) => check("bridge.period", t)?,
            (None, None) => {}
        }
        check("bridge.damping", b.damping)?;
        if let Some(m) = &b.modal {
            check_modal(self, m)?;
        }
        if let Some(t) = b.transverse_period {
            check("bridge.transverse_period", t)?;
        }
        if let Some(z) = b.transverse_damping {
            check("bridge.transverse_damping", z)?;
            if b.transverse_period.is_none() {
                return Err(invalid(
                    "bridge.transverse_damping",
                    z,
                    "is for a deck that moves across: give bridge.transverse_period too",
                ));
            }
        }
        if let Some(f) = &b.far {
            for (key, v) in [
                ("bridge.far.mass", f.mass),
                ("bridge.far.period", f.period),
                ("bridge.far.period_ratio", f.period_ratio),
                ("bridge.far.damping", f.damping),
            ] {
                if let Some(v) = v {
                    check(key, v)?;
                }
            }
            if let (Some(_), Some(r)) = (f.period, f.period_ratio) {
                return Err(invalid(
                    "bridge.far.period_ratio",
                    r,
                    "give either bridge.far.period or period_ratio, not both",
                ));
            }
            if b.transverse_period.is_some() {
                return Err(invalid(
                    "bridge.transverse_period",
                    b.transverse_period.unwrap_or_default(),
                    "an adjacent segment ([bridge.far]) moves along the bridge only: a deck moving across between two \
                     segments is not modelled",
                ));
            }
        }
        Ok(())
    }

    /// The x record: the config's `[record]`, else the built-in default
    /// (Loma Prieta 1989, Corralitos 090, as the model description says).
    pub fn record_x(&self) -> RecordSpec {
        self.record.clone().unwrap_or_else(|| RecordSpec::new(quakejoint_motion::builtin::DEFAULT))
    }
}

/// Smallest inclination of a swivel joist to the bridge axis \[deg\]; built
/// joints incline them by 10 to 30 degrees.
pub const MIN_JOIST_ANGLE_DEG: f64 = 1.0;

/// A TOML error naming the file, with each quoted line of the input cut to
/// 200 characters.
pub fn parse_error(source: &str, e: &toml::de::Error) -> ModelError {
    let message = e.to_string().lines().map(|l| quakejoint_motion::excerpt(l, 200)).collect::<Vec<_>>().join("\n");
    ModelError::Parse { file: source.to_string(), message }
}

/// What a modal bridge does not (yet) combine with, and its own keys.
fn check_modal(config: &Config, m: &ModalConfig) -> Result<(), ModelError> {
    let b = &config.bridge;
    let refuse = |field: &str, what: &str| ModelError::Invalid {
        field: field.to_string(),
        value: "set".to_string(),
        reason: format!("{what} cannot be combined with [bridge.modal] (the modes give the whole bridge)"),
    };
    if b.transverse_period.is_some() {
        return Err(refuse("bridge.transverse_period", "a transverse deck DOF"));
    }
    if b.far.is_some() {
        return Err(refuse("bridge.far", "an adjacent single-DOF segment"));
    }
    match (&m.joint_point, config.joints.is_empty()) {
        (None, true) => {
            return Err(ModelError::Invalid {
                field: "bridge.modal.joint_point".to_string(),
                value: "missing".to_string(),
                reason: "say which point of the modes file the joint's deck side moves with (or place joints \
                         with [[joints]])"
                    .to_string(),
            })
        }
        (Some(p), false) => {
            return Err(ModelError::Invalid {
                field: "bridge.modal.joint_point".to_string(),
                value: format!("\"{p}\""),
                reason: "with [[joints]] each joint names its own deck_point".to_string(),
            })
        }
        _ => {}
    }
    if let Some(n) = m.modes_used {
        if n == 0 {
            return Err(invalid("bridge.modal.modes_used", 0.0, "keep at least one mode"));
        }
        if let Some(held) = m.loaded.as_ref().map(|b| b.modes.len()).filter(|&held| n > held) {
            return Err(invalid(
                "bridge.modal.modes_used",
                n as f64,
                &format!("the modes file {} holds {held} mode{}", m.modes, if held == 1 { "" } else { "s" }),
            ));
        }
    }
    if let Some(f) = m.period_scale {
        check("bridge.modal.period_scale", f)?;
    }
    for (k, j) in config.joints.iter().enumerate() {
        if j.name.trim().is_empty() || config.joints[..k].iter().any(|o| o.name == j.name) {
            return Err(ModelError::Invalid {
                field: format!("joints[{k}].name"),
                value: format!("\"{}\"", j.name),
                reason: "every joint needs a name of its own".to_string(),
            });
        }
        check_lag(k, j)?;
    }
    Ok(())
}

/// A joint's `abutment_lag`: from 0 to [`MAX_ABUTMENT_LAG`],
/// and only at an abutment.
fn check_lag(k: usize, j: &PlacedJointConfig) -> Result<(), ModelError> {
    let Some(lag) = j.abutment_lag else { return Ok(()) };
    let field = format!("joints[{k}].abutment_lag");
    let max = MAX_ABUTMENT_LAG;
    if lag.is_nan() || !(0.0..=max).contains(&lag) {
        return Err(invalid(
            &field,
            lag,
            &format!(
                "must be between 0 and {max} s: the time the ground motion reaches this abutment after the bridge's \
                 other supports (an abutment reached first would have to start displaced; give the bridge's \
                 record as the first support's and the lag to the later abutment)"
            ),
        ));
    }
    if lag != 0.0 && j.abutment_point.is_some() {
        return Err(invalid(
            &field,
            lag,
            "a joint at an in-span hinge (abutment_point) has no abutment of its own for the ground motion to reach",
        ));
    }
    Ok(())
}

/// The largest |`abutment_lag`| \[s\]: a wave crossing a bridge at 100 m/s
/// takes 1 s per 100 m; 10 s is a bridge of kilometres at the slowest
/// apparent speeds.
pub const MAX_ABUTMENT_LAG: f64 = 10.0;

/// A directory against which relative record paths are resolved.
pub fn base_dir(config_path: &std::path::Path) -> PathBuf {
    config_path.parent().map(|p| p.to_path_buf()).unwrap_or_default()
}

pub(crate) fn invalid(field: &str, value: f64, reason: &str) -> ModelError {
    ModelError::Invalid {
        field: field.to_string(),
        value: quakejoint_motion::number(value),
        reason: reason.to_string(),
    }
}

/// Checks `v` against the range of `key` in [`crate::limits::LIMITS`].
pub(crate) fn check(key: &str, v: f64) -> Result<(), ModelError> {
    check_as(key, key, v)
}

/// As [`check`], naming the value `field` (a support beam's index, say).
pub(crate) fn check_as(key: &str, field: &str, v: f64) -> Result<(), ModelError> {
    let Some((unit, bound)) = crate::limits::limit(key) else { return Ok(()) };
    if bound.contains(v) {
        return Ok(());
    }
    let unit = if unit == "1" { String::new() } else { format!(" {unit}") };
    Err(invalid(field, v, &format!("must be within {}{unit}", bound.describe())))
}

/// Checks an enabled `[joint]`.
fn check_joint(j: &JointConfig) -> Result<(), ModelError> {
    check("joint.center_beams", j.center_beams as f64)?;
    for (key, v) in [
        ("joint.pitch", j.pitch),
        ("joint.center_beam.length", j.center_beam.length),
        ("joint.center_beam.width", j.center_beam.width),
        ("joint.center_beam.mass", j.center_beam.mass),
        ("joint.center_beam.inertia", j.center_beam.inertia()),
        ("joint.support_beam.length", j.support_beam.length),
        ("joint.support_beam.mass", j.support_beam.mass),
        ("joint.support_beam.inertia", j.support_beam.inertia()),
        ("joint.bearing.mass", j.bearing.mass),
        ("joint.bearing.inertia", j.bearing.inertia),
        ("joint.bushing.kx", j.bushing.kx),
        ("joint.bushing.ky", j.bushing.ky),
        ("joint.bushing.cx", j.bushing.cx),
        ("joint.bushing.cy", j.bushing.cy),
        ("joint.friction.mu", j.friction.mu),
        ("joint.friction.normal_force", j.friction.normal_force),
        ("joint.friction.surfaces", j.friction.surfaces),
        ("joint.friction.v_eps", j.friction.v_eps),
        ("joint.contact.restitution", j.contact.restitution),
        ("joint.contact.max_penetration", j.contact.max_penetration),
        ("joint.capacity.max_subgap", j.capacity.max_subgap),
    ] {
        check(key, v)?;
    }
    if j.is_link() {
        check_link(j)?;
    }
    if let Some(f) = &j.fuse {
        fuse::check_fuse(j, f)?;
    }
    check("joint.contact.hertz_stiffness", j.contact.hertz_stiffness)?;
    check("joint.contact.linear_stiffness", j.contact.linear_stiffness)?;
    let clear = j.pitch - j.center_beam.width;
    if j.capacity.max_subgap <= clear {
        return Err(invalid(
            "joint.capacity.max_subgap",
            j.capacity.max_subgap,
            &format!(
                "must exceed the clear sub-gap at rest, joint.pitch - joint.center_beam.width = {} m",
                quakejoint_motion::number(clear)
            ),
        ));
    }
    if j.support_beams.is_empty() {
        return Err(invalid("joint.support_beams", 0.0, "the list of support beams is empty"));
    }
    if j.friction.surfaces.fract() != 0.0 {
        return Err(invalid("joint.friction.surfaces", j.friction.surfaces, "must be a whole number"));
    }
    check_support_beams(j)?;
    Ok(())
}

/// Checks `[joint.link]` of a joint modelled as a link element.
fn check_link(j: &JointConfig) -> Result<(), ModelError> {
    let Some(l) = &j.link else {
        return Err(ModelError::Invalid {
            field: "joint.link".to_string(),
            value: "none".to_string(),
            reason: "joint.model = \"link\" needs [joint.link] (stiffness, friction, mass, \
                         gap_stiffness): quakejoint calibrate writes it (docs/link.md)"
                .to_string(),
        });
    };
    for (key, v) in [
        ("joint.link.stiffness", l.stiffness),
        ("joint.link.friction", l.friction),
        ("joint.link.mass", l.mass),
        ("joint.link.gap_stiffness", l.gap_stiffness),
        ("joint.link.damping", l.damping.unwrap_or(0.0)),
        ("joint.link.gap_hertz", l.gap_hertz.unwrap_or(1e6)),
        ("joint.link.v_eps", l.v_eps()),
        ("joint.link.racking_closing", l.racking()[0]),
        ("joint.link.racking_opening", l.racking()[1]),
    ] {
        check(key, v)?;
    }
    if l.racking()[0] >= j.clear_subgap() {
        return Err(invalid(
            "joint.link.racking_closing",
            l.racking()[0],
            &format!("a cell would be closed at rest: it must stay below the clear sub-gap, {} m", j.clear_subgap()),
        ));
    }
    Ok(())
}

/// Checks `joint.support_beams`.
fn check_support_beams(j: &JointConfig) -> Result<(), ModelError> {
    for (k, sb) in j.support_beams.iter().enumerate() {
        check_as("joint.support_beams[k].y", &format!("joint.support_beams[{k}].y"), sb.y)?;
        let field = format!("joint.support_beams[{k}].angle_deg");
        check_as("joint.support_beams[k].angle_deg", &field, sb.angle_deg)?;
        if sb.kind == SupportKind::Joist && sb.angle_deg.abs() < MIN_JOIST_ANGLE_DEG {
            return Err(invalid(
                &field,
                sb.angle_deg,
                &format!(
                    "a swivel joist turns as the gap opens only if it is inclined: at least \
                     {MIN_JOIST_ANGLE_DEG} degrees either way (is the angle in radians? 13 degrees is \
                     0.227 rad)"
                ),
            ));
        }
    }
    Ok(())
}

/// Checks `[simulation]`.
fn check_simulation(s: &SimulationConfig) -> Result<(), ModelError> {
    check("simulation.extra_time", s.extra_time)?;
    for (key, v) in [
        ("simulation.duration", s.duration),
        ("simulation.h_max", s.h_max),
        ("simulation.max_wall_time", s.max_wall_time),
    ] {
        if let Some(v) = v {
            check(key, v)?;
        }
    }
    if let Some(n) = s.max_steps {
        check("simulation.max_steps", n as f64)?;
    }
    check("simulation.rtol", s.rtol)?;
    check("simulation.atol", s.atol)?;
    check("simulation.atol_rotation", s.atol_rotation)?;
    check("simulation.bearing_atol_factor", s.bearing_atol_factor)?;
    Ok(())
}

/// Checks `[service]`.
fn check_service(v: &ServiceConfig) -> Result<(), ModelError> {
    check("service.speed", v.speed)?;
    check("service.amplitude", v.amplitude)?;
    check("service.cycles", v.cycles as f64)?;
    check("service.blend", v.blend)?;
    if v.blend >= 2.0 * v.amplitude / v.speed {
        return Err(invalid("service.blend", v.blend, "must be shorter than one stroke (2 amplitude / speed)"));
    }
    Ok(())
}
