//! The bridge without the joint: a linear single-DOF oscillator under the
//! record, solved exactly (Nigam and Jennings' piecewise-linear step, from
//! the ground-motion crate). Same quantities as [`crate::run::RunResult`].

use std::time::Instant;

use quakejoint_motion::{history, peaks, Record, SpectrumOptions};

use crate::run::{Histories, RunResult};

/// Exact response of the bridge alone (circular frequency `omega` [rad/s],
/// damping ratio `damping`) at the record's sample times.
pub fn linear_response(record: &Record, omega: f64, damping: f64, histories: bool) -> RunResult {
    let start = Instant::now();
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
            joint_force: vec![0.0; n],
            friction_power: vec![0.0; n],
            center_beam_dx: Vec::new(),
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
        duration: record.duration(),
        histories,
        ..RunResult::default()
    }
}
