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
    let histories = histories.then(|| {
        let h = history(&record.acceleration, record.dt, period, damping);
        let n = record.acceleration.len();
        Histories {
            t: (0..n).map(|j| j as f64 * record.dt).collect(),
            ag: record.acceleration.clone(),
            u: h.u,
            v: h.v,
            a_abs: h.a_abs,
            joint_force: vec![f64::NAN; n],
            friction_power: vec![f64::NAN; n],
            center_beam_dx: Vec::new(),
            subgaps: Vec::new(),
            subgaps_wide: Vec::new(),
            contact_force: Vec::new(),
            impacts: Vec::new(),
            ..Histories::default()
        }
    });
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
        duration: record.duration(),
        histories,
        exact_linear: true,
        pounding: crate::pounding::Pounding::not_computed(),
        // across the bridge: see the with-joint run's `sa_without`
        transverse: None,
        far: None,
        validity: crate::validity::Validity::not_checked("no joint: the exact linear solution of the bridge alone"),
        // not computed without the joint (NaN in every output)
        peak_joint_force: f64::NAN,
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
/// modes file: each kept mode's coordinate is `Gamma_i` times the exact
/// single-DOF response at its period and damping, and the point moves by
/// `sum_i phi_ip Gamma_i u_i` (its absolute acceleration: the ground's plus
/// the modes' relative accelerations so summed). `omega` is the frequency
/// the result reports (the longest kept period's).
pub fn modal_response(record: &Record, kept: &[KeptMode], point: usize, histories: bool) -> RunResult {
    let start = Instant::now();
    let cpu = crate::resources::CpuClock::start();
    let h = modal_history(record, kept, point);
    let peak = |x: &[f64]| {
        x.iter()
            .enumerate()
            .fold((0.0f64, 0.0), |(m, t), (j, &v)| if v.abs() > m { (v.abs(), j as f64 * record.dt) } else { (m, t) })
    };
    let ((sa, t_sa), (sd, t_sd), (sv, t_sv)) = (peak(&h.a_abs), peak(&h.u), peak(&h.v));
    let omega = kept[0].omega;
    let n = record.acceleration.len();
    let histories = histories.then(|| Histories {
        t: (0..n).map(|j| j as f64 * record.dt).collect(),
        ag: record.acceleration.clone(),
        u: h.u,
        v: h.v,
        a_abs: h.a_abs,
        joint_force: vec![f64::NAN; n],
        friction_power: vec![f64::NAN; n],
        ..Histories::default()
    });
    let sdof = linear_response(record, omega, kept[0].damping, false);
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
        histories,
        ..sdof
    }
}

/// The history of [`modal_response`] at the record's sample times.
pub fn modal_history(record: &Record, kept: &[KeptMode], point: usize) -> History {
    modal_history_in(record, kept, point, 0)
}

/// [`modal_history`] under a record along the ground's direction `dir`
/// (0: x, 1: y, through the participation factors of that direction), at
/// a point of the modes file along that direction.
pub fn modal_history_in(record: &Record, kept: &[KeptMode], point: usize, dir: usize) -> History {
    let n = record.acceleration.len();
    let mut out = History { u: vec![0.0; n], v: vec![0.0; n], a_abs: record.acceleration.clone() };
    if let Some(a) = out.a_abs.first_mut() {
        // (the single-DOF histories start at rest: a_abs(0) = 0)
        *a = 0.0;
    }
    for k in kept {
        let factor = k.shape[point] * k.gamma[dir];
        if factor == 0.0 {
            continue;
        }
        let period = 2.0 * std::f64::consts::PI / k.omega;
        let h = history(&record.acceleration, record.dt, period, k.damping);
        for j in 0..n {
            out.u[j] += factor * h.u[j];
            out.v[j] += factor * h.v[j];
            if j > 0 {
                out.a_abs[j] += factor * (h.a_abs[j] - record.acceleration[j]);
            }
        }
    }
    out
}

/// The bridge alone at every point of its modes file, by exact modal
/// superposition ([`modal_history`]): each point's peak displacement \[m\]
/// and absolute acceleration \[m/s^2\], and the peak base shear \[N\],
/// `|sum_i Gamma_i (w_i^2 q_i + 2 zeta_i w_i q_i')| = |sum_i Gamma_i^2
/// a_abs,i|` with `a_abs,i` the single-DOF absolute acceleration of mode `i`.
pub fn modal_alone(record: &Record, kept: &[KeptMode], points: usize) -> (Vec<[f64; 2]>, f64) {
    let n = record.acceleration.len();
    let mut u = vec![vec![0.0; n]; points];
    let mut a = vec![vec![0.0; n]; points];
    let mut shear = vec![0.0; n];
    for k in kept {
        let period = 2.0 * std::f64::consts::PI / k.omega;
        let h = history(&record.acceleration, record.dt, period, k.damping);
        let g2 = k.gamma[0] * k.gamma[0];
        for j in 0..n {
            let rel = if j > 0 { h.a_abs[j] - record.acceleration[j] } else { 0.0 };
            shear[j] -= g2 * h.a_abs[j];
            for p in 0..points {
                let f = k.shape[p] * k.gamma[0];
                u[p][j] += f * h.u[j];
                a[p][j] += f * rel;
            }
        }
    }
    let peak = |x: &[f64]| x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let peaks = (0..points)
        .map(|p| {
            let abs: Vec<f64> = a[p]
                .iter()
                .zip(&record.acceleration)
                .enumerate()
                .map(|(j, (r, g))| if j > 0 { r + g } else { 0.0 })
                .collect();
            [peak(&u[p]), peak(&abs)]
        })
        .collect();
    (peaks, peak(&shear))
}
