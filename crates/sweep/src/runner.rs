//! Running a sweep: jobs on a rayon pool, results over a channel to one
//! writer thread that journals them (fsync per job), keeps the arrays and
//! checkpoints the HDF5 file.
//!
//! Each job runs single-threaded (the solver's linear algebra never spawns
//! threads), so a job's numbers depend only on its inputs: the results are
//! bit-identical whatever the thread count, the job order or the sharding.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use crossbeam_channel::{unbounded, Receiver};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use quakejoint_model::run::{simulate_records, RunOptions, RunResult};
use quakejoint_model::ModelError;
use quakejoint_motion::{history, spectrum, SpectrumOptions};
use quakejoint_solver::SolverError;

use crate::error::{io_err, SweepError};
use crate::journal::{Header, Journal};
use crate::plan::{Job, Plan};
use crate::results::{status, JobHistory, JobResult, Results, FIELDS};
use crate::sweep_h5::{write_sweep, StoredRecord, SweepFile};

/// Version of the journal format.
const JOURNAL_SCHEMA: u32 = 1;

/// How to run a sweep.
#[derive(Debug, Clone)]
pub struct SweepOptions {
    /// The HDF5 output (the journal is `<output>.journal`).
    pub output: PathBuf,
    /// Worker threads (None: all cores).
    pub threads: Option<usize>,
    /// Continue from the journal.
    pub resume: bool,
    /// Run only shard `k` of `n` (1-based).
    pub shard: Option<(usize, usize)>,
    /// Show progress bars on stderr.
    pub progress: bool,
}

/// What a sweep did.
#[derive(Debug, Clone)]
pub struct Summary {
    /// Jobs in this run's scope (the shard, or all).
    pub jobs: usize,
    /// Of these, finished before this run (from the journal).
    pub resumed: usize,
    /// Run now.
    pub ran: usize,
    /// Failed jobs: (case, record, damping, period, message).
    pub failed: Vec<(String, String, f64, f64, String)>,
    /// Wall-clock time [s].
    pub wall_time_s: f64,
    /// The HDF5 output.
    pub output: PathBuf,
    /// The journal.
    pub journal: PathBuf,
    /// Peak resident memory of the process [MB] (Linux; for cluster job
    /// requests).
    pub peak_memory_mb: Option<f64>,
}

/// `<output>.journal`.
pub fn journal_path(output: &Path) -> PathBuf {
    let mut s = output.as_os_str().to_owned();
    s.push(".journal");
    PathBuf::from(s)
}

/// Checks that files can be created beside `output` (before any job runs).
pub fn check_writable(output: &Path) -> Result<(), SweepError> {
    let probe = {
        let mut s = output.as_os_str().to_owned();
        s.push(format!(".probe-{}", std::process::id()));
        PathBuf::from(s)
    };
    std::fs::write(&probe, b"probe").map_err(|e| SweepError::Io {
        path: output.display().to_string(),
        message: format!("the output location is not writable: {e}"),
    })?;
    std::fs::remove_file(&probe).map_err(|e| io_err(&probe, e))
}

/// The journal header of a plan.
pub fn header(plan: &Plan, shard: Option<(usize, usize)>) -> Header {
    Header {
        schema: JOURNAL_SCHEMA,
        program_version: crate::h5::VERSION.to_string(),
        config_sha256: plan.config_sha256.clone(),
        records: plan.records.iter().chain(&plan.record_y).map(|r| (r.record.name.clone(), r.sha256.clone())).collect(),
        jobs: plan.job_count() as u64,
        shard: shard.map(|(k, n)| (k as u32, n as u32)),
    }
}

/// The file skeleton of a plan (results not yet filled).
pub fn sweep_file(plan: &Plan, shard: Option<(usize, usize)>) -> SweepFile {
    SweepFile {
        config: plan.config_text.clone(),
        shard: shard.map_or("all".to_string(), |(k, n)| format!("{k}/{n}")),
        periods: plan.periods.clone(),
        damping: plan.damping.clone(),
        cases: plan.cases.iter().map(|c| c.name.clone()).collect(),
        records: plan
            .records
            .iter()
            .map(|r| StoredRecord {
                name: r.record.name.clone(),
                source: r.record.source.clone(),
                dt: r.record.dt,
                scale: r.record.scale,
                pga: r.record.pga(),
                acceleration: r.record.acceleration.clone(),
            })
            .collect(),
        results: Results::new(plan.dims()),
    }
}

