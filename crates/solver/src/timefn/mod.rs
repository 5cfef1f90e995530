//! Functions of time: sampled series joined linearly, and a few analytic
//! shapes used for loads and kinematic drivers.
//!
//! Every function reports its breakpoints (times where a derivative jumps) so
//! that the integrator never steps across one. Values at a breakpoint are the
//! limit from the left: a step that ends at a breakpoint sees the segment
//! before it, the next step the segment after it.

use std::sync::Arc;

use crate::error::BuildError;

mod lagged;

pub use lagged::LaggedGround;

/// A signal sampled at increasing times and joined linearly between samples.
///
/// Before the first sample the value is the first sample; after the last
/// sample it is zero (ground-motion convention: the record has ended) unless
/// [`TimeSeries::hold_last`] is set.
#[derive(Debug, Clone, PartialEq)]
pub struct TimeSeries {
    /// Sample times [s], strictly increasing.
    times: Vec<f64>,
    /// Sample values (units of the quantity described).
    values: Vec<f64>,
    /// Uniform spacing [s] when the samples are equally spaced.
    uniform_dt: Option<f64>,
    /// Keep the last value after the end instead of dropping to zero.
    hold_last: bool,
}

impl TimeSeries {
    /// Equally spaced samples `values[j]` at `t0 + j*dt`.
    pub fn uniform(t0: f64, dt: f64, values: Vec<f64>) -> Result<Self, BuildError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(invalid("time series", "dt", dt, "must be positive and finite"));
        }
        check_values(&values)?;
        let times = (0..values.len()).map(|j| t0 + j as f64 * dt).collect();
        Ok(Self { times, values, uniform_dt: Some(dt), hold_last: false })
    }

    /// Samples at arbitrary strictly increasing times.
    pub fn from_points(times: Vec<f64>, values: Vec<f64>) -> Result<Self, BuildError> {
        if times.len() != values.len() {
            return Err(invalid("time series", "times", times.len() as f64, "must have as many entries as values"));
        }
        check_values(&values)?;
        for w in times.windows(2) {
            if w[1].is_nan() || w[1] <= w[0] || w[1].is_infinite() {
                return Err(invalid("time series", "times", w[1], "must be finite and strictly increasing"));
            }
        }
        Ok(Self { times, values, uniform_dt: None, hold_last: false })
    }

    /// Keep the last sample's value after the end of the series.
    pub fn hold_last(mut self, hold: bool) -> Self {
        self.hold_last = hold;
        self
    }

    /// Sample times \[s\].
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// Sample values.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Time of the last sample \[s\].
    pub fn end_time(&self) -> f64 {
        *self.times.last().expect("non-empty by construction")
    }

    /// Index `j` of the segment `(t_j, t_{j+1}]` that contains `t`
    /// (`None` before the first or after the last sample).
    fn segment(&self, t: f64) -> Option<usize> {
        let n = self.times.len();
        if n < 2 || t <= self.times[0] || t > self.times[n - 1] {
            return None;
        }
        let j = match self.uniform_dt {
            Some(dt) => {
                let x = (t - self.times[0]) / dt;
                let mut j = (x.ceil() as usize).saturating_sub(1).min(n - 2);
                // Guard against rounding at sample times: keep (t_j, t_{j+1}].
                while j > 0 && t <= self.times[j] {
                    j -= 1;
                }
                while j + 2 < n && t > self.times[j + 1] {
                    j += 1;
                }
                j
            }
            None => self.times.partition_point(|&tj| tj < t).saturating_sub(1).min(n - 2),
        };
        Some(j)
    }

    /// Value at time `t` (left limit at breakpoints).
    pub fn value(&self, t: f64) -> f64 {
        match self.segment(t) {
            Some(j) => {
                let (t0, t1) = (self.times[j], self.times[j + 1]);
                let s = (t - t0) / (t1 - t0);
                self.values[j] + s * (self.values[j + 1] - self.values[j])
            }
            None if t <= self.times[0] => self.values[0],
            None if self.hold_last => *self.values.last().expect("non-empty"),
            None => 0.0,
        }
    }

    /// Slope at time `t` (left limit at breakpoints).
    pub fn slope(&self, t: f64) -> f64 {
        match self.segment(t) {
            Some(j) => (self.values[j + 1] - self.values[j]) / (self.times[j + 1] - self.times[j]),
            None => 0.0,
        }
    }

    /// First breakpoint strictly after `t` (a sample time, or the end).
    pub fn next_breakpoint(&self, t: f64) -> Option<f64> {
        let n = self.times.len();
        if t >= self.times[n - 1] {
            return None;
        }
        let k = match self.uniform_dt {
            Some(dt) => {
                let mut k = ((t - self.times[0]) / dt).floor().max(0.0) as usize;
                while k < n && self.times[k] <= t {
                    k += 1;
                }
                while k > 0 && self.times[k - 1] > t {
                    k -= 1;
                }
                k
            }
            None => self.times.partition_point(|&tj| tj <= t),
        };
        self.times.get(k).copied()
    }
}

