//! Exact linear response spectra: peaks of one oscillator ([`peaks`]), a
//! whole spectrum ([`spectrum`]), the full response history ([`history`])
//! and period grids ([`period_range`]).
//!
//! Conventions: the oscillator starts at rest at t = 0 with a_g(0) equal to
//! the first sample (no ramp from zero); a_g is linear between samples; the
//! response is followed from the first to the last sample (nothing is
//! appended after the record). Peaks are the largest absolute values at the
//! sample times, or at `subdivisions` points per sample interval if
//! [`SpectrumOptions::subdivisions`] > 1.

use crate::error::SpectrumError;
use crate::oscillator::{check_parameters, run_lanes, step_coefficients, step_once, Oscillator, RawPeaks, Refined};
use crate::record::Record;

/// Largest accepted [`SpectrumOptions::subdivisions`].
pub const MAX_SUBDIVISIONS: u32 = 1000;

/// Options of the spectrum computation.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SpectrumOptions {
    /// Points per sample interval at which peaks are sought [-]: 0 or 1
    /// means the sample times only (the usual convention); m > 1 also
    /// looks at t_n + k·dt/m, k = 1..m-1 (the response there is exact too).
    /// At most [`MAX_SUBDIVISIONS`].
    pub subdivisions: u32,
}

/// Peak responses of one oscillator, SI units. Times are those of the first
/// occurrence of each peak, from the first sample (t = 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peaks {
    /// spectral acceleration: peak absolute acceleration |u'' + a_g| =
    /// |ω²u + 2ζωu'| [m/s²]
    pub sa: f64,
    /// time of `sa` \[s\]
    pub t_sa: f64,
    /// spectral velocity: peak relative velocity |u'| [m/s]
    pub sv: f64,
    /// time of `sv` \[s\]
    pub t_sv: f64,
    /// spectral displacement: peak relative displacement |u| \[m\]
    pub sd: f64,
    /// time of `sd` \[s\]
    pub t_sd: f64,
    /// pseudo-spectral acceleration ω²·Sd [m/s²] (PGA for T = 0)
    pub psa: f64,
    /// pseudo-spectral velocity ω·Sd [m/s] (0 for T = 0)
    pub psv: f64,
}

impl Peaks {
    /// All fields NaN (the answer to invalid input of [`peaks`]).
    pub const NAN: Peaks = Peaks {
        sa: f64::NAN,
        t_sa: f64::NAN,
        sv: f64::NAN,
        t_sv: f64::NAN,
        sd: f64::NAN,
        t_sd: f64::NAN,
        psa: f64::NAN,
        psv: f64::NAN,
    };
}

/// One row of a spectrum.
#[derive(Debug, Clone, PartialEq)]
pub struct SpectrumRow {
    /// damping ratio ζ [-]
    pub damping: f64,
    /// period T \[s\]
    pub period: f64,
    /// peak responses
    pub peaks: Peaks,
}

/// Response of one oscillator at every sample time (index i is t = i·dt).
#[derive(Debug, Clone, PartialEq)]
pub struct History {
    /// relative displacement u \[m\]
    pub u: Vec<f64>,
    /// relative velocity u' [m/s]
    pub v: Vec<f64>,
    /// absolute acceleration u'' + a_g = -(ω²u + 2ζωu') [m/s²]
    pub a_abs: Vec<f64>,
}

fn check_samples(accel: &[f64]) -> Result<(), SpectrumError> {
    if accel.is_empty() {
        return Err(SpectrumError::Record("has no samples".into()));
    }
    if let Some(i) = accel.iter().position(|a| !a.is_finite()) {
        return Err(SpectrumError::Record(format!("sample {i} is {}, not finite", accel[i])));
    }
    Ok(())
}

fn check_options(options: SpectrumOptions) -> Result<u32, SpectrumError> {
    if options.subdivisions > MAX_SUBDIVISIONS {
        return Err(SpectrumError::Subdivisions(options.subdivisions));
    }
    Ok(options.subdivisions.max(1))
}

