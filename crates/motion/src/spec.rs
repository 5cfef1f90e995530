//! How a record is described in a configuration file: [`RecordSpec`],
//! [`Format`] and [`Units`].

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::RecordError;

/// Units of the acceleration numbers in a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
pub enum Units {
    /// Standard gravity, g = [`crate::G`] = 9.80665 m/s² (written `"g"`).
    #[serde(rename = "g")]
    G,
    /// Metres per second squared (written `"m/s2"`).
    #[serde(rename = "m/s2")]
    MetersPerSecond2,
    /// Centimetres per second squared, gal (written `"cm/s2"` or `"gal"`).
    #[serde(rename = "cm/s2", alias = "gal")]
    CentimetersPerSecond2,
}

/// What a file says about the units of its numbers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum HeaderUnits {
    /// The format has no place for units (plain text and CSV).
    NotInFormat,
    /// The header should state them and does not (an AT2 line 3 without
    /// `UNITS`).
    Missing,
    /// The header states these.
    Stated(Units),
    /// The header states something not recognised (the text as written,
    /// shortened).
    Unrecognised(String),
    /// A text file's column header names a unit for the acceleration column
    /// (`acc_m_s2`, `acc [g]`, `Beschleunigung [m/s2]`): informal, so it is
    /// never used on its own, only checked against the spec's `units`.
    Label {
        /// the unit the label names
        units: Units,
        /// the column header as written (shortened)
        label: String,
    },
}

impl Units {
    /// Reads a unit as written in a file header, case and spaces ignored:
    /// `G`; `GAL`, `CM/S/S`, `CM/SEC/SEC`, `CM/S2`, `CM/S^2`, `CM/S**2`,
    /// `CM/SEC2`, `CM/SEC^2`; `M/S/S`, `M/SEC/SEC`, `M/S2`, `M/S^2` (and the
    /// `SEC` and `**2` variants). Anything else is `None`.
    pub fn from_header(text: &str) -> Option<Units> {
        let t: String = text.chars().filter(|c| !c.is_whitespace()).collect::<String>().to_ascii_uppercase();
        let t = t.trim_end_matches(['.', ',', ';', ')']).trim_start_matches('(');
        let per_s2 = |unit: &str| {
            let rest = t.strip_prefix(unit).and_then(|r| r.strip_prefix('/'));
            rest.is_some_and(|r| {
                matches!(r, "S/S" | "SEC/SEC" | "S2" | "S^2" | "S**2" | "SEC2" | "SEC^2" | "SEC**2" | "SS")
            })
        };
        match t {
            "G" | "GS" | "G'S" => Some(Units::G),
            "GAL" | "GALS" | "GALILEO" => Some(Units::CentimetersPerSecond2),
            _ if per_s2("CM") => Some(Units::CentimetersPerSecond2),
            _ if per_s2("M") => Some(Units::MetersPerSecond2),
            _ => None,
        }
    }
}

impl Units {
    /// Factor from a number in these units to m/s² [m/s² per unit].
    pub fn to_si(self) -> f64 {
        match self {
            Units::G => crate::G,
            Units::MetersPerSecond2 => 1.0,
            Units::CentimetersPerSecond2 => 0.01,
        }
    }

    /// The name used in configuration files (`"g"`, `"m/s2"`, `"cm/s2"`).
    pub fn name(self) -> &'static str {
        match self {
            Units::G => "g",
            Units::MetersPerSecond2 => "m/s2",
            Units::CentimetersPerSecond2 => "cm/s2",
        }
    }
}