fn check_values(values: &[f64]) -> Result<(), BuildError> {
    if values.is_empty() {
        return Err(invalid("time series", "values", 0.0, "needs at least one sample"));
    }
    if let Some((j, v)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(BuildError::InvalidParameter {
            what: format!("time series sample {j}"),
            name: "value",
            value: *v,
            reason: "must be finite",
        });
    }
    Ok(())
}

fn invalid(what: &str, name: &'static str, value: f64, reason: &'static str) -> BuildError {
    BuildError::InvalidParameter { what: what.to_string(), name, value, reason }
}

/// A scalar function of time with its first two derivatives and breakpoints.
#[derive(Debug, Clone, PartialEq)]
pub enum TimeFunction {
    /// f(t) = value.
    Constant(f64),
    /// f(t) = value0 + rate * t.
    Linear {
        /// Value at t = 0.
        value0: f64,
        /// Rate [unit/s].
        rate: f64,
    },
    /// f(t) = offset + amplitude * sin(omega t + phase).
    Harmonic {
        /// Amplitude.
        amplitude: f64,
        /// Circular frequency [rad/s].
        omega: f64,
        /// Phase \[rad\].
        phase: f64,
        /// Constant offset.
        offset: f64,
    },
    /// A sampled series joined linearly (second derivative zero between samples).
    Series(Arc<TimeSeries>),
    /// A triangle wave between -amplitude and +amplitude at constant speed,
    /// starting at 0 at t = 0 and rising, with its corners rounded by a causal
    /// moving average of width `blend` (so position and velocity are
    /// continuous and the acceleration is piecewise constant). The corner
    /// amplitude is raised by `speed*blend/4` so that the rounded wave peaks at
    /// exactly +/- amplitude.
    SmoothTriangle(SmoothTriangle),
    /// A support reached by the ground motion later (wave passage).
    LaggedGround(Arc<LaggedGround>),
}

/// Parameters of [`TimeFunction::SmoothTriangle`].
#[derive(Debug, Clone, PartialEq)]
pub struct SmoothTriangle {
    /// Peak value reached (after rounding).
    pub amplitude: f64,
    /// Speed of the straight parts [unit/s].
    pub speed: f64,
    /// Width of the rounding window \[s\]; must be shorter than a straight part.
    pub blend: f64,
}

impl SmoothTriangle {
    /// Validates the parameters.
    pub fn new(amplitude: f64, speed: f64, blend: f64) -> Result<Self, BuildError> {
        if !(amplitude > 0.0 && amplitude.is_finite()) {
            return Err(invalid("triangle wave", "amplitude", amplitude, "must be positive"));
        }
        if !(speed > 0.0 && speed.is_finite()) {
            return Err(invalid("triangle wave", "speed", speed, "must be positive"));
        }
        if !(blend > 0.0 && blend < 2.0 * amplitude / speed) {
            return Err(invalid(
                "triangle wave",
                "blend",
                blend,
                "must be positive and shorter than one straight part (2*amplitude/speed)",
            ));
        }
        Ok(Self { amplitude, speed, blend })
    }

    /// Corner amplitude of the underlying sharp triangle.
    fn corner(&self) -> f64 {
        self.amplitude + self.speed * self.blend / 4.0
    }

    /// Period of the wave \[s\].
    pub fn period(&self) -> f64 {
        4.0 * self.corner() / self.speed
    }

