//! Records ready for use ([`Record`]) and loading them from a
//! [`RecordSpec`] ([`load_record`], [`load_record_from_str`]).

use std::path::Path;

use crate::at2::parse_at2;
use crate::error::RecordError;
use crate::formats::channel::Channel;
use crate::formats::{cosmos::parse_cosmos, csmip::parse_csmip, detect_format, esm::parse_esm, knet::parse_knet};
use crate::spec::{Format, HeaderUnits, RecordSpec, Units};
use crate::text::{parse_one_column, parse_sequence, parse_two_column};

/// A record as parsed from a file, before unit conversion and scaling.
#[derive(Debug, Clone, PartialEq)]
pub struct RawRecord {
    /// time step \[s\]
    pub dt: f64,
    /// acceleration samples in the file's units
    pub values: Vec<f64>,
    /// header lines, trailing blanks removed (AT2: the 4 header lines; ESM:
    /// the `KEY: value` lines; K-NET: up to `Memo.`; COSMOS: the text
    /// header; plain text: empty)
    pub header: Vec<String>,
    /// time of the first sample \[s\] (two-column files only)
    pub first_time: Option<f64>,
    /// what the file says about its units (AT2 header line 3, ESM `UNITS`,
    /// K-NET scale factor, COSMOS units code, a text column header)
    pub header_units: HeaderUnits,
    /// what the reader found worth saying (a K-NET mean removed, a header
    /// peak that disagrees with the data, ...), each starting with the
    /// file's name
    pub warnings: Vec<String>,
    /// the channel read, where the format says which (COSMOS, CSMIP, ESM,
    /// K-NET): its number, of how many, where it points
    pub channel: Option<Channel>,
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
    /// `acceleration`: the unit factor ([`Record::unit_factor`]) times
    /// `user_scale`
    pub scale: f64,
    /// the user's factor [-] alone: the spec's `scale`, or the factor that
    /// gives `target_pga_g` (1 for [`Record::new`])
    pub user_scale: f64,
    /// units of the numbers in the file (m/s² for [`Record::new`])
    pub units: Units,
    /// the file's own PGA, max |value| as read, in the file's `units` (for
    /// K-NET after the mean is removed), before any scaling
    pub file_pga: f64,
    /// the file's header lines (AT2, ESM, K-NET, COSMOS), else empty
    pub header: Vec<String>,
    /// the channel of the file read, where the format says which (None
    /// for text and [`Record::new`])
    pub channel: Option<Channel>,
}

impl Record {
    /// A record from samples [m/s²] at time step `dt` \[s\]. Errors if dt is
    /// not finite and > 0, if there are no samples or if a sample is not
    /// finite.
    pub fn new(name: impl Into<String>, dt: f64, acceleration: Vec<f64>) -> Result<Self, RecordError> {
        let name = name.into();
        validate(&name, dt, &acceleration)?;
        let file_pga = acceleration.iter().fold(0.0f64, |m, a| m.max(a.abs()));
        Ok(Record {
            name,
            source: "(memory)".into(),
            dt,
            acceleration,
            scale: 1.0,
            user_scale: 1.0,
            units: Units::MetersPerSecond2,
            file_pga,
            header: Vec::new(),
            channel: None,
        })
    }