/// File format of a record.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Format {
    /// Decide from the file ([`crate::detect_format`]): an `.at2` extension
    /// (any case) means [`Format::At2`]; else the first line of the content
    /// names ESM (`EVENT_NAME:`), K-NET/KiK-net (`Origin Time`) or COSMOS
    /// (`... (Format v01.20 ...)`) or CSMIP (`Uncorrected Accelerogram
    /// Data`, `Corrected accelerogram`); else plain text:
    /// [`Format::OneColumn`] if `dt` is given, else [`Format::TwoColumn`].
    #[default]
    Auto,
    /// PEER NGA `.AT2`: 4 header lines, line 4 holds NPTS and DT, then the
    /// values (in g), any number per line.
    At2,
    /// Text or CSV with the time \[s\] in column 1 and the acceleration in
    /// another column (default 2); the time step must be uniform.
    TwoColumn,
    /// Text with one acceleration value per line and the time step given
    /// in the spec (`dt`).
    OneColumn,
    /// ESM (Engineering Strong Motion database, ORFEUS) ASCII: `KEY: value`
    /// header lines, then one value per line ([`crate::formats::esm`]).
    Esm,
    /// K-NET / KiK-net (NIED) ASCII: header up to `Memo.`, then integer
    /// counts ([`crate::formats::knet`]).
    #[serde(alias = "k-net", alias = "kik-net")]
    Knet,
    /// COSMOS Strong-Motion Data Format v1.20, V1 or V2 acceleration
    /// ([`crate::formats::cosmos`]).
    Cosmos,
    /// CSMIP/DMG Volume 1 or Volume 2, the format CESMD distributes
    /// (`.v1`, `.RAW`, `.V2`; [`crate::formats::csmip`]).
    #[serde(alias = "dmg")]
    Csmip,
    /// Numbers in reading order, any number per line (the body of a K-NET,
    /// COSMOS or PEER file without its header), at the spec's `dt`.
    Sequence,
}

impl Format {
    /// The name used in configuration files (`"auto"`, `"at2"`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Format::Auto => "auto",
            Format::At2 => "at2",
            Format::TwoColumn => "two-column",
            Format::OneColumn => "one-column",
            Format::Esm => "esm",
            Format::Knet => "knet",
            Format::Cosmos => "cosmos",
            Format::Csmip => "csmip",
            Format::Sequence => "sequence",
        }
    }

    /// What the format is, for messages (`"PEER NGA AT2"`, `"ESM ASCII"`, ...).
    pub fn description(self) -> &'static str {
        match self {
            Format::Auto => "automatically detected",
            Format::At2 => "PEER NGA AT2",
            Format::TwoColumn => "two-column text (time, acceleration)",
            Format::OneColumn => "one-column text",
            Format::Esm => "ESM ASCII",
            Format::Knet => "K-NET/KiK-net ASCII",
            Format::Cosmos => "COSMOS V1/V2",
            Format::Csmip => "CSMIP/DMG Volume 1/2",
            Format::Sequence => "sequence of values",
        }
    }

    /// Whether the file carries its own time step (then `dt` is an error).
    pub fn has_own_time_step(self) -> bool {
        matches!(self, Format::At2 | Format::TwoColumn | Format::Esm | Format::Knet | Format::Cosmos | Format::Csmip)
    }

    /// Whether a file of the format may hold several channels (then
    /// `channel` or `azimuth` choose one).
    pub fn has_channels(self) -> bool {
        matches!(self, Format::Cosmos | Format::Csmip)
    }
}

fn one() -> f64 {
    1.0
}

