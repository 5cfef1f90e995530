//! Reading a `[sweep]` table's parts: numbers, lists and grids of the
//! swept axes (periods, damping ratios, a modal bridge's period scales),
//! what a case may not change, the suite's table, the warnings about a
//! suite's factors and a short run window, and the merging of a case's
//! overrides into the base config.

use super::*;

pub(super) fn sweep_err(field: &str, message: impl Into<String>) -> SweepError {
    SweepError::Config { field: field.to_string(), message: message.into() }
}

pub(super) fn f64_of(v: &toml::Value, field: &str) -> Result<f64, SweepError> {
    match v {
        toml::Value::Float(x) => Ok(*x),
        toml::Value::Integer(i) => Ok(*i as f64),
        other => Err(sweep_err(field, format!("expected a number, found {other}"))),
    }
}

pub(super) fn list_of_f64(v: &toml::Value, field: &str) -> Result<Vec<f64>, SweepError> {
    match v {
        toml::Value::Array(items) => items.iter().map(|x| f64_of(x, field)).collect(),
        other => Ok(vec![f64_of(other, field)?]),
    }
}

/// The key of a case's `[bridge]` table `b` that a case may not change,
/// and why (`modal`: the sweep's bridge is given by its modes).
pub(super) fn refused_in_case(b: &toml::Table, modal: bool) -> Option<(String, &'static str)> {
    let modal_table = b.get("modal").and_then(|m| m.as_table());
    if !modal {
        if b.contains_key("modal") {
            return Some((
                "modal".into(),
                "the sweep's bridge is a single-DOF deck; a case cannot give it modes (a sweep of a bridge given by \
                 its modes has [bridge.modal] in its base config)",
            ));
        }
        return ["w0", "period", "damping"]
            .into_iter()
            .find(|k| b.contains_key(*k))
            .map(|k| (k.to_string(), "the bridge period and damping are swept, not set per case"));
    }
    for k in ["w0", "period"] {
        if b.contains_key(k) {
            return Some((
                k.into(),
                "the bridge is given by its modes: its periods are the modes file's times sweep.period_scales",
            ));
        }
    }
    if b.contains_key("damping") {
        return Some((
            "damping".into(),
            "the modes' damping (the modes file's, or bridge.damping) is the sweep's damping axis, shared by its \
             cases: run one sweep per bridge.damping",
        ));
    }
    match modal_table {
        Some(m) if m.contains_key("modes") => Some((
            "modal.modes".into(),
            "the modes file is the sweep's bridge, shared by its cases (a case may keep fewer or more of its modes: \
             bridge.modal.modes_used)",
        )),
        Some(m) if m.contains_key("period_scale") => {
            Some(("modal.period_scale".into(), "the period scale is swept (sweep.period_scales), not set per case"))
        }
        _ => None,
    }
}

/// A swept axis: a list, or `{ from, to, count, spacing }` (`field`, in
/// `unit`), each value checked against the range of the config key `key`
/// it overrides, each once.
pub(super) fn grid_of(v: &toml::Value, field: &str, key: &str, unit: &str) -> Result<Vec<f64>, SweepError> {
    let values = match v {
        toml::Value::Table(t) => {
            for key in t.keys() {
                if !["from", "to", "count", "spacing"].contains(&key.as_str()) {
                    return Err(sweep_err(
                        &format!("{field}.{key}"),
                        "unknown key (expected from, to, count, spacing)",
                    ));
                }
            }
            let get = |k: &str| t.get(k).ok_or_else(|| sweep_err(&format!("{field}.{k}"), "missing"));
            let from = f64_of(get("from")?, &format!("{field}.from"))?;
            let to = f64_of(get("to")?, &format!("{field}.to"))?;
            let count = match get("count")? {
                toml::Value::Integer(n) if *n >= 1 => *n as usize,
                other => {
                    return Err(sweep_err(&format!("{field}.count"), format!("{other}: must be a whole number >= 1")))
                }
            };
            let log = match t.get("spacing").map(|s| s.as_str()) {
                None | Some(Some("log")) => true,
                Some(Some("linear")) => false,
                Some(other) => {
                    return Err(sweep_err(
                        &format!("{field}.spacing"),
                        format!("{other:?}: expected \"log\" or \"linear\""),
                    ))
                }
            };
            period_range(from, to, count, log).map_err(|e| match e {
                // (the range's words are about periods in s)
                quakejoint_motion::SpectrumError::Range(m) if unit != "s" => {
                    sweep_err(field, format!("range: {}", m.replace(" s", "").replace("periods", "values")))
                }
                other => sweep_err(field, other.to_string()),
            })?
        }
        other => list_of_f64(other, field)?,
    };
    if values.is_empty() {
        return Err(sweep_err(field, if unit == "s" { "no periods" } else { "no values" }));
    }
    check_swept(&values, field, key)?;
    Ok(values)
}

