//! Errors. Every [`RecordError`] message names the file (or the record) and,
//! where it applies, the 1-based line number and the offending token or
//! value; spec errors name the field.

/// Why a record could not be read or built.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// The file could not be read.
    #[error("{file}: cannot read the file: {source}")]
    Io {
        /// path as given
        file: String,
        /// the operating system's error
        #[source]
        source: std::io::Error,
    },
    /// The file holds nothing but white space.
    #[error("{file}: the file is empty")]
    Empty {
        /// path as given
        file: String,
    },
    /// A header problem (AT2 line 4 without NPTS or DT, a header cut short,
    /// a file that is not an acceleration record).
    #[error("{file}:{line}: {message}")]
    Header {
        /// path as given
        file: String,
        /// 1-based line number
        line: usize,
        /// what is wrong
        message: String,
    },
    /// The time step is not > 0 (AT2 `DT`, or a two-column time column that
    /// does not increase).
    #[error("{file}:{line}: time step dt = {dt} s must be finite and > 0")]
    BadDt {
        /// path as given
        file: String,
        /// 1-based line number
        line: usize,
        /// the time step found \[s\]
        dt: f64,
    },
    /// A token that does not read as a number.
    #[error("{file}:{line}: `{token}` is not a number")]
    NotANumber {
        /// path as given
        file: String,
        /// 1-based line number
        line: usize,
        /// the token as written
        token: String,
    },
    /// A number that is NaN or infinite.
    #[error("{file}:{line}: `{token}` is not a finite number (NaN and infinity are not allowed)")]
    NotFinite {
        /// path as given
        file: String,
        /// 1-based line number
        line: usize,
        /// the token as written
        token: String,
    },
    /// Fewer values than the header's NPTS.
    #[error("{file}:{line}: the header says NPTS = {expected} but the file ends after {found} values")]
    TooFewValues {
        /// path as given
        file: String,
        /// 1-based number of the last line
        line: usize,
        /// NPTS from the header
        expected: usize,
        /// values found
        found: usize,
    },
    /// More values than the header's NPTS.
    #[error("{file}:{line}: more values than NPTS = {expected}: value number {} is on this line", expected + 1)]
    TooManyValues {
        /// path as given
        file: String,
        /// 1-based line of the first value too many
        line: usize,
        /// NPTS from the header
        expected: usize,
    },
    /// A line of a text file with the wrong number of columns.
    #[error("{file}:{line}: {message}")]
    Columns {
        /// path as given
        file: String,
        /// 1-based line number
        line: usize,
        /// what is wrong
        message: String,
    },
    /// A number written with a decimal comma (`0,005`): never read, since
    /// a comma also separates values and which one it is would be a guess.
    #[error(
        "{file}:{line}: decimal commas are not read: {} (write every number with a decimal point; a comma also \
         separates the values of a CSV file, so which one a comma is would be a guess)",
        decimal_hint(token)
    )]
    DecimalComma {
        /// path as given
        file: String,
        /// 1-based line number
        line: usize,
        /// the number as written (shortened)
        token: String,
    },
    /// The time column of a two-column file is not uniform.
    #[error(
        "{file}:{line}: the time column is not uniform: t = {found} s where {expected} s was expected \
         (dt = {dt} s from the first and last times; tolerance 1 % of dt)"
    )]
    NonUniformTime {
        /// path as given
        file: String,
        /// 1-based line number
        line: usize,
        /// time expected from a uniform step \[s\]
        expected: f64,
        /// time found \[s\]
        found: f64,
        /// mean time step \[s\]
        dt: f64,
    },
    /// A record with too few samples (no value at all, or a single sample
    /// where a time step must be derived).
    #[error("{file}: {message}")]
    TooShort {
        /// path as given
        file: String,
        /// what is wrong
        message: String,
    },
    /// A field of a [`crate::RecordSpec`] that is invalid or contradicts
    /// another.
    #[error("{file}: field `{field}`: {message}")]
    Spec {
        /// path as given
        file: String,
        /// the field's name in the configuration
        field: &'static str,
        /// what is wrong
        message: String,
    },
    /// A record built in memory ([`crate::Record::new`]) or scaled that is
    /// not usable (dt <= 0, no samples, a sample not finite, a zero record
    /// scaled to a target PGA).
    #[error("record `{name}`: {message}")]
    Invalid {
        /// the record's name or file
        name: String,
        /// what is wrong
        message: String,
    },
}

/// What to do about a number with a comma, for
/// [`RecordError::DecimalComma`]: `convert `0,005` to `0.005``, or the
/// generic example for a token with several commas or a point too.
fn decimal_hint(token: &str) -> String {
    if token.matches(',').count() == 1 && !token.contains('.') {
        format!("convert `{token}` to `{}`", token.replace(',', "."))
    } else {
        format!("`{token}` has a comma inside a number: convert `0,5` to `0.5` and remove thousands separators")
    }
}

/// Invalid arguments to the spectrum functions.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpectrumError {
    /// A period that is negative, not finite, or positive below
    /// [`crate::oscillator::MIN_PERIOD`].
    #[error("period T = {} s must be 0 (the rigid oscillator: Sa = PGA) or from 1e-6 s on, and finite", crate::text::number(*.0))]
    Period(f64),
    /// A damping ratio outside [0, 1).
    #[error("damping ratio {0} must be finite, >= 0 and < 1")]
    Damping(f64),
    /// A time step that is not > 0.
    #[error("time step dt = {0} s must be finite and > 0")]
    Dt(f64),
    /// A record without samples, or with a sample that is not finite.
    #[error("the record {0}")]
    Record(String),
    /// Too many subdivisions of the sample interval.
    #[error("subdivisions = {0} is more than the maximum {max}", max = crate::MAX_SUBDIVISIONS)]
    Subdivisions(u32),
    /// An invalid period range.
    #[error("period range: {0}")]
    Range(String),
    /// A target spectrum parameter out of range.
    #[error("target.{field}: {message}")]
    Target {
        /// The parameter.
        field: String,
        /// What is wrong.
        message: String,
    },
    /// A suite that cannot be scaled.
    #[error("suite: {0}")]
    Suite(String),
}
