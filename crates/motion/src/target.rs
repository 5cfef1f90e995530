//! Target spectra of design codes, to scale a suite of records to
//! ([`crate::suite`]): the Eurocode 8 elastic response spectrum, the ASCE 7
//! design response spectrum, or a table.
//!
//! - Eurocode 8 (EN 1998-1:2004, 3.2.2.2, Table 3.2 for type 1 and Table 3.3
//!   for type 2): with the design ground acceleration `a_g` on ground type A
//!   (the importance factor included), the soil factor `S`, the corner
//!   periods `T_B`, `T_C`, `T_D` of the ground type and the damping
//!   correction `eta = sqrt(10 / (5 + xi[%])) >= 0.55` (equation 3.6):
//!   `Se = a_g S (1 + T/T_B (2.5 eta - 1))` up to `T_B`, `a_g S eta 2.5` up
//!   to `T_C`, `a_g S eta 2.5 T_C/T` up to `T_D`, and
//!   `a_g S eta 2.5 T_C T_D / T^2` beyond (the code defines the spectrum up
//!   to 4 s; the same branch is used past it).
//! - ASCE 7 (ASCE/SEI 7-16, 11.4.6): with `S_DS`, `S_D1` and `T_L`,
//!   `T_0 = 0.2 S_D1/S_DS`, `T_S = S_D1/S_DS`: `Sa = S_DS (0.4 + 0.6 T/T_0)`
//!   up to `T_0`, `S_DS` up to `T_S`, `S_D1/T` up to `T_L`, `S_D1 T_L/T^2`
//!   beyond; its damping is 5 %.
//! - A table of (period \[s\], Sa \[g\]) points, interpolated linearly in log-log
//!   between them and refused outside them.

use serde::{Deserialize, Serialize};

use crate::error::SpectrumError;
use crate::G;

/// The spectrum type of Eurocode 8 (type 1: larger, distant earthquakes,
/// surface-wave magnitude above 5.5; type 2: smaller, nearer ones), written
/// `type = 1` or `type = 2`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(try_from = "u8", into = "u8")]
pub enum Ec8Type {
    /// Type 1 (Table 3.2).
    One,
    /// Type 2 (Table 3.3).
    Two,
}

impl TryFrom<u8> for Ec8Type {
    type Error = String;

    fn try_from(v: u8) -> Result<Self, String> {
        match v {
            1 => Ok(Ec8Type::One),
            2 => Ok(Ec8Type::Two),
            _ => Err(format!("type = {v}: Eurocode 8 spectra are of type 1 or 2")),
        }
    }
}

impl From<Ec8Type> for u8 {
    fn from(t: Ec8Type) -> u8 {
        match t {
            Ec8Type::One => 1,
            Ec8Type::Two => 2,
        }
    }
}

/// A target spectrum, as a config's `target` gives it (`code = "ec8"`,
/// `"asce7"` or `"table"`).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(tag = "code", rename_all = "lowercase", deny_unknown_fields)]
pub enum TargetSpectrum {
    /// The Eurocode 8 horizontal elastic response spectrum.
    Ec8 {
        /// Spectrum type, 1 or 2.
        #[serde(rename = "type")]
        kind: Ec8Type,
        /// Ground type: "A" to "E".
        ground: String,
        /// Design ground acceleration on type A ground, `a_g = gamma_I a_gR` \[g\].
        ag_g: f64,
        /// Viscous damping ratio of the spectrum [-] (default 0.05).
        #[serde(default = "five_percent")]
        damping: f64,
    },
    /// The ASCE 7 design response spectrum (5 % damping).
    Asce7 {
        /// Design spectral acceleration at short periods `S_DS` \[g\].
        sds_g: f64,
        /// Design spectral acceleration at 1 s `S_D1` \[g\].
        sd1_g: f64,
        /// Long-period transition period `T_L` \[s\].
        tl: f64,
    },
    /// A table of `[period [s], Sa [g]]` points, periods increasing.
    Table {
        /// The points.
        points: Vec<[f64; 2]>,
        /// Damping ratio the table is for [-] (default 0.05).
        #[serde(default = "five_percent")]
        damping: f64,
    },
}

fn five_percent() -> f64 {
    0.05
}