/// The swept axis of a bridge given by its modes (`sweep.period_scales`,
/// default the config's `bridge.modal.period_scale`, 1) and what the sweep
/// keeps of its modes file; `sweep.periods` and `sweep.damping` are
/// refused.
pub(super) fn modal_axis(
    sweep: &toml::Table,
    m: &ModalConfig,
    config: &Config,
    base_dir: &Path,
) -> Result<ModalSweep, SweepError> {
    if sweep.contains_key("periods") {
        return Err(sweep_err(
            "sweep.periods",
            "the bridge is given by its modes ([bridge.modal]): sweep its periods with sweep.period_scales, a \
             factor on every period of the modes (period_scales = [0.8, 1.0, 1.25], or { from, to, count, spacing })",
        ));
    }
    if sweep.contains_key("damping") {
        return Err(sweep_err(
            "sweep.damping",
            "the bridge is given by its modes ([bridge.modal]): their damping ratios are the modes file's, or \
             bridge.damping where it gives none, and are not swept; sweep the periods with sweep.period_scales (and \
             run one sweep per bridge.damping to study the damping)",
        ));
    }
    let swept = sweep.contains_key("period_scales");
    let period_scales = match sweep.get("period_scales") {
        Some(v) => {
            if let Some(f) = m.period_scale {
                return Err(sweep_err(
                    "bridge.modal.period_scale",
                    format!(
                        "{}: the sweep sets every job's period scale (sweep.period_scales); remove \
                         bridge.modal.period_scale, or sweep.period_scales to run the config's scale alone",
                        quakejoint_motion::number(f)
                    ),
                ));
            }
            grid_of(v, "sweep.period_scales", "bridge.modal.period_scale", "1")?
        }
        None => vec![m.scale()],
    };
    Ok(ModalSweep {
        period_scales,
        swept,
        file: m.modes.clone(),
        path: base_dir.join(&m.modes),
        sha256: quakejoint_model::modal::loaded(m)?.sha256.clone(),
        joints: config.joints.iter().skip(1).map(|j| j.name.clone()).collect(),
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

/// Reads `[sweep.suite]`, scales the suite's records to its target (in
/// place) and returns it. The records are fitted over the runs' window
/// (what the jobs see), and each scaled record is checked again against
/// the bound on a record's acceleration.
pub(super) fn suite_of(
    v: &toml::Value,
    periods: &[f64],
    records: &mut [SweepRecord],
    config: &Config,
) -> Result<Suite, SweepError> {
    let toml::Value::Table(t) = v else {
        return Err(sweep_err("sweep.suite", "must be a table ([sweep.suite])"));
    };
    for key in t.keys() {
        if !SUITE_KEYS.contains(&key.as_str()) {
            return Err(sweep_err(
                &format!("sweep.suite.{key}"),
                format!("unknown key (expected {})", SUITE_KEYS.join(", ")),
            ));
        }
    }
    let target: TargetSpectrum = t
        .get("target")
        .ok_or_else(|| {
            sweep_err("sweep.suite.target", "missing: the target spectrum (code = \"ec8\", \"asce7\" or \"table\")")
        })?
        .clone()
        .try_into()
        .map_err(|e: toml::de::Error| sweep_err("sweep.suite.target", e.message().to_string()))?;
    target.validate().map_err(|e| sweep_err("sweep.suite", e.to_string()))?;
    let (shortest, longest) = periods.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &p| (a.min(p), b.max(p)));
    let range = match t.get("range") {
        Some(v) => match list_of_f64(v, "sweep.suite.range")?[..] {
            [a, b] => (a, b),
            _ => return Err(sweep_err("sweep.suite.range", "two periods [from, to] in s")),
        },
        // Eurocode 8's 0.2 T1 to 2 T1 around every swept period
        None => ((0.2 * shortest).max(0.01), (2.0 * longest).min(10.0)),
    };
    let rule = match t.get("rule") {
        Some(v) => v.clone().try_into().map_err(|e: toml::de::Error| {
            sweep_err(
                "sweep.suite.rule",
                format!("{} (\"ec8\" scales the suite up to the rule, \"check\" only reports)", e.message()),
            )
        })?,
        None => SuiteRule::Ec8,
    };
    let windows: Vec<Record> = records.iter().map(|r| quakejoint_model::run::run_window(config, &r.record)).collect();
    let refs: Vec<&Record> = windows.iter().collect();
    let scaling = scale_suite(&refs, &target, range, rule).map_err(|e| sweep_err("sweep.suite", e.to_string()))?;
    let limit = MAX_ACCELERATION_G * G;
    for (r, f) in records.iter_mut().zip(&scaling.factors) {
        let rec = &mut r.record;
        rec.acceleration.iter_mut().for_each(|a| *a *= f);
        rec.scale *= f;
        rec.user_scale *= f;
        let peak = rec.pga();
        if peak > limit {
            return Err(sweep_err(
                "sweep.suite",
                format!(
                    "record {:?} scaled by {f:.3} peaks at {:.2} g, beyond {MAX_ACCELERATION_G} g: no recorded ground \
                     motion is that strong; leave the record out of the suite or choose a weaker target",
                    rec.name,
                    peak / G
                ),
            ));
        }
    }
    Ok(Suite { target, range, rule, scaling })
}

/// What the suite's scaling says a user should know.
pub(super) fn suite_warnings(suite: &Suite) -> Vec<String> {
    let s = &suite.scaling;
    let mut out: Vec<String> = s.warnings.iter().map(|w| format!("suite: {w}")).collect();
    if !s.ec8_satisfied {
        out.push(format!(
            "suite: the mean of the scaled records is {:.1} % of the target at T = {:.3} s, below the 90 % of \
             Eurocode 8 (rule = \"check\" reports it; rule = \"ec8\" scales the suite up)",
            100.0 * s.min_ratio.0,
            s.min_ratio.1
        ));
    }
    out
}

/// A warning when the run window ([`quakejoint_model::run::run_window`])
/// cuts `record` short: both spectra cover the window only, and how much
/// the spectrum without the joint over the whole record is larger says how
/// much of the record's effect the window leaves out (a bridge given by its
/// modes, `modal`: the bridge alone at the first joint's point at each
/// period scale).
pub(super) fn window_warning(
    config: &Config,
    record: &Record,
    periods: &[f64],
    damping: &[f64],
    modal: Option<&ModalSweep>,
) -> Option<String> {
    use quakejoint_motion::{spectrum, SpectrumOptions};
    let window = quakejoint_model::run::run_window(config, record);
    if window.acceleration.len() >= record.acceleration.len() {
        return None;
    }
    let (whole, cut, labels): (Vec<f64>, Vec<f64>, Vec<String>) = match modal {
        None => {
            let sa = |r: &Record| -> Vec<f64> {
                spectrum(r, periods, damping, SpectrumOptions::default())
                    .map(|rows| rows.iter().map(|row| row.peaks.sa).collect())
                    .unwrap_or_default()
            };
            let labels = (0..periods.len() * damping.len())
                .map(|i| format!("T = {:.4} s, damping {}", periods[i % periods.len()], damping[i / periods.len()]))
                .collect();
            (sa(record), sa(&window), labels)
        }
        Some(m) => {
            let at = |t: usize, r: &Record| {
                RunSpec::new(config.clone(), &m.overrides(t))
                    .and_then(|spec| modal_alone(&spec.config, r))
                    .map_or(f64::NAN, |alone| alone.sa)
            };
            let n = m.period_scales.len();
            let labels = (0..n)
                .map(|t| format!("period scale {}, longest period {:.4} s", m.period_scales[t], periods[t]))
                .collect();
            ((0..n).map(|t| at(t, record)).collect(), (0..n).map(|t| at(t, &window)).collect(), labels)
        }
    };
    let worst = whole
        .iter()
        .zip(&cut)
        .enumerate()
        .map(|(i, (w, c))| (i, if *c > 0.0 { w / c - 1.0 } else { 0.0 }))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    let missed = match worst {
        Some((i, excess)) if excess > 1e-3 => format!(
            "; over the whole record the bridge without the joint would respond up to {:.1} % more ({})",
            100.0 * excess,
            labels[i]
        ),
        _ => "; the record's remainder changes no peak of the spectrum without the joint".to_string(),
    };
    Some(format!(
        "record {}: the runs cover its first {} s of {} s (simulation.duration); both spectra, with and without \
          the joint, are taken over that window{missed}",
        record.name,
        quakejoint_motion::number(window.duration()),
        quakejoint_motion::number(record.duration())
    ))
}

/// Recursively merges `over` into `base` (tables merge, other values replace).
pub(super) fn merge(base: &mut toml::Table, over: &toml::Table) {
    for (k, v) in over {
        match (base.get_mut(k), v) {
            (Some(toml::Value::Table(b)), toml::Value::Table(o)) => merge(b, o),
            _ => {
                base.insert(k.clone(), v.clone());
            }
        }
    }
}

/// Settings that change no finished result are left out of the config's
/// hash: the per-job limits `simulation.max_wall_time` and
/// `simulation.max_steps` (a job either ends within them with the same
/// numbers or is recorded as stopped) and `sweep.checkpoint_seconds`. So a
/// sweep can be continued, and its stopped jobs retried, with raised limits.
/// `table` is the config or its `[sweep]` table (whose cases may set the
/// limits too).
pub(super) fn without_run_settings(table: &toml::Table) -> toml::Table {
    fn strip(t: &mut toml::Table) {
        if let Some(toml::Value::Table(sim)) = t.get_mut("simulation") {
            sim.remove("max_wall_time");
            sim.remove("max_steps");
            if sim.is_empty() {
                t.remove("simulation");
            }
        }
    }
    let mut t = table.clone();
    strip(&mut t);
    t.remove("checkpoint_seconds");
    if let Some(toml::Value::Array(cases)) = t.get_mut("cases") {
        for case in cases {
            if let toml::Value::Table(c) = case {
                strip(c);
            }
        }
    }
    t
}
