//! A bridge given by its modes without its joints, exactly: the kept
//! modes' single-DOF responses (Nigam and Jennings) superposed at every
//! point of the modes file.

use quakejoint_motion::{history, History, Record};

use super::KeptMode;

/// A modal bridge alone under a record, by exact modal superposition: each
/// point's history and the base shear, at the record's sample times.
#[derive(Debug, Clone)]
pub struct ModalAlone {
    /// Each point of the modes file: displacement and velocity relative to
    /// the ground, absolute acceleration.
    pub points: Vec<History>,
    /// The base shear along the ground's direction \[N\].
    pub base_shear: Vec<f64>,
}

impl ModalAlone {
    /// Point `p`'s peak displacement \[m\] and absolute acceleration
    /// \[m/s^2\].
    pub fn peaks(&self, p: usize) -> [f64; 2] {
        let h = &self.points[p];
        [peak(&h.u), peak(&h.a_abs)]
    }

    /// Adds the static correction's ground part `r_p a_g(t)` to each
    /// point's displacement (`r`: [`crate::modal::ModalBridge::ground_residual`];
    /// none: nothing), under the record the superposition ran on.
    pub fn with_ground_static(mut self, r: Option<&[f64]>, record: &Record) -> Self {
        for (point, rp) in self.points.iter_mut().zip(r.unwrap_or_default()) {
            for (u, a) in point.u.iter_mut().zip(&record.acceleration) {
                *u += rp * a;
            }
        }
        self
    }

    /// The peak base shear \[N\].
    pub fn base_shear_peak(&self) -> f64 {
        peak(&self.base_shear)
    }
}

fn peak(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// The bridge alone under `record` along the ground's direction `dir`
/// (0: x, 1: y, through that direction's participation factors): each kept
/// mode's coordinate is `Gamma_i` times the exact single-DOF response at
/// its period and damping (Nigam and Jennings, one per mode), a point moves
/// by `sum_i phi_ip Gamma_i u_i` (its absolute acceleration: the ground's
/// plus the modes' relative accelerations so summed), and the base shear is
/// `sum_i Gamma_i (w_i^2 q_i + 2 zeta_i w_i q_i') = -sum_i Gamma_i^2
/// a_abs,i` with `a_abs,i` mode `i`'s single-DOF absolute acceleration.
pub fn modal_superposition(record: &Record, kept: &[KeptMode], dir: usize) -> ModalAlone {
    let n = record.acceleration.len();
    let points = kept.first().map_or(0, |k| k.shape.len());
    let mut start = record.acceleration.clone();
    if let Some(a) = start.first_mut() {
        // (the single-DOF histories start at rest: a_abs(0) = 0)
        *a = 0.0;
    }
    let mut out = ModalAlone {
        points: vec![History { u: vec![0.0; n], v: vec![0.0; n], a_abs: start }; points],
        base_shear: vec![0.0; n],
    };
    for k in kept {
        let gamma = k.gamma[dir];
        if gamma == 0.0 {
            continue;
        }
        let period = 2.0 * std::f64::consts::PI / k.omega;
        let h = history(&record.acceleration, record.dt, period, k.damping);
        for (j, a) in h.a_abs.iter().enumerate() {
            out.base_shear[j] -= gamma * gamma * a;
        }
        for (p, point) in out.points.iter_mut().enumerate() {
            let factor = k.shape[p] * gamma;
            if factor == 0.0 {
                continue;
            }
            for j in 0..n {
                point.u[j] += factor * h.u[j];
                point.v[j] += factor * h.v[j];
                if j > 0 {
                    point.a_abs[j] += factor * (h.a_abs[j] - record.acceleration[j]);
                }
            }
        }
    }
    out
}