    /// Factor [m/s² per file unit] of the file's units alone
    /// (`units.to_si()`): `scale / user_scale`.
    pub fn unit_factor(&self) -> f64 {
        self.units.to_si()
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

/// Smallest admissible time step of a record \[s\]: recorded and synthetic
/// accelerograms are sampled at 50 to 1000 Hz; 1e-5 s (100 kHz) leaves room.
pub const MIN_DT: f64 = 1e-5;
/// Largest admissible time step \[s\]: coarser sampling misses the motion a
/// bridge responds to.
pub const MAX_DT: f64 = 1.0;
/// Largest admissible |acceleration| \[g\], of the file as read (after unit
/// conversion) and of the scaled record: the strongest ground motions
/// recorded peak at about 4 g (2008 Iwate-Miyagi, KiK-net IWTH25); a
/// number beyond 5 g is a unit or scale error (m/s² read as g is 9.8 times
/// too strong, cm/s² read as g 981 times).
pub const MAX_ACCELERATION_G: f64 = 5.0;
/// Longest admissible record \[s\]: one day.
pub const MAX_DURATION: f64 = 86_400.0;

fn validate(name: &str, dt: f64, acceleration: &[f64]) -> Result<(), RecordError> {
    let invalid = |message: String| Err(RecordError::Invalid { name: name.into(), message });
    if !(dt.is_finite() && (MIN_DT..=MAX_DT).contains(&dt)) {
        return invalid(format!(
            "time step dt = {} s is outside {MIN_DT:e} to {MAX_DT} s: not a ground-motion record (is it in seconds?)",
            crate::text::number(dt)
        ));
    }
    if acceleration.len() < 2 {
        return invalid(format!("the record has {} sample(s); at least 2 are needed", acceleration.len()));
    }
    if let Some(i) = acceleration.iter().position(|a| !a.is_finite()) {
        return invalid(format!("sample {i} (t = {} s) is {}, not a finite number", i as f64 * dt, acceleration[i]));
    }
    let duration = (acceleration.len() - 1) as f64 * dt;
    if duration > MAX_DURATION {
        return invalid(format!(
            "it lasts {} s, more than a day ({MAX_DURATION} s): not a ground-motion record",
            crate::text::number(duration)
        ));
    }
    if let Some(i) = beyond_limit(acceleration, 1.0) {
        return invalid(format!(
            "sample {i} (t = {} s) is {:.4e} m/s² ({:.3e} g), beyond {MAX_ACCELERATION_G} g: no recorded ground \
             motion is that strong (the strongest peak at about 4 g); check the units and the scale",
            i as f64 * dt,
            acceleration[i],
            acceleration[i] / crate::G
        ));
    }
    Ok(())
}

/// The first sample whose |value| × `factor` [m/s²] is beyond
/// [`MAX_ACCELERATION_G`].
fn beyond_limit(values: &[f64], factor: f64) -> Option<usize> {
    let limit = MAX_ACCELERATION_G * crate::G;
    values.iter().position(|v| (v * factor).abs() > limit)
}

/// A loaded record and the warnings raised while reading it.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedRecord {
    /// the format the file was read as ([`Format::Auto`] resolved by
    /// [`crate::detect_format`])
    pub format: Format,
    /// the record
    pub record: Record,
    /// warnings, each naming the file (e.g. a record that does not start
    /// near zero)
    pub warnings: Vec<String>,
    /// SHA-256 of the file's bytes (of the text for
    /// [`load_record_from_str`]), in hex: which file it was, for provenance
    pub sha256: String,
    /// the channel read, where the format says which (COSMOS, CSMIP: one of
    /// several; ESM, K-NET: the file's one): its number, of how many, and
    /// where it points
    pub channel: Option<Channel>,
}

/// SHA-256 of some bytes, in hex.
pub fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::Digest;
    sha2::Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// A record "does not start near zero" if |a\[0\]| exceeds this fraction of
/// its PGA (1 %); loading it raises a warning, not an error.
pub const START_WARNING_FRACTION: f64 = 0.01;

/// Read the file named by `spec` (a relative path is taken relative to
/// `base_dir`), convert units, scale, and check it.
pub fn load_record(spec: &RecordSpec, base_dir: &Path) -> Result<LoadedRecord, RecordError> {
    let file = spec.file.display().to_string();
    spec.validate()?;
    let bytes = match crate::builtin::bytes(&spec.file) {
        Some(b) => b.to_vec(),
        None => {
            let path = spec.resolve_path(base_dir);
            crate::input::read_input(&path, crate::input::MAX_RECORD_BYTES).map_err(|source| RecordError::Io {
                file: if path == spec.file { file.clone() } else { format!("{file} ({})", path.display()) },
                source,
            })?
        }
    };
    let text = String::from_utf8_lossy(&bytes);
    let mut loaded = load_record_from_str(spec, &text)?;
    loaded.sha256 = sha256_hex(&bytes);
    Ok(loaded)
}

/// As [`load_record`] with the file's text given (no IO): parse `text` as
/// the file named by `spec`, in the format [`detect_format`] finds.
pub fn load_record_from_str(spec: &RecordSpec, text: &str) -> Result<LoadedRecord, RecordError> {
    spec.validate()?;
    let format = detect_format(spec, text);
    // `dt` or `column` given for a file that turns out to be ESM, say, or
    // `channel` for a text file
    spec.validate_for(format)?;
    let file = spec.file.display().to_string();
    // validate_for() guarantees dt for one-column and sequence files
    let dt = spec.dt.unwrap_or(f64::NAN);
    let raw = match format {
        Format::At2 => parse_at2(text, &file)?,
        Format::OneColumn => parse_one_column(text, &file, dt, spec.column)?,
        Format::Sequence => parse_sequence(text, &file, dt)?,
        Format::TwoColumn | Format::Auto => parse_two_column(text, &file, spec.column.unwrap_or(2))?,
        Format::Esm => parse_esm(text, &file)?,
        Format::Knet => parse_knet(text, &file)?,
        Format::Cosmos => parse_cosmos(text, &file, spec.channel_choice())?,
        Format::Csmip => parse_csmip(text, &file, spec.channel_choice())?,
    };
    from_raw(spec, format, raw, sha256_hex(text.as_bytes()))
}

/// The units of a parsed record: from the header, or the spec where the
/// header states none; never a default, never a column header's alone.
fn units_of(
    spec: &RecordSpec,
    format: Format,
    raw: &RawRecord,
    warnings: &mut Vec<String>,
) -> Result<Units, RecordError> {
    let file = spec.file.display().to_string();
    let err = |message: String| Err(RecordError::Spec { file: file.clone(), field: "units", message });
    let names = "`g`, `m/s2` or `cm/s2`";
    match (&raw.header_units, spec.units) {
        (HeaderUnits::Stated(h), Some(given)) if *h != given => {
            // one of the two is wrong, and guessing which would scale the
            // whole spectrum by a constant factor: refuse
            err(format!(
                "the file's header says units of {} but the config says `{}`: remove `units` (the header is \
                 authoritative) or fix the file",
                h.name(),
                given.name()
            ))
        }
        (HeaderUnits::Stated(h), _) => Ok(*h),
        (HeaderUnits::Label { units, label }, Some(given)) if *units != given => err(format!(
            "the column header `{label}` says {} but the config says `units = \"{}\"`: one of the two is wrong; fix \
             `units` or the column header (rename the column if `{label}` does not name its unit)",
            units.name(),
            given.name()
        )),
        (HeaderUnits::Label { .. }, Some(given)) => Ok(given),
        (HeaderUnits::Label { units, label }, None) => err(format!(
            "a text record cannot say its units, and a column header is informal: the column header `{label}` \
             suggests `units = \"{}\"`; confirm it with `units`",
            units.name()
        )),
        (HeaderUnits::Unrecognised(text), Some(given)) => {
            warnings.push(format!(
                "{file}: the header's units `{text}` are not recognised; the config's `units = \"{}\"` are used",
                given.name()
            ));
            Ok(given)
        }
        (HeaderUnits::Unrecognised(text), None) => err(format!(
            "the header's units `{text}` are not recognised: say the units of the numbers in the file with `units` \
             ({names})"
        )),
        (HeaderUnits::Missing, Some(given)) => {
            warnings.push(format!("{file}: the header states no units; the config's `{}` are used", given.name()));
            Ok(given)
        }
        (HeaderUnits::Missing, None) => {
            let place = match format {
                Format::At2 => "the header (line 3) states no units",
                Format::Esm => "the header states no units (no `UNITS:` value)",
                _ => "the header states no units",
            };
            err(format!("{place}: say the units of the numbers in the file with `units` ({names})"))
        }
        (HeaderUnits::NotInFormat, Some(given)) => Ok(given),
        (HeaderUnits::NotInFormat, None) => {
            err(format!("a text record cannot say its units: give them with `units` ({names})"))
        }
    }
}

/// A record from samples held in memory (a numpy array, say): `values` in
/// the spec's `units` (required: an array cannot say its units) at time
/// step `dt` \[s\], converted, scaled (`scale`, `target_pga_g`) and checked
/// exactly as a file's numbers are. `spec.file` names the samples in
/// messages; `sha256` is that of the samples' little-endian bytes.
pub fn load_record_from_samples(spec: &RecordSpec, dt: f64, values: Vec<f64>) -> Result<LoadedRecord, RecordError> {
    let file = spec.file.display().to_string();
    if spec.units.is_none() {
        return Err(RecordError::Spec {
            file,
            field: "units",
            message: "an array cannot say its units: give them with `units` (`g`, `m/s2`, `cm/s2` or `gal`)".into(),
        });
    }
    RecordSpec { format: Format::Sequence, dt: Some(dt), ..spec.clone() }.validate()?;
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(RecordError::Invalid {
            name: file,
            message: format!("sample {i} (t = {} s) is {}, not a finite number", i as f64 * dt, values[i]),
        });
    }
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    let raw = RawRecord {
        dt,
        values,
        header: Vec::new(),
        first_time: None,
        header_units: HeaderUnits::NotInFormat,
        warnings: Vec::new(),
        channel: None,
    };
    from_raw(spec, Format::Sequence, raw, sha256_hex(&bytes))
}

