//! The bridge without the joint: a linear single-DOF oscillator under the
//! record, solved exactly (Nigam and Jennings' piecewise-linear step, from
//! the ground-motion crate). Same quantities as [`crate::run::RunResult`].

use std::time::Instant;

use quakejoint_motion::{history, peaks, History, Record, SpectrumOptions};

use crate::bridge::{Bridge, Modal, SingleDof};
use crate::modal::{modal_superposition, KeptMode, ModalAlone};
use crate::run::{Histories, RunResult};
use crate::scenario::Scenario;

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

impl SingleDof {
    /// The deck without its joints under `window` (the ground motion along
    /// x over a run's window), exactly.
    pub fn alone(&self, window: &Record, histories: bool) -> RunResult {
        linear_response(window, self.omega, self.damping, histories)
    }

    /// Its absolute acceleration \[m/s^2\] without the joints at the first
    /// `samples` sample times of `window` (NaN past it).
    pub fn a_abs_alone(&self, window: &Record, samples: usize) -> Vec<f64> {
        let mut a = history(&window.acceleration, window.dt, self.period, self.damping).a_abs;
        a.resize(samples, f64::NAN);
        a
    }
}

impl Modal {
    /// The bridge without its joints at `point` of its modes file, from
    /// `every` point's exact superposition under `window`
    /// ([`Modal::superposition`]), reported at the longest kept period.
    pub fn alone_at(&self, window: &Record, every: &ModalAlone, point: usize, histories: bool) -> RunResult {
        modal_result(window, self.kept[0].omega, every.points[point].clone(), histories)
    }
}

impl Bridge {
    /// The bridge without its joints under `window` (the ground motion
    /// along x over a run's window), exactly, at `point` (the first joint's
    /// deck point; a single-DOF deck has one): one implementation per
    /// variant.
    pub fn alone(&self, window: &Record, point: usize, histories: bool) -> RunResult {
        match self {
            Bridge::SingleDof(b) => b.alone(window, histories),
            Bridge::Modal(m) => m.alone_at(window, &m.superposition(window, 0), point, histories),
        }
    }
}

impl Scenario {
    /// The bridge without its joints under `window` (the ground motion
    /// along x over the run's window), at the first joint's deck point
    /// ([`Bridge::alone`]).
    pub fn alone(&self, window: &Record, histories: bool) -> RunResult {
        self.bridge.alone(window, self.first_point(), histories)
    }
}
