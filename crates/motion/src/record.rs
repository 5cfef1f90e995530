//! Records ready for use ([`Record`]) and loading them from a
//! [`RecordSpec`] ([`load_record`], [`load_record_from_str`]).

use std::path::Path;

use crate::at2::parse_at2;
use crate::error::RecordError;
use crate::spec::{Format, RecordSpec, Units};
use crate::text::{parse_one_column, parse_two_column};

/// A record as parsed from a file, before unit conversion and scaling.
#[derive(Debug, Clone, PartialEq)]
pub struct RawRecord {
    /// time step \[s\]
    pub dt: f64,
    /// acceleration samples in the file's units
    pub values: Vec<f64>,
    /// header lines (AT2: the 4 header lines, trailing blanks removed; else empty)
    pub header: Vec<String>,
    /// time of the first sample \[s\] (two-column files only)
    pub first_time: Option<f64>,
    /// units stated in the header, if recognised (AT2 `UNITS OF G`)
    pub header_units: Option<Units>,
}

/// A record ready for use: uniform time step, acceleration in m/s² after
/// unit conversion and scaling.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// label (the spec's `name`, else the file stem)
    pub name: String,
    /// the path as given in the spec (`"(memory)"` for [`Record::new`])
    pub source: String,
    /// time step \[s\]
    pub dt: f64,
    /// ground acceleration [m/s²] at t = i·dt, i = 0..n
    pub acceleration: Vec<f64>,
    /// total factor [m/s² per file unit] from the numbers in the file to
    /// `acceleration` (unit conversion times scale)
    pub scale: f64,
    /// AT2 header lines, else empty
    pub header: Vec<String>,
}

impl Record {
    /// A record from samples [m/s²] at time step `dt` \[s\]. Errors if dt is
    /// not finite and > 0, if there are no samples or if a sample is not
    /// finite.
    pub fn new(name: impl Into<String>, dt: f64, acceleration: Vec<f64>) -> Result<Self, RecordError> {
        let name = name.into();
        validate(&name, dt, &acceleration)?;
        Ok(Record { name, source: "(memory)".into(), dt, acceleration, scale: 1.0, header: Vec::new() })
    }

    /// Peak ground acceleration max |a_i| [m/s²] (0 for an empty record).
    pub fn pga(&self) -> f64 {
        self.acceleration.iter().fold(0.0, |m, a| m.max(a.abs()))
    }

    /// Duration (n - 1)·dt \[s\] from the first to the last sample.
    pub fn duration(&self) -> f64 {
        self.acceleration.len().saturating_sub(1) as f64 * self.dt
    }

    /// Time of sample `i` \[s\] (i·dt).
    pub fn time(&self, i: usize) -> f64 {
        i as f64 * self.dt
    }
}

fn validate(name: &str, dt: f64, acceleration: &[f64]) -> Result<(), RecordError> {
    let invalid = |message: String| Err(RecordError::Invalid { name: name.into(), message });
    if !(dt.is_finite() && dt > 0.0) {
        return invalid(format!("time step dt = {dt} s must be finite and > 0"));
    }
    if acceleration.is_empty() {
        return invalid("the record has no samples".into());
    }
    if let Some(i) = acceleration.iter().position(|a| !a.is_finite()) {
        return invalid(format!("sample {i} (t = {} s) is {}, not a finite number", i as f64 * dt, acceleration[i]));
    }
    Ok(())
}

/// A loaded record and the warnings raised while reading it.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedRecord {
    /// the record
    pub record: Record,
    /// warnings, each naming the file (e.g. a record that does not start
    /// near zero)
    pub warnings: Vec<String>,
}

/// A record "does not start near zero" if |a\[0\]| exceeds this fraction of
/// its PGA (1 %); loading it raises a warning, not an error.
pub const START_WARNING_FRACTION: f64 = 0.01;