/// Soil factor and corner periods `(S, T_B, T_C, T_D)` of Eurocode 8,
/// Tables 3.2 (type 1) and 3.3 (type 2).
pub fn ec8_parameters(kind: Ec8Type, ground: &str) -> Option<(f64, f64, f64, f64)> {
    let row = match (kind, ground) {
        (Ec8Type::One, "A") => (1.0, 0.15, 0.4, 2.0),
        (Ec8Type::One, "B") => (1.2, 0.15, 0.5, 2.0),
        (Ec8Type::One, "C") => (1.15, 0.20, 0.6, 2.0),
        (Ec8Type::One, "D") => (1.35, 0.20, 0.8, 2.0),
        (Ec8Type::One, "E") => (1.4, 0.15, 0.5, 2.0),
        (Ec8Type::Two, "A") => (1.0, 0.05, 0.25, 1.2),
        (Ec8Type::Two, "B") => (1.35, 0.05, 0.25, 1.2),
        (Ec8Type::Two, "C") => (1.5, 0.10, 0.25, 1.2),
        (Ec8Type::Two, "D") => (1.8, 0.10, 0.30, 1.2),
        (Ec8Type::Two, "E") => (1.6, 0.05, 0.25, 1.2),
        _ => return None,
    };
    Some(row)
}

fn invalid(field: &str, message: String) -> SpectrumError {
    SpectrumError::Target { field: field.to_string(), message }
}

impl TargetSpectrum {
    /// Checks the parameters (ranges, ground type, table order).
    pub fn validate(&self) -> Result<(), SpectrumError> {
        match self {
            TargetSpectrum::Ec8 { kind, ground, ag_g, damping } => {
                if ec8_parameters(*kind, ground).is_none() {
                    return Err(invalid("ground", format!("{ground:?}: Eurocode 8 ground types are A, B, C, D and E")));
                }
                if !(ag_g.is_finite() && *ag_g > 0.0 && *ag_g <= 2.0) {
                    return Err(invalid("ag_g", format!("{ag_g} g: must be within 0 < a_g <= 2 g")));
                }
                check_damping(*damping)
            }
            TargetSpectrum::Asce7 { sds_g, sd1_g, tl } => {
                for (name, v) in [("sds_g", sds_g), ("sd1_g", sd1_g)] {
                    if !(v.is_finite() && *v > 0.0 && *v <= 5.0) {
                        return Err(invalid(name, format!("{v} g: must be within 0 < x <= 5 g")));
                    }
                }
                if !(tl.is_finite() && *tl >= 1.0 && *tl <= 20.0) {
                    return Err(invalid("tl", format!("{tl} s: T_L must be within 1 to 20 s (ASCE 7 maps 4 to 16 s)")));
                }
                if sd1_g / sds_g >= *tl {
                    return Err(invalid(
                        "sd1_g",
                        format!(
                            "T_S = S_D1 / S_DS = {} s is not below T_L = {tl} s",
                            crate::text::number(sd1_g / sds_g)
                        ),
                    ));
                }
                Ok(())
            }
            TargetSpectrum::Table { points, damping } => {
                if points.len() < 2 {
                    return Err(invalid("points", "a table needs at least 2 points [period, Sa]".into()));
                }
                for (i, [t, sa]) in points.iter().enumerate() {
                    if !(t.is_finite() && *t > 0.0 && sa.is_finite() && *sa > 0.0 && *sa <= 10.0) {
                        return Err(invalid(
                            "points",
                            format!("point {i} [{t}, {sa}]: periods and Sa [g] must be positive (Sa at most 10 g)"),
                        ));
                    }
                    if i > 0 && *t <= points[i - 1][0] {
                        return Err(invalid("points", format!("point {i}: periods must increase ({t} s)")));
                    }
                }
                check_damping(*damping)
            }
        }
    }

    /// Damping ratio the spectrum is for [-].
    pub fn damping(&self) -> f64 {
        match self {
            TargetSpectrum::Ec8 { damping, .. } | TargetSpectrum::Table { damping, .. } => *damping,
            TargetSpectrum::Asce7 { .. } => 0.05,
        }
    }

