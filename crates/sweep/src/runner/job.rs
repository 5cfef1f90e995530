//! One job of a sweep: its coupled run (or the failure a test injects)
//! into a row of results, and the spectra without the joint that every
//! job is set against.

use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use quakejoint_model::run::{RunOptions, RunResult};
use quakejoint_model::runspec::{Reference, RunSpec};
use quakejoint_model::ModelError;
use quakejoint_solver::SolverError;

use crate::error::SweepError;
use crate::plan::{Job, Plan};
use crate::results::{status, JobResult, JointJobResult, Results, FIELDS};

/// The exact linear spectra of every record, damping and period; for a
/// bridge given by its modes, the exact modal superposition at the first
/// joint's point of every case, record and period scale
/// ([`quakejoint_model::scenario::Scenario::alone`]).
pub fn without_joint(plan: &Plan, results: &mut Results) -> Result<(), SweepError> {
    let [_, nr, nz, nt] = plan.dims();
    if let Some(m) = &plan.modal {
        for (c, case) in plan.cases.iter().enumerate() {
            for (r, rec) in plan.records.iter().enumerate() {
                // over the runs' window, which every case shares (Plan::new)
                let reference = Reference::for_run(&case.config, &rec.record, &rec.record);
                for t in 0..nt {
                    let spec = RunSpec::new(case.config.clone(), &m.overrides(t))?;
                    let alone = spec.scenario.alone(reference.window(), false);
                    let at = ((c * nr + r) * nz) * nt + t;
                    for (k, v) in [alone.sa, alone.psa, alone.sd, alone.sv].into_iter().enumerate() {
                        results.without[k][at] = v;
                    }
                }
            }
        }
        return Ok(());
    }
    for (r, rec) in plan.records.iter().enumerate() {
        // over the runs' window, which every case shares (Plan::new)
        let reference = Reference::for_run(&plan.cases[0].config, &rec.record, &rec.record);
        let rows = reference
            .spectrum(&plan.periods, &plan.damping)
            .map_err(|e| SweepError::Config { field: "sweep".into(), message: e.to_string() })?;
        for (i, row) in rows.iter().enumerate() {
            let (z, t) = (i / nt, i % nt);
            let at = (r * nz + z) * nt + t;
            let p = &row.peaks;
            for (k, v) in [p.sa, p.psa, p.sd, p.sv].into_iter().enumerate() {
                results.without[k][at] = v;
            }
        }
    }
    Ok(())
}

/// The job's values in [`FIELDS`] order: the run's fields marked `per_job`.
fn values_of(r: &RunResult) -> Vec<f64> {
    quakejoint_model::fields::FIELDS.iter().filter(|f| f.per_job).map(|f| (f.value)(r)).collect()
}

/// Runs one job; `None` if `cancel` stopped it.
pub fn run_job(
    plan: &Plan,
    index: usize,
    progress: Option<quakejoint_model::run::ProgressFn>,
    cancel: Option<Arc<AtomicBool>>,
) -> Option<JobResult> {
    let job = plan.job(index);
    let Job { case, record, period, .. } = job;
    // the job's period and damping from the grid (a bridge given by its
    // modes: its period scale), applied and checked as every front end's
    // overrides are
    let overrides = plan.overrides(job);
    let want_history = plan.history_periods.contains(&period);
    let rec = &plan.records[record].record;
    let options = RunOptions { histories: want_history, progress, cancel, ..RunOptions::default() };
    let outcome = if crate::fault::job_fails(index) {
        Err(ModelError::Solver(SolverError::StepFailed {
            time: 0.0,
            h: 0.0,
            attempts: 0,
            cause: quakejoint_solver::StepFailure::NonFinite,
        }))
    } else {
        RunSpec::new(plan.cases[case].config.clone(), &overrides)
            .and_then(|spec| spec.run(rec, plan.record_y.as_ref().map(|r| &r.record), &options))
    };
    match outcome {
        Ok(mut r) => {
            let history = r.histories.take().map(|h| h.for_sweep());
            Some(JobResult {
                job: index as u32,
                status: status::OK,
                message: String::new(),
                values: values_of(&r),
                validity: r.validity.flags.0,
                findings: r.validity.message(),
                history,
                joints: r
                    .joints
                    .iter()
                    .map(|j| JointJobResult {
                        values: j.scalars().iter().map(|&(_, v, _)| v).collect(),
                        validity: j.validity.flags.0,
                    })
                    .collect(),
            })
        }
        Err(ModelError::Interrupted { .. }) => None,
        Err(e) => {
            let code = match &e {
                ModelError::Solver(SolverError::WallClockLimit { .. } | SolverError::StepLimit { .. }) => status::LIMIT,
                ModelError::Solver(_) => status::FAILED,
                _ => status::INVALID,
            };
            Some(JobResult {
                job: index as u32,
                status: code,
                message: e.to_string(),
                values: vec![f64::NAN; FIELDS.len()],
                validity: quakejoint_model::validity::Flags::NOT_CHECKED.0,
                findings: "not_checked: the job did not finish".to_string(),
                history: None,
                joints: Vec::new(),
            })
        }
    }
}
