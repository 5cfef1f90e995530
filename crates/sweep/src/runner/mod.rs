//! Running a sweep: jobs on a rayon pool, results over a channel to one
//! writer thread that journals them (fsync per job), keeps the arrays,
//! checkpoints the HDF5 file and reports progress.
//!
//! A sweep continues the journal of its output when there is one (after
//! checking that it records the same sweep), so the same command can be run
//! again after a crash, a kill or a full disk. Before anything of the output
//! is touched the output's lock is taken ([`crate::lock`]); an output that
//! would overwrite an input, or an existing file without a journal, is
//! refused; an output that disagrees with its journal (missing, damaged,
//! foreign) is rebuilt from it, with a warning.
//!
//! Each job runs single-threaded (the solver's linear algebra never spawns
//! threads), so a job's numbers depend only on its inputs: the results are
//! bit-identical whatever the thread count, the job order or the sharding.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use crossbeam_channel::unbounded;
use indicatif::ProgressBar;

use crate::error::SweepError;
use crate::journal::{Header, Journal};
use crate::lock::OutputLock;
use crate::plan::Plan;
use crate::progress::{Progress, Reporter};
use crate::results::{status, JobResult, Results, FIELDS};
use crate::sweep_h5::{StoredRecord, SweepFile};
use quakejoint_io::run_h5::{Provenance, RecordSource};

mod check;
mod job;
mod writer;

use check::{check_output, not_an_output, output_state};
pub use check::{check_sweep, Check};
pub use job::{run_job, without_joint};
use writer::Writer;
/// Version of the journal format (2: the config's hash leaves out the
/// per-job limits; 3: validity flags and split constraint residuals; 4:
/// sub-gap histories, `not_checked` for failed jobs; 5: pounding demands
/// and contact-force histories; 6: each job's CPU time; 11: the joints
/// after the first of a bridge given by its modes, and the modes file's
/// hash in the config's; 12: every joint of a bridge given by its modes,
/// with its own peak forces and friction energy; 13: every joint's fuse;
/// 14: every joint's fastest impact).
pub(crate) const JOURNAL_SCHEMA: u32 = 14;

/// How to run a sweep.
#[derive(Debug, Clone)]
pub struct SweepOptions {
    /// The HDF5 output (the journal is `<output>.journal`, the lock
    /// `<output>.lock`).
    pub output: PathBuf,
    /// Worker threads (None: all cores).
    pub threads: Option<usize>,
    /// Require a journal to continue (without it, a sweep continues a
    /// matching journal if there is one and starts afresh otherwise).
    pub resume: bool,
    /// Run the journalled jobs that failed again (their new results replace
    /// the old; finished jobs are kept).
    pub retry_failed: bool,
    /// Run only shard `k` of `n` (1-based).
    pub shard: Option<(usize, usize)>,
    /// How progress is shown on stderr.
    pub progress: Progress,
    /// The config file (never overwritten; named in the output).
    pub config_path: PathBuf,
    /// The command line, for the output's provenance.
    pub command: String,
    /// When set (by a signal handler), workers take no new job, running jobs
    /// stop at their next step, and the sweep writes a final checkpoint and
    /// returns with [`Summary::interrupted`].
    pub stop: Option<Arc<AtomicBool>>,
}

/// What a sweep did.
#[derive(Debug, Clone)]
pub struct Summary {
    /// Jobs in this run's scope (the shard, or all).
    pub jobs: usize,
    /// Of these, finished before this run (from the journal).
    pub resumed: usize,
    /// Journalled failures run again (`--retry-failed`).
    pub retried: usize,
    /// Run now.
    pub ran: usize,
    /// Jobs of the scope not finished (an interrupted sweep).
    pub not_run: usize,
    /// Failed jobs: (case, record, damping, period, message).
    pub failed: Vec<(String, String, f64, f64, String)>,
    /// Finished jobs outside the model's validity: (case, record, damping,
    /// period, flags, findings).
    pub flagged: Vec<(String, String, f64, f64, u32, String)>,
    /// Finished jobs whose beams pounded (at least one impact).
    pub pounded: usize,
    /// The largest contact force of any job \[N\] and its job (case, record,
    /// damping, period), if any pounded.
    pub peak_contact: Option<(f64, String, String, f64, f64)>,
    /// Finished jobs with a seismic fuse (on any of their joints), those in
    /// which a fuse broke and those in which a fuse's stroke was exhausted.
    pub fuses: [usize; 3],
    /// Whether the bridge is given by its modes: the jobs' "period" above
    /// is then their period scale [-].
    pub modal: bool,
    /// Whether a stop request ended the sweep before every job had run.
    pub interrupted: bool,
    /// Warnings given during the run (damage found in the journal, an
    /// output rebuilt from it).
    pub notices: Vec<String>,
    /// Wall-clock time \[s\].
    pub wall_time_s: f64,
    /// The HDF5 output.
    pub output: PathBuf,
    /// The journal.
    pub journal: PathBuf,
    /// Peak resident memory of the process \[MB\] (Linux; for cluster job
    /// requests).
    pub peak_memory_mb: Option<f64>,
    /// The shard this run was, if any.
    pub shard: Option<(usize, usize)>,
    /// A multiple-stripe sweep: its stripes and the fitted curves of the
    /// jobs in the output.
    pub fragility: Option<(crate::fragility::StoredFragility, Vec<crate::fragility::CurveRow>)>,
    /// With target frequencies: the choice among the cases, at each
    /// damping ratio and period (docs/design.md).
    pub design: Vec<crate::fragility::design::Design>,
}

