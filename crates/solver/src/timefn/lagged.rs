//! The motion of a support the ground motion reaches later (wave passage).

use std::sync::Arc;

use super::TimeSeries;
use crate::error::BuildError;

/// The displacement of a support that the ground motion reaches `lag`
/// seconds after the reference point, relative to the reference ground the
/// bodies' coordinates are measured from: `d(t) = u_g(t - lag) - u_g(t)`
/// \[m\], with its velocity and acceleration (`a_g(t - lag) - a_g(t)`).
///
/// `u_g` is the ground's displacement integrated exactly, twice, from its
/// acceleration `a_g` (a [`TimeSeries`], linear between samples, so `u_g` is
/// cubic between them): at rest until the first sample's time, then the
/// series' acceleration, after its end the series' value there (zero, or
/// the last sample held). A negative `lag` is a support the motion reaches
/// first. To first order `d = -lag v_g(t)`, so the record's velocity
/// matters and a displacement drift of its processing hardly does.
#[derive(Debug, Clone, PartialEq)]
pub struct LaggedGround {
    accel: Arc<TimeSeries>,
    lag: f64,
    /// Ground velocity at each sample \[m/s\].
    velocity: Vec<f64>,
    /// Ground displacement at each sample \[m\].
    displacement: Vec<f64>,
}

impl LaggedGround {
    /// The support's motion under the ground acceleration `accel` \[m/s^2\]
    /// reaching it `lag` \[s\] late.
    pub fn new(accel: Arc<TimeSeries>, lag: f64) -> Result<Self, BuildError> {
        if !lag.is_finite() {
            return Err(BuildError::InvalidParameter {
                what: "lagged ground motion".to_string(),
                name: "lag",
                value: lag,
                reason: "must be finite",
            });
        }
        let (t, a) = (accel.times(), accel.values());
        let mut velocity = vec![0.0; t.len()];
        let mut displacement = vec![0.0; t.len()];
        for j in 0..t.len().saturating_sub(1) {
            let h = t[j + 1] - t[j];
            let da = a[j + 1] - a[j];
            velocity[j + 1] = velocity[j] + a[j] * h + da * h / 2.0;
            displacement[j + 1] = displacement[j] + velocity[j] * h + a[j] * h * h / 2.0 + da * h * h / 6.0;
        }
        Ok(Self { accel, lag, velocity, displacement })
    }

    /// The lag \[s\].
    pub fn lag(&self) -> f64 {
        self.lag
    }

    /// The ground's displacement, velocity and acceleration at `t` (left
    /// limits at the samples).
    pub fn ground(&self, t: f64) -> [f64; 3] {
        let (times, a) = (self.accel.times(), self.accel.values());
        let n = times.len();
        if t <= times[0] {
            return [0.0; 3];
        }
        if t > times[n - 1] {
            let after = self.accel.value(t);
            let s = t - times[n - 1];
            let (u, v) = (self.displacement[n - 1], self.velocity[n - 1]);
            return [u + v * s + after * s * s / 2.0, v + after * s, after];
        }
        let j = times.partition_point(|&tj| tj < t).saturating_sub(1).min(n - 2);
        let (h, s) = (times[j + 1] - times[j], t - times[j]);
        let da = (a[j + 1] - a[j]) / h;
        let (u, v) = (self.displacement[j], self.velocity[j]);
        [u + v * s + a[j] * s * s / 2.0 + da * s * s * s / 6.0, v + a[j] * s + da * s * s / 2.0, a[j] + da * s]
    }

    /// `d`, `d'` and `d''` at `t`.
    pub fn eval(&self, t: f64) -> [f64; 3] {
        let (late, now) = (self.ground(t - self.lag), self.ground(t));
        [late[0] - now[0], late[1] - now[1], late[2] - now[2]]
    }

    /// First time strictly after `t` where `d''` has a kink or a jump: a
    /// sample time, or one `lag` after it.
    pub fn next_breakpoint(&self, t: f64) -> Option<f64> {
        let first = self.accel.times()[0];
        let here = if t < first { Some(first) } else { self.accel.next_breakpoint(t) };
        let late = if t - self.lag < first { Some(first) } else { self.accel.next_breakpoint(t - self.lag) };
        match (here, late.map(|b| b + self.lag).filter(|&b| b > t)) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A constant ground acceleration `a0` from t = 0: `u_g = a0 t^2 / 2`,
    /// so `d(t) = a0 ((t - L)^2 - t^2) / 2` once both have started, and
    /// `-a0 t^2 / 2` before the lagged one has; a sampled sine's double
    /// integral matches its closed form to the linear interpolation's error
    /// (`(w dt)^2 / 8`, 5e-6 at 1000 samples a cycle).
    #[test]
    fn lagged_ground_is_the_exact_double_integral() {
        let a0 = 2.0;
        let series = Arc::new(TimeSeries::uniform(0.0, 0.01, vec![a0; 1001]).unwrap());
        let g = LaggedGround::new(series, 0.25).unwrap();
        for t in [0.1, 0.3, 1.234, 9.99] {
            let d = g.eval(t);
            let late = if t > 0.25 { a0 * (t - 0.25) * (t - 0.25) / 2.0 } else { 0.0 };
            let late_v = if t > 0.25 { a0 * (t - 0.25) } else { 0.0 };
            assert!((d[0] - (late - a0 * t * t / 2.0)).abs() < 1e-12, "{t}: {d:?}");
            assert!((d[1] - (late_v - a0 * t)).abs() < 1e-12, "{t}: {d:?}");
        }
        assert!((g.next_breakpoint(0.1).unwrap() - 0.11).abs() < 1e-9);
        // the lag's breakpoints: 0.25 is the lagged start
        assert!((g.next_breakpoint(0.245).unwrap() - 0.25).abs() < 1e-12);
        assert!((g.next_breakpoint(0.25).unwrap() - 0.26).abs() < 1e-9);

        let w = 2.0 * std::f64::consts::PI;
        let dt = 1e-3;
        let values = (0..=2000).map(|j| (w * j as f64 * dt).sin()).collect();
        let g = LaggedGround::new(Arc::new(TimeSeries::uniform(0.0, dt, values).unwrap()), 0.0).unwrap();
        // u_g = (t - sin(w t) / w) / w for a_g = sin(w t) from rest
        let t = 1.7;
        let u = g.ground(t)[0];
        let exact = (t - (w * t).sin() / w) / w;
        assert!((u - exact).abs() < 1e-5 * exact.abs(), "{u} vs {exact}");
        assert_eq!(g.eval(t), [0.0; 3]);
    }
}
