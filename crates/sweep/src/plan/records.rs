//! The records of a sweep, each read and hashed ([`SweepRecord`]), and the
//! warning when the run window cuts a record short.

use std::path::{Path, PathBuf};

use quakejoint_model::runspec::RunSpec;
use quakejoint_model::Config;
use quakejoint_motion::{load_record, Record, RecordSpec};

use super::modal::ModalSweep;
use crate::error::SweepError;

/// A record of the sweep.
#[derive(Debug, Clone)]
pub struct SweepRecord {
    /// How it was specified.
    pub spec: RecordSpec,
    /// The record (m/s^2).
    pub record: Record,
    /// SHA-256 of the file's bytes (hex).
    pub sha256: String,
    /// Warnings from reading it.
    pub warnings: Vec<String>,
    /// The file it was read from (resolved against the config's folder).
    pub path: PathBuf,
}

impl SweepRecord {
    /// Reads a record and hashes its file.
    pub fn load(spec: RecordSpec, base_dir: &Path) -> Result<Self, SweepError> {
        let loaded = load_record(&spec, base_dir)?;
        let path = spec.resolve_path(base_dir);
        Ok(Self { sha256: loaded.sha256, record: loaded.record, warnings: loaded.warnings, spec, path })
    }
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
                RunSpec::new(config.clone(), &m.overrides(t)).map_or(f64::NAN, |spec| spec.scenario.alone(r, false).sa)
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
        // (to the microsecond: 1999 samples of 0.02 s are 39.980000000000004 s)
        quakejoint_motion::number((window.duration() * 1e6).round() / 1e6),
        quakejoint_motion::number((record.duration() * 1e6).round() / 1e6)
    ))
}