/// `<output>.journal`.
pub fn journal_path(output: &Path) -> PathBuf {
    let mut s = output.as_os_str().to_owned();
    s.push(".journal");
    PathBuf::from(s)
}

/// The journal header of a plan.
pub fn header(plan: &Plan, shard: Option<(usize, usize)>) -> Header {
    Header {
        schema: JOURNAL_SCHEMA,
        program_version: quakejoint_io::h5::VERSION.to_string(),
        config_sha256: plan.config_sha256.clone(),
        records: plan.records.iter().chain(&plan.record_y).map(|r| (r.record.name.clone(), r.sha256.clone())).collect(),
        jobs: plan.job_count() as u64,
        shard: shard.map(|(k, n)| (k as u32, n as u32)),
    }
}

/// The jobs of a run: its shard's, or all.
pub fn scope(plan: &Plan, shard: Option<(usize, usize)>) -> Vec<usize> {
    match shard {
        Some((k, n)) => plan.shard(k, n),
        None => (0..plan.job_count()).collect(),
    }
}

/// The provenance of a sweep's output: the command, the config and every
/// record file with its hash (`[record_y]` under the role `y`).
pub fn provenance(plan: &Plan, command: &str, config_path: &Path) -> Provenance {
    let mut records: Vec<RecordSource> =
        plan.records.iter().map(|r| RecordSource::of(&r.record.name, &r.record, &r.sha256)).collect();
    records.extend(plan.record_y.iter().map(|r| RecordSource::of("y", &r.record, &r.sha256)));
    Provenance {
        command: command.to_string(),
        config_path: config_path.display().to_string(),
        config_file: plan.config_text.clone(),
        config: plan.config_used.clone(),
        records,
        warnings: plan
            .records
            .iter()
            .chain(&plan.record_y)
            .flat_map(|r| r.warnings.clone())
            .chain(plan.warnings.clone())
            .collect(),
    }
}

/// The file skeleton of a plan (results not yet filled).
pub fn sweep_file(plan: &Plan, shard: Option<(usize, usize)>, provenance: Provenance) -> SweepFile {
    SweepFile {
        provenance,
        case_configs: plan.cases.iter().map(|c| toml::to_string(&c.config).unwrap_or_default()).collect(),
        config_sha256: plan.config_sha256.clone(),
        shard: shard.map_or("all".to_string(), |(k, n)| format!("{k}/{n}")),
        scope: scope(plan, shard).into_iter().map(|j| j as u32).collect(),
        periods: plan.periods.clone(),
        modal: plan.modal.as_ref().map(|m| crate::sweep_h5::StoredModal {
            period_scales: m.period_scales.clone(),
            modes_file: m.file.clone(),
            modes_sha256: m.sha256.clone(),
        }),
        damping: plan.damping.clone(),
        cases: plan.cases.iter().map(|c| c.name.clone()).collect(),
        suite: plan.suite.as_ref().map(|s| crate::suite_h5::StoredSuite::of(s, &plan.periods)),
        fragility: plan
            .stripes
            .as_ref()
            .zip(plan.fragility.as_ref())
            .map(|(stripes, spec)| crate::fragility::StoredFragility::new(stripes.clone(), spec.clone())),
        records: plan
            .records
            .iter()
            .map(|r| StoredRecord {
                name: r.record.name.clone(),
                source: r.record.source.clone(),
                sha256: r.sha256.clone(),
                file_units: r.record.units.name().to_string(),
                dt: r.record.dt,
                scale: r.record.scale,
                pga: r.record.pga(),
                acceleration: r.record.acceleration.clone(),
            })
            .collect(),
        results: match &plan.modal {
            Some(m) => Results::modal(plan.dims(), &m.joints),
            None => Results::new(plan.dims()),
        },
    }
}

