//! The modes file of a bridge given by its modes (docs/bridge.md, "The
//! modes file"): its format, read and checked with the config that names
//! it. What a run takes from it (the kept modes, the modal bodies, the
//! superposition) is the runtime's, in [`crate::modal`].

use std::path::Path;

use serde::Deserialize;

use crate::error::ModelError;

/// The format tag the file must carry.
pub const FORMAT: &str = "quakejoint-modes-1";

/// The shortest period of a mode \[s\] (100 kHz).
pub const MIN_PERIOD: f64 = 1e-5;

/// The largest magnitude of a shape value or a participation factor: their
/// squares and products must stay finite.
pub const MAX_MAGNITUDE: f64 = 1e100;

/// The most the modes' effective masses along x may add up to, over
/// `total_mass_x` [-] (the rest is round-off in the file's digits).
pub const MAX_MASS_RATIO: f64 = 1.01;

/// The range of `sum_i Gamma_i phi_i(p)` at a point a file is taken with
/// [-]: 1 with every mode, a file of the lower modes gives between about
/// 0.6 and 1.6 (the tip of a cantilever's first mode alone: 1.57), a point
/// that does not move 0; negated participations give -1, shapes twice
/// too large 4.
pub const MIN_RIGID_SUM: f64 = -0.2;
/// See [`MIN_RIGID_SUM`].
pub const MAX_RIGID_SUM: f64 = 2.5;

/// The share of `total_mass_x` [-] from which a file holds every mode of
/// its model (to its digits): then `sum_i Gamma_i phi_i(p)` is 1 at every
/// point along x, within [`COMPLETE_SUM_TOLERANCE`], whatever the masses
/// (the modes of a model span its motions, the ground's rigid one too).
pub const COMPLETE_MASS_RATIO: f64 = 0.99999;
/// See [`COMPLETE_MASS_RATIO`] [-].
pub const COMPLETE_SUM_TOLERANCE: f64 = 0.02;

/// A direction of a point's motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    /// Along the bridge.
    X,
    /// Across the bridge.
    Y,
}

/// A point of the bridge whose motion the file gives.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModalPoint {
    /// Its name, unique in the file (joints and outputs refer to it).
    pub name: String,
    /// The direction of the motion given.
    pub direction: Direction,
}

/// One mode.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Mode {
    /// Period \[s\].
    pub period: f64,
    /// Damping ratio [-]; none: the config's `bridge.damping`.
    pub damping: Option<f64>,
    /// Participation factor along x, `phi^T M r_x` \[kg^0.5\].
    pub participation_x: f64,
    /// Participation factor across, `phi^T M r_y` \[kg^0.5\].
    #[serde(default)]
    pub participation_y: f64,
    /// Mass-normalised shape at the points, in their order \[kg^-0.5\].
    pub shape: Vec<f64>,
}

/// The full model's static response at the points, for the correction of
/// the modes left out (residual flexibility).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StaticResponse {
    /// Displacement of each point (relative to the ground) under a
    /// ground acceleration of 1 m/s^2 along x, `-K^-1 M r_x` \[s^2\]
    /// (empty: not given).
    #[serde(default)]
    pub ground_x: Vec<f64>,
    /// Static flexibility between the points \[m/N\] (n x n).
    #[serde(default)]
    pub flexibility: Vec<Vec<f64>>,
}

/// The modes file.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModalBridge {
    /// Must be [`FORMAT`].
    pub format: String,
    /// Where the modes come from (free text).
    #[serde(default)]
    pub source: String,
    /// The mass a ground acceleration along x excites \[kg\]: with every
    /// mode the sum of `Gamma_x^2` (a check of the file).
    pub total_mass_x: Option<f64>,
    /// The points, in the order of the shapes' values.
    #[serde(rename = "point")]
    pub points: Vec<ModalPoint>,
    /// The modes.
    #[serde(rename = "mode")]
    pub modes: Vec<Mode>,
    /// The static response, for the correction of the modes left out.
    #[serde(rename = "static")]
    pub static_response: Option<StaticResponse>,
    /// SHA-256 of the file's bytes (hex; set by [`ModalBridge::read`],
    /// empty for text parsed with [`ModalBridge::parse`]): what a sweep's
    /// journal recognises the modes by.
    #[serde(skip)]
    pub sha256: String,
}

