//! Units named in a text file's column header: `time,acc_m_s2`,
//! `acc [g]`, `Beschleunigung [m/s2]`, `accel (cm/s^2)`, `acc_g`.
//!
//! A label is informal: the unit it names is never used on its own, only
//! checked against the spec's `units` (and suggested when `units` is
//! missing), through [`HeaderUnits::Label`].

use crate::spec::{HeaderUnits, Units};
use crate::text::excerpt;

/// The text inside the last `[...]` or `(...)` of `label`, if any.
fn bracketed(label: &str) -> Option<&str> {
    let (open, close) = match (label.rfind('['), label.rfind('(')) {
        (Some(b), Some(p)) if b > p => (b, ']'),
        (Some(b), None) => (b, ']'),
        (_, Some(p)) => (p, ')'),
        (None, None) => return None,
    };
    let inner = &label[open + 1..];
    Some(inner.split(close).next().unwrap_or(inner).trim())
}

/// `label` with `²` written `2` (`m/s²` is `m/s2`).
fn plain(label: &str) -> String {
    label.replace('²', "2")
}

/// Whether `inner` (the text in brackets) is meant as a unit at all: it
/// holds a `/` (`mm/s2`, `ft/s/s`) or a `^`/`2` power, so that
/// `acc (filtered)` is not taken for a unit.
fn looks_like_unit(inner: &str) -> bool {
    inner.contains('/') || inner.contains('^') || inner.ends_with('2')
}

/// What the column header `label` of the acceleration column says about
/// its units: [`HeaderUnits::Label`] if it names one `units` can be,
/// [`HeaderUnits::Unrecognised`] for a bracketed unit that is not one of
/// them (`acc [mm/s2]`), else [`HeaderUnits::NotInFormat`].
///
/// Read: the text in the last brackets (`acc [g]`, `accel (cm/s^2)`),
/// else the last 3, 2 or 1 `_`/space/`-` separated words joined by `/`
/// (`acc_m_s2` is `m/s2`, `acc_cm_s2` is `cm/s2`, `acc_g` is `g`), all
/// through [`Units::from_header`]. A lone `g` counts only after a word of
/// 3 letters or more (`acc_g`), not in `a_g` (the ground acceleration's
/// usual symbol).
pub(crate) fn label_units(label: &str) -> HeaderUnits {
    let text = plain(label.trim());
    let shown = excerpt(label.trim(), 60);
    if let Some(inner) = bracketed(&text) {
        return match Units::from_header(inner) {
            Some(units) => HeaderUnits::Label { units, label: shown },
            None if looks_like_unit(inner) => HeaderUnits::Unrecognised(excerpt(inner, 40)),
            None => HeaderUnits::NotInFormat,
        };
    }
    let words: Vec<&str> = text.split(['_', ' ', '-']).filter(|w| !w.is_empty()).collect();
    for k in [3usize, 2, 1] {
        if words.len() < k {
            continue;
        }
        let unit = words[words.len() - k..].join("/");
        let Some(units) = Units::from_header(&unit) else { continue };
        if k == 1 && units == Units::G {
            // `g` alone is a unit only after a quantity's name (`acc_g`)
            let before = words.len().checked_sub(2).map(|i| words[i]);
            if before.is_none_or(|w| w.chars().filter(|c| c.is_alphabetic()).count() < 3) {
                continue;
            }
        }
        return HeaderUnits::Label { units, label: shown };
    }
    HeaderUnits::NotInFormat
}

/// If the time column's header `label` names a unit other than seconds
/// (`time_ms`, `t [ms]`, `Zeit (min)`), that unit's name.
pub(crate) fn time_label_unit(label: &str) -> Option<&'static str> {
    let text = label.trim().to_ascii_lowercase();
    let unit = match bracketed(&text) {
        Some(inner) => inner.to_string(),
        None => text.split(['_', ' ', '-']).rfind(|w| !w.is_empty())?.to_string(),
    };
    match unit.as_str() {
        "ms" | "msec" | "msecs" | "millisec" | "millisecond" | "milliseconds" => Some("milliseconds"),
        "min" | "mins" | "minute" | "minutes" => Some("minutes"),
        "us" | "µs" | "microsecond" | "microseconds" => Some("microseconds"),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn units(label: &str) -> Option<Units> {
        match label_units(label) {
            HeaderUnits::Label { units, .. } => Some(units),
            _ => None,
        }
    }

    #[test]
    fn labels_naming_units() {
        for (label, want) in [
            ("acc_m_s2", Units::MetersPerSecond2),
            ("acc_cm_s2", Units::CentimetersPerSecond2),
            ("acc_g", Units::G),
            ("acc [g]", Units::G),
            ("Beschleunigung [m/s2]", Units::MetersPerSecond2),
            ("accel (cm/s^2)", Units::CentimetersPerSecond2),
            ("a [m/s²]", Units::MetersPerSecond2),
            ("acc_m_s_s", Units::MetersPerSecond2),
            ("accel-gal", Units::CentimetersPerSecond2),
            ("acc m/s2", Units::MetersPerSecond2),
        ] {
            assert_eq!(units(label), Some(want), "{label}");
        }
        for label in ["acc", "time", "Beschleunigung", "a_g", "g", "ag", "acc (filtered)", "accel_x"] {
            assert_eq!(label_units(label), HeaderUnits::NotInFormat, "{label}");
        }
        assert_eq!(label_units("acc [mm/s2]"), HeaderUnits::Unrecognised("mm/s2".into()));
    }

    #[test]
    fn time_labels() {
        assert_eq!(time_label_unit("time_ms"), Some("milliseconds"));
        assert_eq!(time_label_unit("t [ms]"), Some("milliseconds"));
        assert_eq!(time_label_unit("Zeit (min)"), Some("minutes"));
        for label in ["time", "t [s]", "time_s", "Zeit", "t (sec)"] {
            assert_eq!(time_label_unit(label), None, "{label}");
        }
    }
}