    /// The periods \[s\] the spectrum is defined over.
    pub fn domain(&self) -> (f64, f64) {
        match self {
            TargetSpectrum::Table { points, .. } => {
                (points.first().map_or(f64::NAN, |p| p[0]), points.last().map_or(f64::NAN, |p| p[0]))
            }
            _ => (0.0, f64::INFINITY),
        }
    }

    /// Spectral acceleration [m/s^2] at period `t` \[s\] (the spectrum must be
    /// valid; NaN outside a table).
    pub fn sa(&self, t: f64) -> f64 {
        G * match self {
            TargetSpectrum::Ec8 { kind, ground, ag_g, damping } => {
                let (s, tb, tc, td) = ec8_parameters(*kind, ground).unwrap_or((f64::NAN, 1.0, 1.0, 1.0));
                let eta = (10.0 / (5.0 + 100.0 * damping)).sqrt().max(0.55);
                let plateau = ag_g * s * eta * 2.5;
                if t <= tb {
                    ag_g * s * (1.0 + t / tb * (2.5 * eta - 1.0))
                } else if t <= tc {
                    plateau
                } else if t <= td {
                    plateau * tc / t
                } else {
                    plateau * tc * td / (t * t)
                }
            }
            TargetSpectrum::Asce7 { sds_g, sd1_g, tl } => {
                let (t0, ts) = (0.2 * sd1_g / sds_g, sd1_g / sds_g);
                if t < t0 {
                    sds_g * (0.4 + 0.6 * t / t0)
                } else if t <= ts {
                    *sds_g
                } else if t <= *tl {
                    sd1_g / t
                } else {
                    sd1_g * tl / (t * t)
                }
            }
            TargetSpectrum::Table { points, .. } => {
                let Some(i) = points.windows(2).position(|w| w[0][0] <= t && t <= w[1][0]) else {
                    return f64::NAN;
                };
                let ([t0, s0], [t1, s1]) = (points[i], points[i + 1]);
                let x = (t / t0).ln() / (t1 / t0).ln();
                (s0.ln() + x * (s1 / s0).ln()).exp()
            }
        }
    }

    /// A one-line description (`EC8 type 1, ground C, a_g = 0.3 g, 5 %`).
    pub fn label(&self) -> String {
        match self {
            TargetSpectrum::Ec8 { kind, ground, ag_g, damping } => format!(
                "Eurocode 8 type {}, ground {ground}, a_g = {ag_g} g, {} % damping",
                if *kind == Ec8Type::One { 1 } else { 2 },
                percent(*damping)
            ),
            TargetSpectrum::Asce7 { sds_g, sd1_g, tl } => {
                format!("ASCE 7, S_DS = {sds_g} g, S_D1 = {sd1_g} g, T_L = {tl} s, 5 % damping")
            }
            TargetSpectrum::Table { points, damping } => {
                format!(
                    "table of {} point{}, {} % damping",
                    points.len(),
                    if points.len() == 1 { "" } else { "s" },
                    percent(*damping)
                )
            }
        }
    }
}

/// A damping ratio in percent without the float's last-digit noise (7, not
/// 7.000000000000001).
fn percent(ratio: f64) -> f64 {
    (ratio * 1e11).round() / 1e9
}