/// The file a run writes before any job: the plan's grids, records and
/// provenance with the spectra without the joint (the journal's results
/// are inserted into it).
fn expected_file(plan: &Plan, opts: &SweepOptions) -> Result<SweepFile, SweepError> {
    let mut file = sweep_file(plan, opts.shard, provenance(plan, &opts.command, &opts.config_path));
    without_joint(plan, &mut file.results)?;
    Ok(file)
}

/// Runs a sweep: starts it, or continues the one its journal records.
pub fn run_sweep(plan: &Plan, opts: &SweepOptions) -> Result<Summary, SweepError> {
    let start = Instant::now();
    let output = &opts.output;
    check_output(plan, opts)?;
    // nothing of the output is created, read or deleted before the lock
    let lock = OutputLock::acquire(output)?;
    crate::fault::point(crate::fault::Point::Locked, output);
    let mut notices: Vec<String> = lock.unsupported.iter().cloned().collect();
    let jpath = journal_path(output);
    let head = header(plan, opts.shard);
    let mut file = expected_file(plan, opts)?;
    let (journal, done) = open_journal(opts, &jpath, &head, &mut notices)?;
    for r in done {
        file.results.insert(r);
    }
    // the output on disk must agree with its journal, or it is rebuilt
    let mut dirty = sync_output(output, &jpath, &mut file, &mut notices);
    let scope = scope(plan, opts.shard);
    let retried = if opts.retry_failed { retry_failed(&scope, &mut file.results) } else { 0 };
    dirty |= retried > 0;
    let mut todo: Vec<usize> = scope.iter().copied().filter(|&j| file.results.status[j] == status::NOT_RUN).collect();
    // longest jobs first: the last jobs to finish are short ones
    todo.sort_by(|&a, &b| plan.cost(plan.job(b)).total_cmp(&plan.cost(plan.job(a))).then(a.cmp(&b)));
    let in_scope_done = scope.len() - todo.len();
    let failed_before =
        scope.iter().filter(|&&j| !matches!(file.results.status[j], status::OK | status::NOT_RUN)).count();
    let flagged_before = scope
        .iter()
        .filter(|&&j| {
            file.results.status[j] == status::OK
                && quakejoint_model::validity::Flags(file.results.validity[j]).is_flagged()
        })
        .count();

    // no more workers than jobs to run (a thread waiting for none costs
    // its stack and its start)
    let threads = opts
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .clamp(1, todo.len().max(1));
    let label = output.file_name().map_or(output.display().to_string(), |n| n.to_string_lossy().into_owned());
    let cost_left: f64 = todo.iter().map(|&j| plan.cost(plan.job(j))).sum();
    let reporter = Reporter::new(
        opts.progress,
        label,
        (scope.len(), in_scope_done, failed_before, flagged_before),
        cost_left,
        threads.min(todo.len()),
    );
    for n in &notices {
        reporter.notice(n);
    }
    let workers: Vec<ProgressBar> = (0..threads).map(|w| reporter.worker(w)).collect();

    let (tx, rx) = unbounded::<JobResult>();
    let stop = opts.stop.clone().unwrap_or_default();
    let next = AtomicUsize::new(0);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| SweepError::Io { path: "thread pool".into(), message: e.to_string() })?;
    let writer = {
        let (stop, output) = (stop.clone(), output.clone());
        let checkpoint = Duration::from_secs_f64(plan.checkpoint_seconds);
        let costs: Vec<f64> = (0..plan.job_count()).map(|j| plan.cost(plan.job(j))).collect();
        let state = Writer { journal, file, output, checkpoint, dirty, reporter, costs };
        std::thread::spawn(move || state.run(rx, &stop))
    };
    pool.scope(|s| {
        for bar in &workers {
            let tx = tx.clone();
            let (todo, next, stop) = (&todo, &next, &stop);
            s.spawn(move |_| work(plan, Queue { todo, next }, bar, &tx, stop, opts));
        }
    });
    drop(tx);
    for bar in &workers {
        bar.finish_and_clear();
    }
    let file = writer
        .join()
        .map_err(|_| SweepError::Io {
            path: output.display().to_string(),
            message: "the writer thread panicked".into(),
        })?
        .map_err(|e| SweepError::Stopped { cause: Box::new(e), journal: jpath.display().to_string() })?;
    drop(lock);
    let Tally { failed, flagged, not_run, pounded, peak_contact, fuses } = tally(plan, &scope, &file.results);
    Ok(Summary {
        jobs: scope.len(),
        resumed: in_scope_done,
        retried,
        ran: scope.len() - in_scope_done - not_run,
        not_run,
        failed,
        flagged,
        pounded,
        peak_contact,
        fuses,
        modal: plan.modal.is_some(),
        interrupted: not_run > 0 && stop.load(Ordering::Relaxed),
        notices,
        wall_time_s: start.elapsed().as_secs_f64(),
        output: output.clone(),
        journal: jpath,
        peak_memory_mb: quakejoint_model::resources::peak_memory_mb(),
        shard: opts.shard,
        fragility: file.fragility.as_ref().map(|f| {
            let label = |c: usize, z: usize, t: usize| {
                format!("{} / {}", plan.cases[c].name, plan.axis_label(t))
                    + &if plan.damping.len() > 1 { format!(" / damping {}", plan.damping[z]) } else { String::new() }
            };
            (f.clone(), crate::fragility::rows(f, &file.results, &label))
        }),
        design: Vec::new(),
    }
    .with_design(plan))
}