    /// Sharp triangle (zero before t = 0), its antiderivative and slope.
    fn sharp(&self, t: f64) -> (f64, f64, f64) {
        if t <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        let a = self.corner();
        let v = self.speed;
        let p = self.period();
        let quarter = p / 4.0;
        // Antiderivative over one full period is zero (odd symmetry).
        let cycles = (t / p).floor();
        let s = t - cycles * p;
        // Piecewise on [0,q], [q,3q], [3q,4q].
        let (f, big_f, slope) = if s <= quarter {
            (v * s, 0.5 * v * s * s, v)
        } else if s <= 3.0 * quarter {
            let u = s - quarter;
            let f = a - v * u;
            let f_q = 0.5 * v * quarter * quarter;
            (f, f_q + a * u - 0.5 * v * u * u, -v)
        } else {
            let u = s - 3.0 * quarter;
            let f = -a + v * u;
            let f_q = 0.5 * v * quarter * quarter;
            let f_3q = f_q + a * 2.0 * quarter - 0.5 * v * 4.0 * quarter * quarter;
            (f, f_3q - a * u + 0.5 * v * u * u, v)
        };
        (f, big_f, slope)
    }

    fn eval(&self, t: f64) -> [f64; 3] {
        let w = self.blend;
        let (f1, big1, s1) = self.sharp(t);
        let (f0, big0, s0) = self.sharp(t - w);
        [(big1 - big0) / w, (f1 - f0) / w, (s1 - s0) / w]
    }

    /// Corners of the sharp wave at 0, q, 3q, 5q, ... and the same shifted by `blend`.
    fn next_breakpoint(&self, t: f64) -> Option<f64> {
        let quarter = self.period() / 4.0;
        let next_corner = |tt: f64| -> f64 {
            if tt < 0.0 {
                return 0.0;
            }
            if tt < quarter {
                return quarter;
            }
            // corners at quarter*(1 + 2k)
            let k = ((tt - quarter) / (2.0 * quarter)).floor() + 1.0;
            let mut c = quarter * (1.0 + 2.0 * k);
            if c <= tt {
                c += 2.0 * quarter;
            }
            c
        };
        let a = next_corner(t);
        let b = next_corner(t - self.blend) + self.blend;
        let mut c = a.min(b);
        if c <= t {
            c = a.max(b);
        }
        Some(c)
    }
}

impl TimeFunction {
    /// Value, first and second derivative at `t` (left limits at breakpoints).
    pub fn eval(&self, t: f64) -> [f64; 3] {
        match self {
            TimeFunction::Constant(c) => [*c, 0.0, 0.0],
            TimeFunction::Linear { value0, rate } => [value0 + rate * t, *rate, 0.0],
            TimeFunction::Harmonic { amplitude, omega, phase, offset } => {
                let (s, c) = (omega * t + phase).sin_cos();
                [offset + amplitude * s, amplitude * omega * c, -amplitude * omega * omega * s]
            }
            TimeFunction::Series(s) => [s.value(t), s.slope(t), 0.0],
            TimeFunction::SmoothTriangle(tri) => tri.eval(t),
            TimeFunction::LaggedGround(g) => g.eval(t),
        }
    }

    /// Value at `t`.
    pub fn value(&self, t: f64) -> f64 {
        match self {
            TimeFunction::Constant(c) => *c,
            TimeFunction::Series(s) => s.value(t),
            _ => self.eval(t)[0],
        }
    }

    /// First breakpoint strictly after `t`, if any.
    pub fn next_breakpoint(&self, t: f64) -> Option<f64> {
        match self {
            TimeFunction::Series(s) => s.next_breakpoint(t),
            TimeFunction::SmoothTriangle(tri) => tri.next_breakpoint(t),
            TimeFunction::LaggedGround(g) => g.next_breakpoint(t),
            _ => None,
        }
    }