/// Read the file named by `spec` (a relative path is taken relative to
/// `base_dir`), convert units, scale, and check it.
pub fn load_record(spec: &RecordSpec, base_dir: &Path) -> Result<LoadedRecord, RecordError> {
    let file = spec.file.display().to_string();
    spec.validate()?;
    let path = spec.resolve_path(base_dir);
    let bytes = std::fs::read(&path).map_err(|source| RecordError::Io {
        file: if path == spec.file { file.clone() } else { format!("{file} ({})", path.display()) },
        source,
    })?;
    let text = String::from_utf8_lossy(&bytes);
    load_record_from_str(spec, &text)
}

/// As [`load_record`] with the file's text given (no IO): parse `text` as
/// the file named by `spec`.
pub fn load_record_from_str(spec: &RecordSpec, text: &str) -> Result<LoadedRecord, RecordError> {
    spec.validate()?;
    let file = spec.file.display().to_string();
    let raw = match spec.resolved_format() {
        Format::At2 => parse_at2(text, &file)?,
        Format::OneColumn => {
            // validate() guarantees dt for one-column files
            let dt = spec.dt.unwrap_or(f64::NAN);
            parse_one_column(text, &file, dt, spec.column)?
        }
        Format::TwoColumn | Format::Auto => parse_two_column(text, &file, spec.column.unwrap_or(2))?,
    };
    from_raw(spec, raw)
}

/// Unit conversion, scaling and warnings for a parsed record.
fn from_raw(spec: &RecordSpec, raw: RawRecord) -> Result<LoadedRecord, RecordError> {
    let file = spec.file.display().to_string();
    let name = spec.label();
    let units = spec.resolved_units();
    let mut warnings = Vec::new();
    if let (Some(header_units), Some(given)) = (raw.header_units, spec.units) {
        if header_units != given {
            // one of the two is wrong, and guessing which would scale the
            // whole spectrum by a constant factor: refuse
            return Err(RecordError::Spec {
                file,
                field: "units",
                message: format!(
                    "the file's header says units of {} but the spec says `{}`: remove `units` (the header is \
                     authoritative) or fix the file",
                    header_units.name(),
                    given.name()
                ),
            });
        }
    }
    if let Some(t0) = raw.first_time {
        if t0.abs() > 0.5 * raw.dt {
            warnings.push(format!(
                "{file}: the time column starts at t = {t0} s; times are counted from the first sample (t = 0)"
            ));
        }
    }
    let to_si = units.to_si();
    let factor = match spec.target_pga_g {
        Some(target) => {
            let pga_si = raw.values.iter().fold(0.0f64, |m, a| m.max(a.abs())) * to_si;
            if pga_si == 0.0 {
                return Err(RecordError::Spec {
                    file,
                    field: "target_pga_g",
                    message: "the record is zero everywhere; it cannot be scaled to a PGA".into(),
                });
            }
            target * crate::G / pga_si
        }
        None => spec.scale,
    };
    let scale = to_si * factor;
    let acceleration: Vec<f64> = raw.values.iter().map(|v| v * scale).collect();
    if let Some(i) = acceleration.iter().position(|a| !a.is_finite()) {
        return Err(RecordError::Invalid {
            name: file,
            message: format!("sample {i} overflows after scaling by {scale} (m/s² per file unit)"),
        });
    }
    let record = Record { name, source: file.clone(), dt: raw.dt, acceleration, scale, header: raw.header };
    validate(&file, record.dt, &record.acceleration)?;
    let pga = record.pga();
    let a0 = record.acceleration[0];
    if a0.abs() > START_WARNING_FRACTION * pga {
        warnings.push(format!(
            "{file}: the record does not start near zero: |a[0]| = {:.4e} m/s² is {:.2} % of PGA (threshold {} %); \
             the oscillator starts at rest with a_g(0) = a[0]",
            a0.abs(),
            100.0 * a0.abs() / pga,
            100.0 * START_WARNING_FRACTION
        ));
    }
    Ok(LoadedRecord { record, warnings })
}