/// Refuses a vertical channel unless `allow_vertical` (then warns).
fn check_vertical(
    spec: &RecordSpec,
    raw: &RawRecord,
    file: &str,
    warnings: &mut Vec<String>,
) -> Result<(), RecordError> {
    if let Some(c) = raw.channel.as_ref().filter(|c| c.orientation.is_vertical()) {
        if !spec.allow_vertical {
            return Err(RecordError::Spec {
                file: file.to_string(),
                field: "allow_vertical",
                message: format!(
                    "{} is a vertical component, but the joint model's excitation is horizontal (along or across \
                     the bridge): read a horizontal channel{}, or set `allow_vertical = true` \
                     (`--allow-vertical`) if the vertical motion is meant",
                    c.describe(),
                    if c.of > 1 { " (`channel = N`, `--channel N`)" } else { "" }
                ),
            });
        }
        warnings.push(format!("{file}: {} is a vertical component, read as asked (`allow_vertical`)", c.describe()));
    }
    Ok(())
}

/// Unit conversion, scaling and warnings for a parsed record.
fn from_raw(spec: &RecordSpec, format: Format, raw: RawRecord, sha256: String) -> Result<LoadedRecord, RecordError> {
    let file = spec.file.display().to_string();
    // the channels of one file named apart (`CICLC.ch2`) unless named
    let name = match &raw.channel {
        Some(c) if c.of > 1 && spec.name.is_none() => format!("{}.ch{}", spec.label(), c.number),
        _ => spec.label(),
    };
    let mut warnings = Vec::new();
    let units = units_of(spec, format, &raw, &mut warnings)?;
    warnings.extend(raw.warnings.iter().cloned());
    check_vertical(spec, &raw, &file, &mut warnings)?;
    if let Some(t0) = raw.first_time {
        if t0.abs() > 0.5 * raw.dt {
            warnings.push(format!(
                "{file}: the time column starts at t = {t0} s; times are counted from the first sample (t = 0)"
            ));
        }
    }
    let to_si = units.to_si();
    // the file as read: a record beyond any earthquake is a unit error,
    // even if a target PGA would scale it down to a plausible one
    if let Some(i) = beyond_limit(&raw.values, to_si) {
        return Err(RecordError::Invalid {
            name: file,
            message: format!(
                "sample {i} (t = {} s) is {} {} in the file{}, beyond {MAX_ACCELERATION_G} g: no recorded ground \
                 motion is that strong (the strongest peak at about 4 g); check `units` (the numbers are read as {})",
                i as f64 * raw.dt,
                crate::text::number(raw.values[i]),
                units.name(),
                if units == Units::G { String::new() } else { format!(" ({:.3} g)", raw.values[i] * to_si / crate::G) },
                units.name()
            ) + if raw.values.iter().all(|v| v.fract() == 0.0) {
                "; every value is a whole number: digitiser counts? (read a K-NET file with its header, which gives \
                 the factor to gal)"
            } else {
                ""
            },
        });
    }
    let file_pga = raw.values.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    let user_scale = match spec.target_pga_g {
        Some(target) => {
            let pga_si = file_pga * to_si;
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
    let scale = to_si * user_scale;
    let acceleration: Vec<f64> = raw.values.iter().map(|v| v * scale).collect();
    // the file as read passed the 5 g limit above: beyond it now is the
    // user's factor's doing, so the error names that field
    if let Some(i) = beyond_limit(&acceleration, 1.0).or_else(|| acceleration.iter().position(|a| !a.is_finite())) {
        let (field, value) = match spec.target_pga_g {
            Some(t) => ("target_pga_g", t),
            None => ("scale", spec.scale),
        };
        return Err(RecordError::Spec {
            file,
            field,
            message: format!(
                "{field} = {}: the scaled record reaches {} at sample {i} (t = {} s), beyond {MAX_ACCELERATION_G} g: \
                 no recorded ground motion is that strong",
                crate::text::number(value),
                if acceleration[i].is_finite() {
                    format!("{:.3} g", acceleration[i] / crate::G)
                } else {
                    "an overflow".to_string()
                },
                crate::text::number(i as f64 * raw.dt)
            ),
        });
    }
    let record = Record {
        name,
        source: file.clone(),
        dt: raw.dt,
        acceleration,
        scale,
        user_scale,
        units,
        file_pga,
        header: raw.header.clone(),
        channel: raw.channel.clone(),
    };
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
    Ok(LoadedRecord { format, record, warnings, sha256, channel: raw.channel })
}