/// Peaks of the rigid oscillator (T = 0): Sa = PGA, Sd = Sv = 0.
fn rigid_peaks(accel: &[f64], h: f64) -> Peaks {
    let (mut pga, mut ip) = (0.0f64, 0usize);
    for (i, a) in accel.iter().enumerate() {
        if a.abs() > pga {
            pga = a.abs();
            ip = i;
        }
    }
    Peaks { sa: pga, t_sa: ip as f64 * h, sv: 0.0, t_sv: 0.0, sd: 0.0, t_sd: 0.0, psa: pga, psv: 0.0 }
}

fn to_peaks(raw: &RawPeaks, omega: f64, h: f64) -> Peaks {
    Peaks {
        sa: raw.a,
        t_sa: raw.ia as f64 * h,
        sv: raw.v,
        t_sv: raw.iv as f64 * h,
        sd: raw.u,
        t_sd: raw.iu as f64 * h,
        psa: omega * omega * raw.u,
        psv: omega * raw.u,
    }
}

impl Oscillator {
    /// Peak responses to ground acceleration `accel` [m/s²] sampled at this
    /// oscillator's dt; errors on an empty or non-finite record or too many
    /// subdivisions.
    pub fn peaks(&self, accel: &[f64], options: SpectrumOptions) -> Result<Peaks, SpectrumError> {
        check_samples(accel)?;
        let m = check_options(options)?;
        let h = self.dt / m as f64;
        Ok(match self.step {
            None => rigid_peaks(accel, self.dt),
            Some(step) => {
                let step = if m > 1 { step_coefficients(self.period, self.damping, h) } else { step };
                let w2 = self.omega2();
                let acc = Refined::new(accel, m as usize);
                let raw = run_lanes(&[step], &[w2], &[2.0 * self.damping * self.omega], acc);
                to_peaks(&raw[0], self.omega, h)
            }
        })
    }

    /// Response at every sample time of `accel` [m/s²]; errors on an empty
    /// or non-finite record.
    pub fn history(&self, accel: &[f64]) -> Result<History, SpectrumError> {
        check_samples(accel)?;
        let n = accel.len();
        let Some(step) = self.step else {
            return Ok(History { u: vec![0.0; n], v: vec![0.0; n], a_abs: accel.to_vec() });
        };
        let (w2, tzw) = (self.omega2(), 2.0 * self.damping * self.omega);
        let mut h = History { u: Vec::with_capacity(n), v: Vec::with_capacity(n), a_abs: Vec::with_capacity(n) };
        let (mut u, mut v) = (0.0, 0.0);
        h.u.push(u);
        h.v.push(v);
        h.a_abs.push(0.0);
        for w in accel.windows(2) {
            (u, v) = step_once(&step, u, v, w[0], w[1]);
            h.u.push(u);
            h.v.push(v);
            h.a_abs.push(-(w2 * u + tzw * v));
        }
        Ok(h)
    }
}

/// Peak responses of the oscillator (period \[s\], damping ratio [-]) to
/// ground acceleration `accel` [m/s²] at time step `dt` \[s\].
///
/// Takes validated inputs: for an invalid period, damping, dt, options or
/// record (see [`Oscillator::new`], [`Oscillator::peaks`]) it returns
/// [`Peaks::NAN`] instead of panicking; use [`Oscillator`] to get the error.
pub fn peaks(accel: &[f64], dt: f64, period: f64, damping: f64, options: SpectrumOptions) -> Peaks {
    Oscillator::new(period, damping, dt).and_then(|o| o.peaks(accel, options)).unwrap_or(Peaks::NAN)
}

/// Exact relative displacement, relative velocity and absolute acceleration
/// at every sample time (period \[s\], damping ratio [-], dt \[s\], `accel`
/// [m/s²]).
///
/// Takes validated inputs: for invalid ones it returns NaN vectors of the
/// record's length instead of panicking; use [`Oscillator::history`] to get
/// the error.
pub fn history(accel: &[f64], dt: f64, period: f64, damping: f64) -> History {
    Oscillator::new(period, damping, dt).and_then(|o| o.history(accel)).unwrap_or_else(|_| {
        let nan = vec![f64::NAN; accel.len()];
        History { u: nan.clone(), v: nan.clone(), a_abs: nan }
    })
}

/// Lanes run in lockstep by [`spectrum_samples`].
const LANES: usize = 8;