impl Summary {
    /// The summary with its choice among the plan's cases.
    fn with_design(mut self, plan: &Plan) -> Self {
        use crate::fragility::design::{designs, Candidate};
        if let Some((f, rows)) = self.fragility.as_ref().filter(|_| self.shard.is_none()) {
            let candidates: Vec<Candidate> = plan.cases.iter().map(|c| Candidate::of(&c.name, &c.config)).collect();
            self.design = designs(f, rows, &candidates);
        }
        self
    }
}

/// Clears the failed jobs of `scope` so that they run again; how many.
fn retry_failed(scope: &[usize], results: &mut Results) -> usize {
    let mut retried = 0;
    for &j in scope {
        if !matches!(results.status[j], status::OK | status::NOT_RUN) {
            results.clear(j);
            retried += 1;
        }
    }
    retried
}

/// The jobs a sweep runs now, in order, and the index of the next one to
/// take (shared by the workers).
#[derive(Clone, Copy)]
struct Queue<'a> {
    todo: &'a [usize],
    next: &'a AtomicUsize,
}

/// One worker: takes the next job until none is left or the sweep stops,
/// runs it with its progress on `bar` and sends its result to the writer.
fn work(
    plan: &Plan,
    queue: Queue<'_>,
    bar: &ProgressBar,
    tx: &crossbeam_channel::Sender<JobResult>,
    stop: &Arc<AtomicBool>,
    opts: &SweepOptions,
) {
    loop {
        if stop.load(Ordering::Relaxed) {
            break;
        }
        let i = queue.next.fetch_add(1, Ordering::Relaxed);
        let Some(&index) = queue.todo.get(i) else { break };
        if i + 1 == queue.todo.len() && crate::fault::hold(opts.shard, &opts.output, stop) {
            break;
        }
        let job = plan.job(index);
        let label = job_label(plan, &job);
        bar.set_message(format!("{label}: starting"));
        let progress: quakejoint_model::run::ProgressFn = {
            let bar = bar.clone();
            Arc::new(move |t| bar.set_message(format!("{label}: t = {t:.1} s")))
        };
        let Some(result) = run_job(plan, index, Some(progress), Some(stop.clone())) else { break };
        if tx.send(result).is_err() {
            break;
        }
    }
}

/// The sweep's journal: continued (with the jobs it records), or created
/// for a sweep that starts.
fn open_journal(
    opts: &SweepOptions,
    jpath: &Path,
    head: &Header,
    notices: &mut Vec<String>,
) -> Result<(Journal, Vec<JobResult>), SweepError> {
    let output = &opts.output;
    let opened = if jpath.exists() {
        let c = Journal::continue_or_restart(jpath, head)?;
        notices.extend(c.notices);
        (c.journal, c.results)
    } else if opts.resume {
        return Err(SweepError::Journal {
            path: jpath.display().to_string(),
            message: "--resume: there is no journal to continue (run without --resume to start the sweep)".into(),
        });
    } else if output.exists() {
        // appeared since the check before the lock
        return Err(not_an_output(output));
    } else {
        (Journal::create(jpath, head)?, Vec::new())
    };
    Ok(opened)
}