impl ModalBridge {
    /// Reads and checks a modes file.
    pub fn read(path: &Path) -> Result<Self, ModelError> {
        let file = path.display().to_string();
        let io = |message: String| ModelError::Io { file: file.clone(), message };
        // the bytes hashed are the bytes parsed
        let bytes =
            quakejoint_motion::read_input(path, quakejoint_motion::MAX_TABLE_BYTES).map_err(|e| io(e.to_string()))?;
        let text = String::from_utf8(bytes).map_err(|e| io(format!("not UTF-8 text: {e}")))?;
        let mut bridge = Self::parse(&text, &file)?;
        bridge.sha256 = quakejoint_motion::sha256_hex(text.as_bytes());
        Ok(bridge)
    }

    /// Parses and checks a modes file's text; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Self, ModelError> {
        let bridge: Self =
            toml::from_str(text).map_err(|e| ModelError::Parse { file: file.to_string(), message: e.to_string() })?;
        bridge.check(file)?;
        Ok(bridge)
    }

    fn check(&self, file: &str) -> Result<(), ModelError> {
        let bad = |field: String, value: String, reason: &str| ModelError::Invalid {
            field: format!("{file}: {field}"),
            value,
            reason: reason.to_string(),
        };
        if self.format != FORMAT {
            return Err(bad("format".into(), format!("\"{}\"", self.format), "must be \"quakejoint-modes-1\""));
        }
        if self.points.is_empty() {
            return Err(bad("point".into(), "[]".into(), "give at least one [[point]]"));
        }
        if self.modes.is_empty() {
            return Err(bad("mode".into(), "[]".into(), "give at least one [[mode]]"));
        }
        for (k, p) in self.points.iter().enumerate() {
            if p.name.trim().is_empty() {
                return Err(bad(format!("point[{k}].name"), "\"\"".into(), "must not be empty"));
            }
            if self.points[..k].iter().any(|q| q.name == p.name && q.direction == p.direction) {
                return Err(bad(
                    format!("point[{k}].name"),
                    format!("\"{}\"", p.name),
                    "appears twice in one direction",
                ));
            }
        }
        let n = self.points.len();
        for (i, m) in self.modes.iter().enumerate() {
            let f = |name: &str| format!("mode[{i}].{name}");
            if !(m.period.is_finite() && (MIN_PERIOD..=100.0).contains(&m.period)) {
                return Err(bad(
                    f("period"),
                    quakejoint_motion::number(m.period),
                    &format!(
                        "must be from {MIN_PERIOD:e} to 100 s (a mode above 100 kHz is none of a structure's: a unit \
                         or export error; leave such modes out of the file)"
                    ),
                ));
            }
            if let Some(z) = m.damping {
                if !(z.is_finite() && (0.0..1.0).contains(&z)) {
                    return Err(bad(f("damping"), quakejoint_motion::number(z), "must be at least 0 and below 1"));
                }
            }
            for (name, v) in [("participation_x", m.participation_x), ("participation_y", m.participation_y)] {
                if !v.is_finite() || v.abs() > MAX_MAGNITUDE {
                    return Err(bad(
                        f(name),
                        quakejoint_motion::number(v),
                        &format!("must be a finite number of at most {MAX_MAGNITUDE:e} in size [kg^0.5]"),
                    ));
                }
            }
            if m.shape.len() != n {
                return Err(bad(
                    f("shape"),
                    format!("{} values", m.shape.len()),
                    &format!("must have one value per [[point]] ({n})"),
                ));
            }
            if let Some(v) = m.shape.iter().find(|v| !v.is_finite() || v.abs() > MAX_MAGNITUDE) {
                return Err(bad(
                    f("shape"),
                    quakejoint_motion::number(*v),
                    &format!("must hold finite numbers of at most {MAX_MAGNITUDE:e} in size [kg^-0.5]"),
                ));
            }
        }
        if let Some(m) = self.total_mass_x {
            if !(m.is_finite() && m > 0.0) {
                return Err(bad("total_mass_x".into(), quakejoint_motion::number(m), "must be a positive mass [kg]"));
            }
        }
        self.check_normalisation(file)?;
        if let Some(s) = &self.static_response {
            if (!s.ground_x.is_empty() && s.ground_x.len() != n) || s.ground_x.iter().any(|v| !v.is_finite()) {
                return Err(bad(
                    "static.ground_x".into(),
                    format!("{} values", s.ground_x.len()),
                    &format!("must have one finite value per [[point]] ({n})"),
                ));
            }
            if !s.flexibility.is_empty()
                && (s.flexibility.len() != n
                    || s.flexibility.iter().any(|r| r.len() != n || r.iter().any(|v| !v.is_finite())))
            {
                return Err(bad(
                    "static.flexibility".into(),
                    format!("{} rows", s.flexibility.len()),
                    &format!("must be {n} x {n} finite values [m/N]"),
                ));
            }
            check_flexibility(&s.flexibility).map_err(|(field, value, reason)| bad(field, value, &reason))?;
        }
        Ok(())
    }

    /// The checks of the modes' normalisation and signs that need no
    /// model: the effective masses add up to at most `total_mass_x`, and
    /// at every point along x `sum_i Gamma_x,i phi_i(p)` (1 with every
    /// mode of the model, for a point that moves with the ground's
    /// displacement) lies between [`MIN_RIGID_SUM`] and [`MAX_RIGID_SUM`]:
    /// negated participations give -1, shapes not mass-normalised (times
    /// a) give a^2, and either doubles or halves the mass ratio.
    fn check_normalisation(&self, file: &str) -> Result<(), ModelError> {
        let bad = |field: &str, value: String, reason: String| ModelError::Invalid {
            field: format!("{file}: {field}"),
            value,
            reason,
        };
        let effective: f64 = self.modes.iter().map(|m| m.participation_x * m.participation_x).sum();
        if let Some(total) = self.total_mass_x {
            let ratio = effective / total;
            if ratio > MAX_MASS_RATIO {
                return Err(bad(
                    "total_mass_x",
                    format!("{total:e}"),
                    format!(
                        "the modes' effective masses along x add up to {effective:.6e} kg, {:.1} % of total_mass_x: \
                         more than all of it. Is total_mass_x in another unit (tonnes?), or are the shapes not \
                         mass-normalised (phi^T M phi = 1; docs/bridge.md, \"What the numbers are\")?",
                        100.0 * ratio
                    ),
                ));
            }
        }
        for (p, point) in self.points.iter().enumerate() {
            let gamma = |m: &Mode| if point.direction == Direction::X { m.participation_x } else { m.participation_y };
            if self.modes.iter().all(|m| gamma(m) == 0.0) {
                continue;
            }
            let sum: f64 = self.modes.iter().map(|m| gamma(m) * m.shape[p]).sum();
            if !(MIN_RIGID_SUM..=MAX_RIGID_SUM).contains(&sum) {
                let along = if point.direction == Direction::X { "x" } else { "y" };
                return Err(bad(
                    &format!("point[{p}]"),
                    format!("\"{}\"", point.name),
                    format!(
                        "sum over the modes of participation_{along} times shape there is {sum:.4}; with every mode \
                         of the model it is 1 (a point moving with the ground), and a file of the lower modes comes \
                         close: near -1 the participations have the opposite sign convention to the shapes (negate \
                         every participation), near a^2 the shapes are not mass-normalised (times a); \
                         docs/bridge.md, \"What the numbers are\""
                    ),
                ));
            }
            let complete = self.total_mass_x.is_some_and(|total| effective / total >= COMPLETE_MASS_RATIO);
            if complete && point.direction == Direction::X && (sum - 1.0).abs() > COMPLETE_SUM_TOLERANCE {
                return Err(bad(
                    &format!("point[{p}]"),
                    format!("\"{}\"", point.name),
                    format!(
                        "sum over the modes of participation_x times shape there is {sum:.4}; the modes hold \
                         {:.2} % of total_mass_x, every mode of the model, and then the sum is 1 at every point \
                         (within {COMPLETE_SUM_TOLERANCE}): the shapes or the participations are scaled (shapes \
                         not mass-normalised, times a, give a or a^2; negated participations -1); docs/bridge.md, \
                         \"What the numbers are\"",
                        100.0 * effective / self.total_mass_x.unwrap_or(f64::NAN)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// A warning when a joint moves across the bridge with the point `p`
    /// (direction y) while no mode has `participation_y`: the point may be
    /// the second DOF of a 2-D frame, which is vertical, not across.
    pub fn across_warning(&self, p: usize) -> Option<String> {
        self.modes.iter().all(|m| m.participation_y == 0.0).then(|| {
            format!(
                "\"{}\" is a point across the bridge (direction y), but no mode of the file has participation_y: is \
                 it the second DOF of a 2-D frame, which is vertical? quakejoint's y is horizontal, across the bridge \
                 (docs/bridge.md)",
                self.points[p].name
            )
        })
    }

    /// The index of the point `name` (along `direction`), or an error that
    /// names `field` and lists the file's points.
    pub fn point(&self, name: &str, direction: Direction, field: &str) -> Result<usize, ModelError> {
        self.points.iter().position(|p| p.name == name && p.direction == direction).ok_or_else(|| {
            let names: Vec<String> =
                self.points.iter().map(|p| format!("\"{}\" ({:?})", p.name, p.direction)).collect();
            ModelError::Invalid {
                field: field.to_string(),
                value: format!("\"{name}\""),
                reason: format!(
                    "the modes file has no such point along {}; its points: {}",
                    if direction == Direction::X { "x" } else { "y" },
                    names.join(", ")
                ),
            }
        })
    }
}

/// The `[static]` flexibility as a flexibility matrix must be: symmetric
/// (Maxwell's reciprocity), with positive diagonal, and positive
/// semi-definite (no load does negative work); the error names the entry
/// (field, value, reason).
fn check_flexibility(f: &[Vec<f64>]) -> Result<(), (String, String, String)> {
    let n = f.len();
    for (p, row) in f.iter().enumerate() {
        if row[p].is_nan() || row[p] <= 0.0 {
            return Err((
                format!("static.flexibility[{p}][{p}]"),
                quakejoint_motion::number(row[p]),
                "must be positive: a unit force at a point moves it along itself [m/N]".into(),
            ));
        }
    }
    for p in 0..n {
        for q in p + 1..n {
            let scale = (f[p][p] * f[q][q]).sqrt();
            if (f[p][q] - f[q][p]).abs() > 1e-6 * scale {
                return Err((
                    format!("static.flexibility[{p}][{q}]"),
                    format!("{:e} against [{q}][{p}] = {:e}", f[p][q], f[q][p]),
                    "must be symmetric (Maxwell's reciprocity): the displacement at one point under a unit force \
                     at the other is the same both ways"
                        .into(),
                ));
            }
        }
    }
    // Cholesky of the matrix scaled to a unit diagonal: a pivot below
    // -1e-9 is a load that does negative work
    let d: Vec<f64> = (0..n).map(|p| f[p][p].sqrt()).collect();
    let mut l = vec![vec![0.0; n]; n];
    for j in 0..n {
        let mut pivot = 1.0 - (0..j).map(|k| l[j][k] * l[j][k]).sum::<f64>();
        if pivot < -1e-9 {
            return Err((
                "static.flexibility".into(),
                format!("{n} x {n}"),
                format!("must be positive semi-definite (no load does negative work); it is not from row {j} on"),
            ));
        }
        pivot = pivot.max(0.0).sqrt();
        l[j][j] = pivot;
        for i in j + 1..n {
            let sym = 0.5 * (f[i][j] + f[j][i]) / (d[i] * d[j]);
            let v = sym - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>();
            l[i][j] = if pivot > 0.0 { v / pivot } else { 0.0 };
        }
    }
    Ok(())
}