/// Response spectrum of `record` for every period \[s\] and damping ratio
/// [-]; rows ordered damping-major (all periods of the first damping, then
/// the next). Errors on invalid periods, dampings, options or record.
pub fn spectrum(
    record: &Record,
    periods: &[f64],
    dampings: &[f64],
    options: SpectrumOptions,
) -> Result<Vec<SpectrumRow>, SpectrumError> {
    spectrum_samples(&record.acceleration, record.dt, periods, dampings, options)
}

/// [`spectrum`] of raw samples `accel` [m/s²] at time step `dt` \[s\].
pub fn spectrum_samples(
    accel: &[f64],
    dt: f64,
    periods: &[f64],
    dampings: &[f64],
    options: SpectrumOptions,
) -> Result<Vec<SpectrumRow>, SpectrumError> {
    check_samples(accel)?;
    let m = check_options(options)?;
    let mut oscillators = Vec::with_capacity(periods.len() * dampings.len());
    for &damping in dampings {
        for &period in periods {
            check_parameters(period, damping, dt)?;
            oscillators.push((period, damping));
        }
    }
    let h = dt / m as f64;
    let acc = Refined::new(accel, m as usize);
    // linear interpolation cannot exceed the samples: the rigid peaks are
    // those of the samples
    let rigid = rigid_peaks(accel, dt);
    let mut rows: Vec<SpectrumRow> =
        oscillators.iter().map(|&(period, damping)| SpectrumRow { damping, period, peaks: rigid }).collect();
    let moving: Vec<usize> = (0..oscillators.len()).filter(|&i| oscillators[i].0 > 0.0).collect();
    for chunk in moving.chunks(LANES) {
        // pad the last chunk with copies of its first oscillator
        let idx: [usize; LANES] = std::array::from_fn(|l| chunk.get(l).copied().unwrap_or(chunk[0]));
        let omega = idx.map(|i| 2.0 * std::f64::consts::PI / oscillators[i].0);
        let steps = idx.map(|i| step_coefficients(oscillators[i].0, oscillators[i].1, h));
        let w2 = omega.map(|w| w * w);
        let tzw: [f64; LANES] = std::array::from_fn(|l| 2.0 * oscillators[idx[l]].1 * omega[l]);
        let raw = run_lanes(&steps, &w2, &tzw, acc);
        for (l, &i) in chunk.iter().enumerate() {
            rows[i].peaks = to_peaks(&raw[l], omega[l], h);
        }
    }
    Ok(rows)
}

/// The most periods a range may have (a million periods is far finer than
/// any record resolves; the bound keeps a typo from exhausting memory).
pub const MAX_PERIODS: usize = 1_000_000;

/// `count` periods \[s\] from `from` to `to` (both included), spaced
/// logarithmically (`log`, needs from > 0) or linearly (needs from >= 0).
/// Needs finite bounds, to >= from and 1 <= count <= [`MAX_PERIODS`]
/// (count = 1 gives `[from]`, and then to must equal from).
pub fn period_range(from: f64, to: f64, count: usize, log: bool) -> Result<Vec<f64>, SpectrumError> {
    let bad = |m: String| Err(SpectrumError::Range(m));
    if !(from.is_finite() && to.is_finite()) {
        return bad(format!("bounds {from} s and {to} s must be finite"));
    }
    if log && from <= 0.0 {
        return bad(format!("a logarithmic range needs from > 0 (got {from} s)"));
    }
    if from < 0.0 {
        return bad(format!("periods must be >= 0 (got from = {from} s)"));
    }
    if to < from {
        return bad(format!("to = {to} s is less than from = {from} s"));
    }
    if count == 0 {
        return bad("count must be at least 1".into());
    }
    if count > MAX_PERIODS {
        return bad(format!("count = {count} is more than {MAX_PERIODS} periods"));
    }
    if count == 1 {
        if to != from {
            return bad(format!("count = 1 needs from = to (got {from} s and {to} s)"));
        }
        return Ok(vec![from]);
    }
    let last = (count - 1) as f64;
    let mut out: Vec<f64> = (0..count)
        .map(|i| {
            let f = i as f64 / last;
            if log {
                from * (to / from).powf(f)
            } else {
                from + (to - from) * f
            }
        })
        .collect();
    out[0] = from;
    out[count - 1] = to;
    Ok(out)
}