/// Whether the output on disk is behind its journal (or must be refitted,
/// or rebuilt: said in `notices`); a fragility memo it holds is kept.
fn sync_output(output: &Path, jpath: &Path, file: &mut SweepFile, notices: &mut Vec<String>) -> bool {
    match output_state(output, file) {
        Ok(check::OutputState { behind, refit, memo }) => {
            if let (Some(memo), Some(f)) = (memo, &mut file.fragility) {
                f.memo = memo;
            }
            if refit {
                notices.push(format!(
                    "{}: the limit states or their fitting ([sweep.fragility]) changed: refitted from the journal, no \
                     job runs again",
                    output.display()
                ));
            }
            behind || refit
        }
        Err(problem) => {
            notices.push(format!(
                "{}: {problem}; it is rebuilt from the journal {}",
                output.display(),
                jpath.display()
            ));
            true
        }
    }
}

/// A job in words, as the progress shows it.
fn job_label(plan: &Plan, job: &crate::Job) -> String {
    match &plan.modal {
        Some(_) => format!(
            "{} / {} / {}",
            plan.cases[job.case].name,
            plan.records[job.record].record.name,
            plan.axis_label(job.period)
        ),
        None => format!(
            "{} / {} / z {} / T {:.4} s",
            plan.cases[job.case].name,
            plan.records[job.record].record.name,
            plan.damping[job.damping],
            plan.periods[job.period]
        ),
    }
}

/// The jobs of a sweep's scope by outcome, for its summary.
struct Tally {
    failed: Vec<(String, String, f64, f64, String)>,
    flagged: Vec<(String, String, f64, f64, u32, String)>,
    not_run: usize,
    pounded: usize,
    peak_contact: Option<(f64, String, String, f64, f64)>,
    fuses: [usize; 3],
}

/// Whether job `j` has a fuse, whether one broke and whether one ran out of
/// stroke: every joint's, on a bridge with several (a job counts once).
fn job_fuses(results: &Results, j: usize, [broken, exhausted]: [usize; 2]) -> [bool; 3] {
    let (b, e) = (results.joint_values(j, broken), results.joint_values(j, exhausted));
    [b.iter().any(|x| !x.is_nan()), b.iter().any(|&x| x > 0.5), e.iter().any(|&x| x > 0.5)]
}

/// Counts the outcomes of the jobs of `scope`.
fn tally(plan: &Plan, scope: &[usize], results: &Results) -> Tally {
    let mut failed = Vec::new();
    let mut flagged = Vec::new();
    let mut not_run = 0;
    let (mut pounded, mut peak_contact) = (0, None::<(f64, String, String, f64, f64)>);
    let field = |name: &str| FIELDS.iter().position(|f| *f == name).unwrap_or(0);
    let (impacts, peak) = (field("impacts"), field("peak_contact_force"));
    let (broken, exhausted) = (field("fuse_broken"), field("fuse_stroke_exhausted"));
    let mut fuses = [0; 3];
    for &j in scope {
        let st = results.status[j];
        let job = plan.job(j);
        let (case, record) = (plan.cases[job.case].name.clone(), plan.records[job.record].record.name.clone());
        let (z, t) = (plan.damping[job.damping], plan.axis()[job.period]);
        if st == status::NOT_RUN {
            not_run += 1;
        } else if st != status::OK {
            failed.push((case.clone(), record.clone(), z, t, results.messages[j].clone()));
        } else if quakejoint_model::validity::Flags(results.validity[j]).is_flagged() {
            flagged.push((case.clone(), record.clone(), z, t, results.validity[j], results.findings[j].clone()));
        }
        if st != status::OK {
            continue;
        }
        let [fused, broke, ran_out] = job_fuses(results, j, [broken, exhausted]);
        fuses[0] += usize::from(fused);
        fuses[1] += usize::from(broke);
        fuses[2] += usize::from(ran_out);
        // (every joint's impacts, on a bridge with several: a job counts once)
        if results.joint_values(j, impacts).iter().any(|&n| n > 0.0) {
            pounded += 1;
            let f = results.joint_values(j, peak).into_iter().fold(f64::NAN, f64::max);
            if peak_contact.as_ref().is_none_or(|p| f > p.0) {
                peak_contact = Some((f, case, record, z, t));
            }
        }
    }
    Tally { failed, flagged, not_run, pounded, peak_contact, fuses }
}
