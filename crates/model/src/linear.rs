//! The bridge without the joint: a linear single-DOF oscillator under the
//! record, solved exactly (Nigam and Jennings' piecewise-linear step, from
//! the ground-motion crate). Same quantities as [`crate::run::RunResult`].

use std::time::Instant;

use quakejoint_motion::{history, peaks, History, Record, SpectrumOptions};

use crate::modal::KeptMode;
use crate::run::{Histories, RunResult};

/// Exact response of the bridge alone (circular frequency `omega` [rad/s],
/// damping ratio `damping`) at the record's sample times. Pass the record
/// over the run's window ([`crate::run::run_window`]) to compare with a
/// coupled run.
pub fn linear_response(record: &Record, omega: f64, damping: f64, histories: bool) -> RunResult {
    let start = Instant::now();
    let cpu = crate::resources::CpuClock::start();
    let period = 2.0 * std::f64::consts::PI / omega;
    let p = peaks(&record.acceleration, record.dt, period, damping, SpectrumOptions::default());
    let histories =
        histories.then(|| exact_histories(record, history(&record.acceleration, record.dt, period, damping)));
    RunResult {
        omega,
        sa: p.sa,
        t_sa: p.t_sa,
        psa: p.psa,
        sd: p.sd,
        t_sd: p.t_sd,
        sv: p.sv,
        t_sv: p.t_sv,
        wall_time_s: start.elapsed().as_secs_f64(),
        cpu_time_s: cpu.elapsed_s(),
        histories,
        ..not_computed(record)
    }
}

/// The histories of an exact solution `h` at the record's sample times
/// (the joint's series NaN).
fn exact_histories(record: &Record, h: History) -> Histories {
    let n = record.acceleration.len();
    Histories {
        t: (0..n).map(|j| j as f64 * record.dt).collect(),
        ag: record.acceleration.clone(),
        u: h.u,
        v: h.v,
        a_abs: h.a_abs,
        joint_force: vec![f64::NAN; n],
        friction_power: vec![f64::NAN; n],
        ..Histories::default()
    }
}

/// An exact solution of the bridge alone over `record`, before its
/// values: what it does not compute is NaN, its validity not checked.
fn not_computed(record: &Record) -> RunResult {
    RunResult {
        duration: record.duration(),
        exact_linear: true,
        pounding: crate::pounding::Pounding::not_computed(),
        // across the bridge: see the with-joint run's `sa_without`
        transverse: None,
        far: None,
        validity: crate::validity::Validity::not_checked("no joint: the exact linear solution of the bridge alone"),
        // not computed without the joint (NaN in every output)
        peak_joint_force: f64::NAN,
        peak_abutment_force: f64::NAN,
        peak_bushing_force: f64::NAN,
        peak_friction_force: f64::NAN,
        friction_energy: f64::NAN,
        damping_energy: f64::NAN,
        earthquake_work: f64::NAN,
        energy_error: f64::NAN,
        residuals: quakejoint_solver::ConstraintResiduals {
            position: f64::NAN,
            angle: f64::NAN,
            velocity: f64::NAN,
            angular_velocity: f64::NAN,
        },
        ..RunResult::default()
    }
}

/// Exact response of a modal bridge alone at the point `point` of its
/// modes file ([`modal_superposition`]); `omega` is the frequency the
/// result reports (the longest kept period's).
pub fn modal_response(record: &Record, kept: &[KeptMode], point: usize, histories: bool) -> RunResult {
    modal_result(record, kept[0].omega, modal_history(record, kept, point), histories)
}

/// The result of the bridge alone from its history `h` at a point
/// ([`modal_response`]), reporting the frequency `omega` [rad/s].
pub fn modal_result(record: &Record, omega: f64, h: History, histories: bool) -> RunResult {
    let start = Instant::now();
    let cpu = crate::resources::CpuClock::start();
    let peak = |x: &[f64]| {
        x.iter()
            .enumerate()
            .fold((0.0f64, 0.0), |(m, t), (j, &v)| if v.abs() > m { (v.abs(), j as f64 * record.dt) } else { (m, t) })
    };
    let ((sa, t_sa), (sd, t_sd), (sv, t_sv)) = (peak(&h.a_abs), peak(&h.u), peak(&h.v));
    RunResult {
        omega,
        sa,
        t_sa,
        psa: omega * omega * sd,
        sd,
        t_sd,
        sv,
        t_sv,
        wall_time_s: start.elapsed().as_secs_f64(),
        cpu_time_s: cpu.elapsed_s(),
        histories: histories.then(|| exact_histories(record, h)),
        ..not_computed(record)
    }
}

/// The history of [`modal_response`] at the record's sample times.
pub fn modal_history(record: &Record, kept: &[KeptMode], point: usize) -> History {
    modal_superposition(record, kept, 0).points.swap_remove(point)
}

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
