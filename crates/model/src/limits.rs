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

/// Shortest and longest bridge period of the model \[s\]: the range of
/// design response spectra (Eurocode 8 to 4 s, ASCE 7 to 10 s) from a
/// stiff pier to a base-isolated deck.
pub const PERIOD_RANGE: (f64, f64) = (0.01, 10.0);

/// Every numeric key: name, unit (`1` for ratios and counts), admissible
/// range. `joint.support_beams[k].*` stands for every support beam.
///
/// The ranges span the modular expansion joints that are built and the
/// bridges that carry them, with a margin; their edges are where a value
/// in the wrong unit lands: a center-beam mass in tonnes (0.9), a preload
/// in kN (20), a regularisation velocity in mm/s (1), a damping ratio in
/// percent (5), a pitch in m written for mm.
pub const LIMITS: &[(&str, &str, Bound)] = &[
    ("joint.center_beams", "1", closed(1.0, 1000.0)),
    // a clear sub-gap of at most 80 mm plus a beam of up to 0.3 m
    ("joint.pitch", "m", closed(0.02, 1.0)),
    ("joint.center_beam.length", "m", closed(0.5, 100.0)),
    ("joint.center_beam.width", "m", below(0.0, 1.0)),
    // steel center beams weigh 20 to 300 kg per metre
    ("joint.center_beam.mass", "kg", closed(10.0, 1e5)),
    ("joint.center_beam.inertia", "kg m^2", above(0.0, 1e9)),
    ("joint.support_beam.length", "m", closed(0.5, 100.0)),
    ("joint.support_beam.mass", "kg", closed(10.0, 1e5)),
    ("joint.support_beam.inertia", "kg m^2", above(0.0, 1e9)),
    ("joint.bearing.mass", "kg", closed(0.1, 1000.0)),
    ("joint.bearing.inertia", "kg m^2", above(0.0, 1e4)),
    ("joint.support_beams[k].y", "m", closed(-1000.0, 1000.0)),
    ("joint.support_beams[k].angle_deg", "deg", open(-90.0, 90.0)),
    // a bushing without stiffness disconnects its center beam
    ("joint.bushing.kx", "N/m", closed(1e4, 1e11)),
    ("joint.bushing.ky", "N/m", closed(1e4, 1e11)),
    ("joint.bushing.cx", "N s/m", closed(0.0, 1e8)),
    ("joint.bushing.cy", "N s/m", closed(0.0, 1e8)),
    ("joint.friction.mu", "1", closed(0.0, 1.0)),
    // a preload of a few kN to some MN per surface (mu = 0 for no friction)
    ("joint.friction.normal_force", "N", closed(100.0, 1e7)),
    ("joint.friction.surfaces", "1", closed(1.0, 4.0)),
    // a regularisation velocity far below the sliding speeds (0.01 to 1 m/s)
    ("joint.friction.v_eps", "m/s", closed(1e-6, 0.01)),
    ("joint.contact.hertz_stiffness", "N/m^1.5", closed(1e7, 1e13)),
    ("joint.contact.linear_stiffness", "N/m", closed(1e5, 1e12)),
    ("joint.contact.restitution", "1", above(0.0, 1.0)),
    // a few times the penetration of the default contact at MN forces
    ("joint.contact.max_penetration", "m", closed(1e-4, 0.05)),
    ("joint.capacity.max_subgap", "m", closed(0.01, 1.0)),
    ("joint.fuse.break_force", "N", closed(1e3, 1e9)),
    ("joint.fuse.stroke", "m", closed(0.001, 2.0)),
    ("joint.fuse.beam", "1", closed(1.0, 1000.0)),
    ("joint.fuse.ramp_deg", "deg", below(0.0, 60.0)),
    ("joint.fuse.mu", "1", closed(0.0, 1.0)),
    ("joint.fuse.mass", "kg", above(0.0, 1e5)),
    ("joint.link.stiffness", "N/m", closed(1e3, 1e12)),
    ("joint.link.friction", "N", closed(0.0, 1e9)),
    ("joint.link.mass", "kg", above(0.0, 1e7)),
    ("joint.link.damping", "N s/m", closed(0.0, 1e9)),
    ("joint.link.gap_stiffness", "N/m", closed(1e3, 1e13)),
    ("joint.link.gap_hertz", "N/m^1.5", closed(1e3, 1e13)),
    ("joint.link.v_eps", "m/s", closed(1e-6, 0.01)),
    ("joint.link.racking_closing", "m", closed(0.0, 1.0)),
    ("joint.link.racking_opening", "m", closed(0.0, 1.0)),
    ("bridge.mass", "kg", closed(1e4, 1e10)),
    // 2 pi / 10 s to 2 pi / 0.01 s, rounded inwards (checked as a period)
    ("bridge.w0", "rad/s", closed(0.6284, 628.3)),
    ("bridge.period", "s", closed(PERIOD_RANGE.0, PERIOD_RANGE.1)),
    // bridges with added dampers reach about 0.3
    ("bridge.damping", "1", closed(0.0, 0.3)),
    // a bridge's periods a tenth to ten times those of its model
    ("bridge.modal.period_scale", "1", closed(0.1, 10.0)),
    ("bridge.transverse_period", "s", closed(PERIOD_RANGE.0, PERIOD_RANGE.1)),
    ("bridge.transverse_damping", "1", closed(0.0, 0.3)),
    ("bridge.far.mass", "kg", closed(1e4, 1e10)),
    ("bridge.far.period", "s", closed(PERIOD_RANGE.0, PERIOD_RANGE.1)),
    ("bridge.far.period_ratio", "1", closed(0.1, 10.0)),
    ("bridge.far.damping", "1", closed(0.0, 0.3)),
    ("simulation.extra_time", "s", closed(0.0, 86_400.0)),
    ("simulation.duration", "s", closed(1e-3, 86_400.0)),
    ("simulation.rtol", "1", closed(1e-12, 0.1)),
    ("simulation.atol", "m, m/s", closed(1e-15, 1.0)),
    ("simulation.atol_rotation", "rad, rad/s", closed(1e-15, 1.0)),
    // 1: the bearings held like every other body; already at 10 a pounding
    // run's contact energy drifts by 2e-3 (docs/performance.md)
    ("simulation.bearing_atol_factor", "1", closed(1.0, 100.0)),
    ("simulation.h_max", "s", closed(1e-9, 86_400.0)),
    ("simulation.max_wall_time", "s", above(0.0, 1e7)),
    ("simulation.max_steps", "1", closed(1.0, 1e12)),
    // the service case is quasi-static: movements of the deck, not shocks
    ("service.speed", "m/s", above(0.0, 1.0)),
    ("service.amplitude", "m", above(0.0, 2.0)),
    ("service.cycles", "1", closed(1.0, 1000.0)),
    ("service.blend", "s", above(0.0, 1e4)),
];

/// The unit and range of a key.
pub fn limit(key: &str) -> Option<(&'static str, Bound)> {
    LIMITS.iter().find(|(k, _, _)| *k == key).map(|&(_, u, b)| (u, b))
}