fn check_damping(damping: f64) -> Result<(), SpectrumError> {
    if !(damping.is_finite() && (0.0..=0.3).contains(&damping)) {
        return Err(invalid("damping", format!("{damping}: must be within 0 to 0.3")));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ec8(kind: Ec8Type, ground: &str, ag_g: f64, damping: f64) -> TargetSpectrum {
        TargetSpectrum::Ec8 { kind, ground: ground.into(), ag_g, damping }
    }

    /// Eurocode 8 type 1, ground C, a_g = 0.3 g, 5 %: S = 1.15, T_B = 0.2,
    /// T_C = 0.6, T_D = 2.0 s, eta = 1. By hand: Se(0) = 0.345 g, the
    /// plateau 0.8625 g, Se(T_C) = 0.8625 g, Se(1.2) = 0.43125 g, Se(T_D) =
    /// 0.25875 g, Se(4) = 0.8625 x 0.6 x 2 / 16 = 0.0646875 g.
    #[test]
    fn eurocode_8_type_1_ground_c_at_its_corners() {
        let s = ec8(Ec8Type::One, "C", 0.3, 0.05);
        for (t, expect) in [
            (0.0, 0.345),
            (0.1, 0.6037_5),
            (0.2, 0.8625),
            (0.6, 0.8625),
            (1.2, 0.43125),
            (2.0, 0.25875),
            (4.0, 0.064_687_5),
        ] {
            assert!((s.sa(t) / G - expect).abs() < 1e-12, "T = {t}: {} g, expected {expect} g", s.sa(t) / G);
        }
    }

    /// Type 2, ground D, a_g = 0.2 g, 10 % damping: S = 1.8, T_B = 0.1,
    /// T_C = 0.3, T_D = 1.2, eta = sqrt(10/15) = 0.81650; plateau
    /// 0.2 x 1.8 x 0.81650 x 2.5 = 0.73485 g.
    #[test]
    fn eurocode_8_type_2_with_damping_correction() {
        let s = ec8(Ec8Type::Two, "D", 0.2, 0.10);
        let eta = (10.0f64 / 15.0).sqrt();
        let plateau = 0.2 * 1.8 * eta * 2.5;
        assert!((s.sa(0.2) / G - plateau).abs() < 1e-12);
        assert!((s.sa(0.6) / G - plateau * 0.3 / 0.6).abs() < 1e-12);
        assert!((s.sa(2.4) / G - plateau * 0.3 * 1.2 / 5.76).abs() < 1e-12);
        // eta is bounded below by 0.55 (28 % damping would give 0.5505, 30 % 0.5345)
        let heavy = ec8(Ec8Type::Two, "D", 0.2, 0.30);
        assert!((heavy.sa(0.2) / G - 0.2 * 1.8 * 0.55 * 2.5).abs() < 1e-12);
    }

    /// ASCE 7 with S_DS = 1.0 g, S_D1 = 0.6 g, T_L = 8 s: T_0 = 0.12 s,
    /// T_S = 0.6 s. By hand: Sa(0) = 0.4 g, Sa(0.06) = 0.7 g, Sa(T_0..T_S) =
    /// 1.0 g, Sa(1.2) = 0.5 g, Sa(8) = 0.075 g, Sa(10) = 0.6 x 8 / 100 = 0.048 g.
    #[test]
    fn asce_7_at_its_corners() {
        let s = TargetSpectrum::Asce7 { sds_g: 1.0, sd1_g: 0.6, tl: 8.0 };
        for (t, expect) in [(0.0, 0.4), (0.06, 0.7), (0.12, 1.0), (0.6, 1.0), (1.2, 0.5), (8.0, 0.075), (10.0, 0.048)] {
            assert!((s.sa(t) / G - expect).abs() < 1e-12, "T = {t}: {} g, expected {expect} g", s.sa(t) / G);
        }
    }

    #[test]
    fn a_table_interpolates_in_log_log_and_refuses_outside() {
        let s = TargetSpectrum::Table { points: vec![[0.1, 1.0], [1.0, 0.1]], damping: 0.05 };
        assert!((s.sa(0.1) / G - 1.0).abs() < 1e-12 && (s.sa(1.0) / G - 0.1).abs() < 1e-12);
        // a straight line of slope -1 in log-log: Sa = 0.1 / T
        assert!((s.sa(0.5) / G - 0.2).abs() < 1e-12);
        assert!(s.sa(2.0).is_nan() && s.sa(0.05).is_nan());
    }

    #[test]
    fn bad_parameters_are_named() {
        let bad = [
            (ec8(Ec8Type::One, "F", 0.3, 0.05), "ground"),
            (ec8(Ec8Type::One, "C", -0.3, 0.05), "ag_g"),
            (ec8(Ec8Type::One, "C", 0.3, 0.5), "damping"),
            (TargetSpectrum::Asce7 { sds_g: 0.0, sd1_g: 0.6, tl: 8.0 }, "sds_g"),
            // T_S = 5 s beyond T_L = 4 s: a spectrum with a jump
            (TargetSpectrum::Asce7 { sds_g: 0.2, sd1_g: 1.0, tl: 4.0 }, "T_S"),
            (TargetSpectrum::Table { points: vec![[1.0, 0.1], [0.5, 0.2]], damping: 0.05 }, "points"),
        ];
        for (s, field) in bad {
            let e = s.validate().unwrap_err().to_string();
            assert!(e.contains(field), "{e}");
        }
    }
}