/// How a record is read: one entry of a TOML configuration
/// (unknown fields are rejected).
///
/// Units are never guessed:
/// - an AT2, ESM, K-NET or COSMOS file states them in its header (AT2 line
///   3 `UNITS OF G`, ESM `UNITS: cm/s^2`, the K-NET scale factor's `(gal)`,
///   the COSMOS units code); `units`, if given, must agree with the header,
///   and is required when the header states none or states something
///   unknown;
/// - a text file cannot state them: `units` is required. A column header
///   naming a unit (`acc_m_s2`, `acc [g]`) is checked against `units` and
///   suggested when `units` is missing, never used on its own.
///
/// Other choices:
/// - `dt` is only for one-column and sequence files (and required there);
///   giving it for a file that carries its own time step (AT2, two-column,
///   ESM, K-NET, COSMOS) is an error.
/// - `column` is for text files: the acceleration column of a two-column
///   file (default 2, at least 2), or the column to take from each line of
///   a one-column file that has several (default: the line must hold
///   exactly one value). Giving it for any other format is an error.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RecordSpec {
    /// Path of the record file; a relative path is resolved against the
    /// base directory given to [`crate::load_record`].
    pub file: PathBuf,
    /// File format (default: [`Format::Auto`]).
    #[serde(default)]
    pub format: Format,
    /// Units of the numbers in the file: required for text files, checked
    /// against the header of an AT2, ESM, K-NET or COSMOS file.
    #[serde(default)]
    pub units: Option<Units>,
    /// Time step \[s\] of a one-column or sequence file (required there,
    /// rejected for formats that carry their own time step).
    #[serde(default)]
    pub dt: Option<f64>,
    /// 1-based column of the acceleration in a multi-column text/CSV file
    /// (two-column default 2; time is column 1).
    #[serde(default)]
    pub column: Option<usize>,
    /// Factor [-] applied after unit conversion (default 1; may be negative
    /// to flip the polarity, not zero).
    #[serde(default = "one")]
    pub scale: f64,
    /// Scale the record so that its PGA equals this value \[g\]; an error if
    /// combined with `scale` other than 1.
    #[serde(default)]
    pub target_pga_g: Option<f64>,
    /// The channel to read from a file of several (COSMOS, CSMIP): its
    /// number as the file gives it (`Chan  2:`); without it (and without
    /// `azimuth`) the first is read, with a warning naming the others.
    // (left out of a config written back when not set, so that the hash of
    // a config that does not use them is what it was before they existed)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub channel: Option<u32>,
    /// The channel to read from a file of several, by the direction it
    /// points \[degrees clockwise from north, 0 to 360\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub azimuth: Option<f64>,
    /// Read a vertical component as the excitation (refused otherwise: the
    /// joint model's excitation is horizontal).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub allow_vertical: bool,
    /// Label of the record (default: the file stem).
    #[serde(default)]
    pub name: Option<String>,
}

impl RecordSpec {
    /// A spec for `file` with every other field at its default.
    pub fn new(file: impl Into<PathBuf>) -> Self {
        RecordSpec {
            file: file.into(),
            format: Format::Auto,
            units: None,
            dt: None,
            column: None,
            scale: 1.0,
            target_pga_g: None,
            name: None,
            channel: None,
            azimuth: None,
            allow_vertical: false,
        }
    }

    /// The channel this spec chooses (`channel`, `azimuth`).
    pub fn channel_choice(&self) -> crate::formats::channel::ChannelChoice {
        crate::formats::channel::ChannelChoice { number: self.channel, azimuth: self.azimuth }
    }

    /// The format after resolving [`Format::Auto`] without the file's
    /// content: `.at2` extension (any case) means [`Format::At2`], else
    /// [`Format::OneColumn`] if `dt` is given, else [`Format::TwoColumn`].
    /// [`crate::detect_format`] also looks at the content (ESM, K-NET,
    /// COSMOS headers); [`crate::load_record`] uses that.
    pub fn resolved_format(&self) -> Format {
        match self.format {
            Format::Auto => {
                if self.has_at2_extension() {
                    Format::At2
                } else if self.dt.is_some() {
                    Format::OneColumn
                } else {
                    Format::TwoColumn
                }
            }
            f => f,
        }
    }