    /// Checks that the parameters are finite.
    pub(crate) fn validate(&self, what: &str) -> Result<(), BuildError> {
        let check = |name: &'static str, v: f64| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(BuildError::InvalidParameter { what: what.to_string(), name, value: v, reason: "must be finite" })
            }
        };
        match self {
            TimeFunction::Constant(c) => check("value", *c),
            TimeFunction::Linear { value0, rate } => {
                check("value0", *value0)?;
                check("rate", *rate)
            }
            TimeFunction::Harmonic { amplitude, omega, phase, offset } => {
                check("amplitude", *amplitude)?;
                check("omega", *omega)?;
                check("phase", *phase)?;
                check("offset", *offset)
            }
            TimeFunction::Series(_) | TimeFunction::SmoothTriangle(_) | TimeFunction::LaggedGround(_) => Ok(()),
        }
    }
}

impl From<f64> for TimeFunction {
    fn from(value: f64) -> Self {
        TimeFunction::Constant(value)
    }
}

impl From<TimeSeries> for TimeFunction {
    fn from(series: TimeSeries) -> Self {
        TimeFunction::Series(Arc::new(series))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_is_linear_between_samples_and_zero_after_end() {
        let s = TimeSeries::uniform(0.0, 0.5, vec![1.0, 3.0, -1.0]).unwrap();
        assert_eq!(s.value(0.0), 1.0);
        assert!((s.value(0.25) - 2.0).abs() < 1e-15);
        assert_eq!(s.value(0.5), 3.0);
        assert!((s.value(0.75) - 1.0).abs() < 1e-15);
        assert_eq!(s.value(1.0), -1.0);
        assert_eq!(s.value(1.0 + 1e-12), 0.0);
        assert_eq!(s.slope(0.5), 4.0, "left limit at a sample");
        assert_eq!(s.slope(0.5 + 1e-9), -8.0);
        assert_eq!(s.next_breakpoint(0.0), Some(0.5));
        assert_eq!(s.next_breakpoint(0.5), Some(1.0));
        assert_eq!(s.next_breakpoint(0.49999), Some(0.5));
        assert_eq!(s.next_breakpoint(1.0), None);
    }

    #[test]
    fn uniform_and_general_series_agree() {
        let vals: Vec<f64> = (0..50).map(|j| (j as f64 * 0.37).sin()).collect();
        let u = TimeSeries::uniform(0.0, 0.01, vals.clone()).unwrap();
        let g = TimeSeries::from_points((0..50).map(|j| j as f64 * 0.01).collect(), vals).unwrap();
        for k in 0..600 {
            let t = k as f64 * 0.000_83;
            assert!((u.value(t) - g.value(t)).abs() < 1e-12, "t = {t}");
            assert_eq!(u.next_breakpoint(t).is_some(), g.next_breakpoint(t).is_some());
            if let (Some(a), Some(b)) = (u.next_breakpoint(t), g.next_breakpoint(t)) {
                assert!((a - b).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn smooth_triangle_peaks_at_amplitude_and_is_c1() {
        let tri = SmoothTriangle::new(0.2, 0.2, 0.1).unwrap();
        let f = TimeFunction::SmoothTriangle(tri.clone());
        let p = tri.period();
        let mut max = f64::MIN;
        let mut min = f64::MAX;
        let n = 200_000;
        let mut prev = f.eval(0.0);
        assert_eq!(prev, [0.0, 0.0, 0.0]);
        for k in 1..=n {
            let t = 2.0 * p * k as f64 / n as f64;
            let e = f.eval(t);
            max = max.max(e[0]);
            min = min.min(e[0]);
            // velocity continuous: small change per tiny step
            assert!((e[1] - prev[1]).abs() < 0.2 * 2.0 / 0.1 * (2.0 * p / n as f64) + 1e-9);
            // finite-difference check of the derivative
            let dt = 1e-7;
            let fd = (f.eval(t + dt)[0] - f.eval(t - dt)[0]) / (2.0 * dt);
            assert!((fd - e[1]).abs() < 1e-5, "t={t} fd={fd} d={}", e[1]);
            prev = e;
        }
        assert!((max - 0.2).abs() < 1e-6, "max {max}");
        assert!((min + 0.2).abs() < 1e-6, "min {min}");
        // breakpoints are increasing and separated
        let mut t = 0.0;
        let mut last = -1.0;
        for _ in 0..10 {
            let b = f.next_breakpoint(t).unwrap();
            assert!(b > t && b > last);
            last = b;
            t = b;
        }
    }
}