/// The exact linear spectra of every record, damping and period.
pub fn without_joint(plan: &Plan, results: &mut Results) -> Result<(), SweepError> {
    let [_, _, nz, nt] = plan.dims();
    for (r, rec) in plan.records.iter().enumerate() {
        let rows = spectrum(&rec.record, &plan.periods, &plan.damping, SpectrumOptions::default())
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

fn values_of(r: &RunResult) -> Vec<f64> {
    let opt = |x: Option<f64>| x.unwrap_or(f64::NAN);
    let s = &r.stats;
    let v = vec![
        r.sa,
        r.psa,
        r.sd,
        r.sv,
        r.t_sa,
        r.t_sd,
        r.t_sv,
        r.peak_joint_force,
        r.peak_bushing_force,
        r.peak_friction_force,
        r.friction_energy,
        r.damping_energy,
        r.earthquake_work,
        opt(r.min_subgap),
        opt(r.max_subgap),
        opt(r.max_subgap_deviation),
        r.energy_error,
        r.max_constraint_residual(),
        s.steps as f64,
        s.rejected as f64,
        s.failed_attempts as f64,
        s.newton_iterations as f64,
        s.factorizations as f64,
        r.wall_time_s,
    ];
    debug_assert_eq!(v.len(), FIELDS.len());
    v
}

/// Runs one job.
pub fn run_job(plan: &Plan, index: usize, progress: Option<quakejoint_model::run::ProgressFn>) -> JobResult {
    let job = plan.job(index);
    let Job { case, record, damping, period } = job;
    let mut config = plan.cases[case].config.clone();
    config.bridge.damping = plan.damping[damping];
    let t = plan.periods[period];
    let omega = 2.0 * std::f64::consts::PI / t;
    let want_history = plan.history_periods.contains(&period);
    let rec = &plan.records[record].record;
    let options = RunOptions { omega: Some(omega), histories: want_history, progress };
    match simulate_records(&config, rec, plan.record_y.as_ref().map(|r| &r.record), &options) {
        Ok(r) => {
            let history = r.histories.as_ref().map(|h| {
                let exact = history(&rec.acceleration, rec.dt, t, plan.damping[damping]).a_abs;
                let mut without: Vec<f64> = exact.into_iter().take(h.t.len()).collect();
                without.resize(h.t.len(), f64::NAN);
                JobHistory {
                    t: h.t.clone(),
                    ag: h.ag.clone(),
                    u: h.u.clone(),
                    a_abs: h.a_abs.clone(),
                    a_abs_without_joint: without,
                    joint_force: h.joint_force.clone(),
                    friction_power: h.friction_power.clone(),
                }
            });
            JobResult { job: index as u32, status: status::OK, message: String::new(), values: values_of(&r), history }
        }
        Err(e) => {
            let code = match &e {
                ModelError::Solver(SolverError::WallClockLimit { .. } | SolverError::StepLimit { .. }) => status::LIMIT,
                ModelError::Solver(_) => status::FAILED,
                _ => status::INVALID,
            };
            JobResult {
                job: index as u32,
                status: code,
                message: e.to_string(),
                values: vec![f64::NAN; FIELDS.len()],
                history: None,
            }
        }
    }
}

/// Runs (or resumes) a sweep.
pub fn run_sweep(plan: &Plan, opts: &SweepOptions) -> Result<Summary, SweepError> {
    let start = Instant::now();
    if let Some((k, n)) = opts.shard {
        if n == 0 || k == 0 || k > n {
            return Err(SweepError::Config { field: "--shard".into(), message: format!("{k}/{n}: need 1 <= K <= N") });
        }
    }
    check_writable(&opts.output)?;
    let jpath = journal_path(&opts.output);
    let head = header(plan, opts.shard);
    let mut file = sweep_file(plan, opts.shard);
    without_joint(plan, &mut file.results)?;
    let (journal, done) = if jpath.exists() {
        if !opts.resume {
            let n = crate::journal::read(&jpath).map(|(_, r)| r.len()).unwrap_or(0);
            return Err(SweepError::Journal {
                path: jpath.display().to_string(),
                message: format!(
                    "a journal of this output already exists ({n} finished jobs): use --resume to continue it, or remove \
                     it (and the output) to start over"
                ),
            });
        }
        Journal::resume(&jpath, &head)?
    } else {
        (Journal::create(&jpath, &head)?, Vec::new())
    };
    let resumed = done.len();
    for r in done {
        file.results.insert(r);
    }
    let scope: Vec<usize> = match opts.shard {
        Some((k, n)) => plan.shard(k, n),
        None => (0..plan.job_count()).collect(),
    };
    let mut todo: Vec<usize> = scope.iter().copied().filter(|&j| file.results.status[j] == status::NOT_RUN).collect();
    // longest jobs first: the last jobs to finish are short ones
    todo.sort_by(|&a, &b| plan.cost(plan.job(b)).total_cmp(&plan.cost(plan.job(a))).then(a.cmp(&b)));
    let in_scope_done = scope.len() - todo.len();

    let threads = opts.threads.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())).max(1);
    let multi = MultiProgress::with_draw_target(if opts.progress {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    });
    let overall = multi.add(ProgressBar::new(scope.len() as u64));
    overall.set_style(
        ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} jobs, {elapsed} elapsed, ETA {eta}")
            .expect("template")
            .progress_chars("=> "),
    );
    overall.set_prefix("sweep");
    overall.set_position(in_scope_done as u64);
    let workers: Vec<ProgressBar> = (0..threads)
        .map(|w| {
            let pb = multi.add(ProgressBar::new_spinner());
            pb.set_style(ProgressStyle::with_template("  worker {prefix}: {msg}").expect("template"));
            pb.set_prefix(w.to_string());
            pb.set_message("idle");
            pb
        })
        .collect();

    let (tx, rx) = unbounded::<JobResult>();
    let cancel = Arc::new(AtomicBool::new(false));
    let next = AtomicUsize::new(0);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| SweepError::Io { path: "thread pool".into(), message: e.to_string() })?;
    let checkpoint = Duration::from_secs_f64(plan.checkpoint_seconds);
    let output = opts.output.clone();
    let writer = {
        let cancel = cancel.clone();
        let overall = overall.clone();
        std::thread::spawn(move || write_results(rx, journal, file, &output, checkpoint, &cancel, &overall))
    };
    pool.scope(|s| {
        for bar in &workers {
            let tx = tx.clone();
            let (todo, next, cancel) = (&todo, &next, &cancel);
            s.spawn(move |_| loop {
                if cancel.load(Ordering::Relaxed) {
                    break;
                }
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(&index) = todo.get(i) else { break };
                let job = plan.job(index);
                let label = format!(
                    "{} / {} / z {} / T {:.4} s",
                    plan.cases[job.case].name,
                    plan.records[job.record].record.name,
                    plan.damping[job.damping],
                    plan.periods[job.period]
                );
                bar.set_message(format!("{label}: starting"));
                let progress: quakejoint_model::run::ProgressFn = {
                    let bar = bar.clone();
                    Arc::new(move |t| bar.set_message(format!("{label}: t = {t:.1} s")))
                };
                let result = run_job(plan, index, Some(progress));
                if tx.send(result).is_err() {
                    break;
                }
            });
        }
    });
    drop(tx);
    for bar in &workers {
        bar.finish_and_clear();
    }
    let file = writer
        .join()
        .map_err(|_| SweepError::Io {
            path: opts.output.display().to_string(),
            message: "the writer thread panicked".into(),
        })?
        .map_err(|e| SweepError::Stopped { cause: Box::new(e), journal: jpath.display().to_string() })?;
    overall.finish_and_clear();
    let mut failed = Vec::new();
    for &j in &scope {
        let st = file.results.status[j];
        if st != status::OK && st != status::NOT_RUN {
            let job = plan.job(j);
            failed.push((
                plan.cases[job.case].name.clone(),
                plan.records[job.record].record.name.clone(),
                plan.damping[job.damping],
                plan.periods[job.period],
                file.results.messages[j].clone(),
            ));
        }
    }
    Ok(Summary {
        jobs: scope.len(),
        resumed: in_scope_done.min(resumed),
        ran: scope.len() - in_scope_done,
        failed,
        wall_time_s: start.elapsed().as_secs_f64(),
        output: opts.output.clone(),
        journal: jpath,
        peak_memory_mb: quakejoint_model::resources::peak_memory_mb(),
    })
}

/// The writer thread: journal, arrays, checkpoints, progress; stops the
/// workers on a write error (the journal keeps what was finished).
fn write_results(
    rx: Receiver<JobResult>,
    mut journal: Journal,
    mut file: SweepFile,
    output: &Path,
    checkpoint: Duration,
    cancel: &AtomicBool,
    overall: &ProgressBar,
) -> Result<SweepFile, SweepError> {
    let mut last = Instant::now();
    let mut dirty = false;
    for result in rx {
        if let Err(e) = journal.append(&result) {
            cancel.store(true, Ordering::Relaxed);
            return Err(e);
        }
        file.results.insert(result);
        overall.inc(1);
        dirty = true;
        if last.elapsed() >= checkpoint {
            if let Err(e) = write_sweep(output, &file) {
                cancel.store(true, Ordering::Relaxed);
                return Err(e.into());
            }
            last = Instant::now();
            dirty = false;
        }
    }
    if dirty || !output.exists() {
        write_sweep(output, &file)?;
    }
    Ok(file)
}