    /// Whether the file name ends in `.at2` (any case).
    pub fn has_at2_extension(&self) -> bool {
        self.file.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("at2"))
    }

    /// The record's label: `name`, else the file stem, else the path.
    pub fn label(&self) -> String {
        if let Some(n) = &self.name {
            return n.clone();
        }
        let file = self.file.to_str().and_then(|f| f.strip_prefix(crate::builtin::PREFIX)).map(Path::new);
        match file.unwrap_or(&self.file).file_stem() {
            Some(s) => s.to_string_lossy().into_owned(),
            None => self.file.display().to_string(),
        }
    }

    /// The path to open: `file` itself if absolute or built in
    /// ([`crate::builtin`]), else `base_dir/file`.
    pub fn resolve_path(&self, base_dir: &Path) -> PathBuf {
        if self.file.is_absolute() || crate::builtin::is_builtin(&self.file) {
            self.file.clone()
        } else {
            base_dir.join(&self.file)
        }
    }

    /// Check the fields against each other (without reading the file),
    /// for the format [`RecordSpec::resolved_format`] gives. Errors name the
    /// file and the field.
    /// `channel` and `azimuth` of a spec whose format is left to the
    /// content (`auto`) are checked once the content says the format
    /// ([`RecordSpec::validate_for`]).
    pub fn validate(&self) -> Result<(), RecordError> {
        self.check(self.resolved_format(), self.format == Format::Auto)
    }

    /// As [`RecordSpec::validate`] for the file read as `format` (the one
    /// [`crate::detect_format`] found in the file's content, say).
    pub fn validate_for(&self, format: Format) -> Result<(), RecordError> {
        self.check(format, false)
    }

    /// The checks, for a file read as `format`; `guessed`: the format is
    /// not known yet (the content decides).
    fn check(&self, format: Format, guessed: bool) -> Result<(), RecordError> {
        let file = self.file.display().to_string();
        let err = |field: &'static str, message: String| Err(RecordError::Spec { file: file.clone(), field, message });
        if crate::builtin::is_builtin(&self.file) && crate::builtin::bytes(&self.file).is_none() {
            return err(
                "file",
                format!("no such built-in record (the built-in record is `{}`)", crate::builtin::DEFAULT),
            );
        }
        match (format, self.dt) {
            (Format::OneColumn, None) => return err("dt", "a one-column file needs the time step `dt` [s]".into()),
            (Format::Sequence, None) => {
                return err("dt", "a sequence of values needs the time step `dt` [s] (and `units`)".into())
            }
            (Format::OneColumn | Format::Sequence, Some(dt)) if !(dt.is_finite() && dt > 0.0) => {
                return err("dt", format!("dt = {dt} s must be finite and > 0"))
            }
            (f, Some(dt)) if f.has_own_time_step() => {
                return err(
                    "dt",
                    format!(
                        "`dt` is only for one-column and sequence files (this file, read as {}, carries its own \
                         time step): remove `dt = {dt}`",
                        f.description()
                    ),
                )
            }
            _ => {}
        }
        match (format, self.column) {
            (Format::TwoColumn, Some(c)) if c < 2 => {
                return err("column", format!("column {c}: the acceleration column is 2 or more (time is column 1)"))
            }
            (Format::OneColumn, Some(0)) => return err("column", "columns are counted from 1".into()),
            (Format::TwoColumn | Format::OneColumn | Format::Auto, _) | (_, None) => {}
            (f, Some(_)) => {
                let mut message =
                    format!("`column` is only for one- and two-column text files, not {}", f.description());
                if f.has_channels() {
                    message += ": to read another channel of the file, give `channel = N` (`--channel N`) or \
                                `azimuth = DEGREES` (`--azimuth DEGREES`)";
                }
                return err("column", message);
            }
        }
        if self.channel.is_some() || self.azimuth.is_some() {
            let field = if self.channel.is_some() { "channel" } else { "azimuth" };
            if !(format.has_channels() || guessed) {
                let message = format!(
                    "`{field}` chooses a channel of a COSMOS or CSMIP file, which may hold several; a file read as \
                     {} holds one",
                    format.description()
                );
                return err(field, message);
            }
            if self.channel.is_some() && self.azimuth.is_some() {
                return err("azimuth", "give either `channel` or `azimuth`, not both".into());
            }
            if self.channel == Some(0) {
                return err("channel", "channels are numbered from 1, as the file numbers them".into());
            }
            if let Some(a) = self.azimuth.filter(|a| !(a.is_finite() && (0.0..=360.0).contains(a))) {
                return err("azimuth", format!("azimuth = {a}: degrees clockwise from north, 0 to 360"));
            }
        }
        if !self.scale.is_finite() || self.scale == 0.0 {
            return err("scale", format!("scale = {} must be finite and not zero", self.scale));
        }
        if let Some(t) = self.target_pga_g {
            if !(t.is_finite() && t > 0.0 && t <= crate::record::MAX_ACCELERATION_G) {
                return err(
                    "target_pga_g",
                    format!(
                        "target_pga_g = {t} g must be above 0 and at most {} g (no recorded ground motion is \
                         stronger)",
                        crate::record::MAX_ACCELERATION_G
                    ),
                );
            }
            if self.scale != 1.0 {
                return err(
                    "target_pga_g",
                    format!("give either `scale` ({}) or `target_pga_g` ({t} g), not both", self.scale),
                );
            }
        }
        Ok(())
    }
}
