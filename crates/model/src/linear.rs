//! The bridge without the joint: a linear single-DOF oscillator under the
//! record, solved exactly (Nigam and Jennings' piecewise-linear step, from
//! the ground-motion crate). Same quantities as [`crate::run::RunResult`].

use std::time::Instant;

use quakejoint_motion::{history, peaks, Record, SpectrumOptions};

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
