//! The swept axes (`sweep.periods`, `sweep.period_scales`,
//! `sweep.damping`): a list, or `{ from, to, count, spacing }`, each value
//! checked against the range of the config key it overrides, each once.

use quakejoint_motion::period_range;

use super::{f64_of, list_of_f64, sweep_err};
use crate::error::SweepError;

/// A swept axis: a list, or `{ from, to, count, spacing }` (`field`, in
/// `unit`), each value checked against the range of the config key `key`
/// it overrides, each once.
pub(super) fn grid_of(v: &toml::Value, field: &str, key: &str, unit: &str) -> Result<Vec<f64>, SweepError> {
    let values = match v {
        toml::Value::Table(t) => range_of(t, field, unit)?,
        other => list_of_f64(other, field)?,
    };
    if values.is_empty() {
        return Err(sweep_err(field, if unit == "s" { "no periods" } else { "no values" }));
    }
    check_swept(&values, field, key)?;
    Ok(values)
}

/// `{ from, to, count, spacing = "log" or "linear" }` (`field`, in `unit`):
/// the values it spans.
pub(super) fn range_of(t: &toml::Table, field: &str, unit: &str) -> Result<Vec<f64>, SweepError> {
    super::known_keys(t, field, &["from", "to", "count", "spacing"])?;
    let get = |k: &str| t.get(k).ok_or_else(|| sweep_err(&format!("{field}.{k}"), "missing"));
    let from = f64_of(get("from")?, &format!("{field}.from"))?;
    let to = f64_of(get("to")?, &format!("{field}.to"))?;
    let count = match get("count")? {
        toml::Value::Integer(n) if *n >= 1 => *n as usize,
        other => return Err(sweep_err(&format!("{field}.count"), format!("{other}: must be a whole number >= 1"))),
    };
    let log = match t.get("spacing").map(|s| s.as_str()) {
        None | Some(Some("log")) => true,
        Some(Some("linear")) => false,
        Some(_) => {
            let shown = t.get("spacing").map_or(String::new(), |v| v.to_string());
            return Err(sweep_err(&format!("{field}.spacing"), format!("{shown}: expected \"log\" or \"linear\"")));
        }
    };
    period_range(from, to, count, log).map_err(|e| match e {
        // (the range's words are about periods in s)
        quakejoint_motion::SpectrumError::Range(m) if unit != "s" => {
            let unit = if unit.is_empty() { String::new() } else { format!(" {unit}") };
            sweep_err(field, format!("range: {}", m.replace(" s", &unit).replace("periods", "values")))
        }
        other => sweep_err(field, other.to_string()),
    })
}

/// Checks swept values (`field`, a list) against the range of the config
/// key `key` they stand for (as an override of it), each once.
pub(super) fn check_swept(values: &[f64], field: &str, key: &str) -> Result<(), SweepError> {
    for (i, &x) in values.iter().enumerate() {
        // as every front end's override of the key is checked, in the same words
        quakejoint_model::runspec::check_override(key, &format!("{field}[{i}]"), x)?;
        if let Some(k) = values[..i].iter().position(|&y| y == x) {
            return Err(sweep_err(
                &format!("{field}[{i}]"),
                format!("{x} is already {field}[{k}]: each is swept once"),
            ));
        }
    }
    Ok(())
}
