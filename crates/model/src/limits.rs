//! The admissible range and unit of every numeric config key: the single
//! source that [`crate::Config::validate`] checks against and that
//! `docs/config.md` is tested against (`crates/model/tests/config_reference.rs`).
//!
//! The ranges are physical, not numerical: they refuse values no bridge or
//! joint has (a 9e18 kg bearing, a preload of 1e300 N, a regularisation
//! velocity of 1e-300 m/s), which would otherwise end deep in the solver as
//! a non-finite number naming no field.

/// An interval of admissible values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bound {
    /// Lower end.
    pub min: f64,
    /// Whether `min` itself is admissible.
    pub min_inclusive: bool,
    /// Upper end.
    pub max: f64,
    /// Whether `max` itself is admissible.
    pub max_inclusive: bool,
}

/// `min <= x <= max`.
const fn closed(min: f64, max: f64) -> Bound {
    Bound { min, min_inclusive: true, max, max_inclusive: true }
}

/// `min < x <= max`.
const fn above(min: f64, max: f64) -> Bound {
    Bound { min, min_inclusive: false, max, max_inclusive: true }
}

/// `min <= x < max`.
const fn below(min: f64, max: f64) -> Bound {
    Bound { min, min_inclusive: true, max, max_inclusive: false }
}

/// `min < x < max`.
const fn open(min: f64, max: f64) -> Bound {
    Bound { min, min_inclusive: false, max, max_inclusive: false }
}

impl Bound {
    /// Whether `x` is finite and inside.
    pub fn contains(&self, x: f64) -> bool {
        x.is_finite()
            && (if self.min_inclusive { x >= self.min } else { x > self.min })
            && (if self.max_inclusive { x <= self.max } else { x < self.max })
    }

    /// The range in words: `0 < x <= 10`.
    pub fn describe(&self) -> String {
        let n = |x: f64| quakejoint_motion::number(x);
        format!(
            "{} {} x {} {}",
            n(self.min),
            if self.min_inclusive { "<=" } else { "<" },
            if self.max_inclusive { "<=" } else { "<" },
            n(self.max)
        )
    }
}

/// Every numeric key: name, unit (`1` for ratios and counts), admissible
/// range. `joint.support_beams[k].*` stands for every support beam.
pub const LIMITS: &[(&str, &str, Bound)] = &[
    ("joint.center_beams", "1", closed(1.0, 1000.0)),
    ("joint.pitch", "m", above(0.0, 10.0)),
    ("joint.center_beam.length", "m", above(0.0, 100.0)),
    ("joint.center_beam.width", "m", below(0.0, 10.0)),
    ("joint.center_beam.mass", "kg", above(0.0, 1e6)),
    ("joint.center_beam.inertia", "kg m^2", above(0.0, 1e9)),
    ("joint.support_beam.length", "m", above(0.0, 100.0)),
    ("joint.support_beam.mass", "kg", above(0.0, 1e6)),
    ("joint.support_beam.inertia", "kg m^2", above(0.0, 1e9)),
    ("joint.bearing.mass", "kg", above(0.0, 1e5)),
    ("joint.bearing.inertia", "kg m^2", above(0.0, 1e6)),
    ("joint.support_beams[k].y", "m", closed(-1000.0, 1000.0)),
    ("joint.support_beams[k].angle_deg", "deg", open(-90.0, 90.0)),
    ("joint.bushing.kx", "N/m", closed(0.0, 1e12)),
    ("joint.bushing.ky", "N/m", closed(0.0, 1e12)),
    ("joint.bushing.cx", "N s/m", closed(0.0, 1e9)),
    ("joint.bushing.cy", "N s/m", closed(0.0, 1e9)),
    ("joint.friction.mu", "1", closed(0.0, 2.0)),
    ("joint.friction.normal_force", "N", closed(0.0, 1e8)),
    ("joint.friction.surfaces", "1", closed(0.0, 100.0)),
    ("joint.friction.v_eps", "m/s", closed(1e-9, 1.0)),
    ("bridge.mass", "kg", above(0.0, 1e12)),
    ("bridge.w0", "rad/s", above(0.0, 1e4)),
    ("bridge.period", "s", closed(1e-3, 1e3)),
    ("bridge.damping", "1", below(0.0, 1.0)),
    ("simulation.extra_time", "s", closed(0.0, 86_400.0)),
    ("simulation.duration", "s", closed(1e-3, 86_400.0)),
    ("simulation.rtol", "1", closed(1e-12, 0.1)),
    ("simulation.atol", "m, m/s", closed(1e-15, 1.0)),
    ("simulation.atol_rotation", "rad, rad/s", closed(1e-15, 1.0)),
    ("simulation.h_max", "s", closed(1e-9, 86_400.0)),
    ("simulation.max_wall_time", "s", above(0.0, 1e7)),
    ("simulation.max_steps", "1", closed(1.0, 1e12)),
    ("service.speed", "m/s", above(0.0, 10.0)),
    ("service.amplitude", "m", above(0.0, 10.0)),
    ("service.cycles", "1", closed(1.0, 1000.0)),
    ("service.blend", "s", above(0.0, 1e4)),
];

/// The unit and range of a key.
pub fn limit(key: &str) -> Option<(&'static str, Bound)> {
    LIMITS.iter().find(|(k, _, _)| *k == key).map(|&(_, u, b)| (u, b))
}
