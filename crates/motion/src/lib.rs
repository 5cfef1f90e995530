//! Ground-motion records and exact linear response spectra.
//!
//! Read a record (PEER NGA-West2 `.AT2`, ESM and K-NET/KiK-net ASCII,
//! COSMOS V1/V2, CSMIP/DMG Volume 1/2 (CESMD), two-column time/acceleration
//! text or CSV, one-column text
//! or a sequence of values with a given time step) described by a
//! [`RecordSpec`], get a [`Record`] in m/s² with a uniform time step, its
//! [`RecordStats`] (PGA, PGV, PGD, Arias intensity, significant duration) and
//! its exact linear response spectrum:
//!
//! ```
//! use quakejoint_motion::*;
//!
//! // 0.1 g constant for 2 s at dt = 0.01 s, read from one-column text
//! let text = "0.1\n".repeat(201);
//! let mut spec = RecordSpec::new("step.txt");
//! spec.dt = Some(0.01);
//! spec.units = Some(Units::G); // a text file cannot say its units
//! let loaded = load_record_from_str(&spec, &text).unwrap();
//! let rec = &loaded.record;
//! assert_eq!(rec.acceleration.len(), 201);
//! assert!((rec.pga() - 0.1 * G).abs() < 1e-12);
//!
//! let periods = period_range(0.1, 2.0, 20, true).unwrap();
//! let rows = spectrum(rec, &periods, &[0.0, 0.05], SpectrumOptions::default()).unwrap();
//! assert_eq!(rows.len(), 40);
//! // an undamped oscillator under a suddenly applied constant load
//! // overshoots to twice the static displacement
//! let row = &rows[5];
//! let w = 2.0 * std::f64::consts::PI / row.period;
//! assert!((w * w * row.peaks.sd / (0.1 * G) - 2.0).abs() < 1e-3);
//! ```
//!
//! Conventions (see `docs/ground-motions.md`): the ground acceleration is
//! linear between samples; the oscillator starts at rest at t = 0 with
//! a_g(0) equal to the first sample; the response is followed over the
//! record's duration only; peaks are taken at the sample times unless
//! [`SpectrumOptions::subdivisions`] asks for more points.
//!
//! The oscillator step is exact for piecewise-linear ground acceleration
//! (Nigam & Jennings 1969). Its coefficients come from the exponential of
//! the augmented 4×4 system, computed by scaling and squaring of a Taylor
//! series in a form that keeps full relative precision for small ω·dt
//! (long periods), where the textbook closed form loses digits.

#![deny(missing_docs)]

pub mod at2;
pub mod builtin;
pub mod error;
pub mod formats;
pub mod input;
mod label;
pub mod oscillator;
pub mod record;
pub mod spec;
pub mod spectrum;
pub mod stats;
pub mod suite;
pub mod target;
pub mod text;

pub use at2::parse_at2;
pub use error::{RecordError, SpectrumError};
pub use formats::channel::{Channel, ChannelChoice, Orientation};
pub use formats::{
    cosmos::parse_cosmos, csmip::parse_csmip, detect_format, esm::parse_esm, knet::parse_knet, sniff_format,
};
pub use input::{read_input, read_input_text, regular_file, MAX_CONFIG_BYTES, MAX_RECORD_BYTES, MAX_TABLE_BYTES};
pub use oscillator::Oscillator;
pub use record::{
    load_record, load_record_from_samples, load_record_from_str, sha256_hex, LoadedRecord, RawRecord, Record,
    MAX_ACCELERATION_G, MAX_DT, MAX_DURATION, MIN_DT, START_WARNING_FRACTION,
};
pub use spec::{Format, HeaderUnits, RecordSpec, Units};
pub use spectrum::{
    history, peaks, period_range, spectrum, spectrum_samples, History, Peaks, SpectrumOptions, SpectrumRow,
    MAX_PERIODS, MAX_SUBDIVISIONS,
};
pub use stats::RecordStats;
pub use suite::{scale_suite, SuiteRule, SuiteScaling};
pub use target::{Ec8Type, TargetSpectrum};
pub use text::{excerpt, number, parse_number, parse_one_column, parse_sequence, parse_two_column};

/// Standard gravity [m/s²] used for the unit `g` and for Arias intensity.
pub const G: f64 = 9.80665;
