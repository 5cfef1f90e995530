//! The checks of a sweep's output and the continuation logic: before
//! anything is written, an output that would overwrite an input, or a file
//! that is not a sweep's output, is refused; the output on disk is
//! measured against its journal (it agrees, is behind, or is rebuilt);
//! and `quakejoint sweep --check` ([`check_sweep`]) says what a run would
//! do without running or writing anything.

use std::path::{Path, PathBuf};

use super::{expected_file, header, journal_path, scope, SweepOptions};
use crate::error::SweepError;
use crate::lock::lock_path;
use crate::plan::Plan;
use crate::results::status;
use crate::sweep_h5::{read_sweep, SweepFile};
use quakejoint_io::files::{describe, same_file};
use quakejoint_io::h5::temporary_name;

/// Refuses an output whose files (the output, its journal, lock or
/// temporary file) would overwrite an input (the config, a record).
fn check_not_an_input(output: &Path, inputs: &[PathBuf]) -> Result<(), SweepError> {
    let targets = [output.to_path_buf(), journal_path(output), lock_path(output), temporary_name(output)];
    for t in &targets {
        if let Some(input) = inputs.iter().find(|i| same_file(t, i)) {
            return Err(SweepError::Config {
                field: "--output".into(),
                message: format!(
                    "{}: writing the sweep there would overwrite the input {}; choose another output name",
                    output.display(),
                    input.display()
                ),
            });
        }
    }
    Ok(())
}

/// Whether `existing` (the output found on disk) agrees with `expected`
/// (the plan's file with the journal's results): everything but the jobs
/// is the same, bit for bit ([`crate::compare::sweep_differences`]), and
/// every job it holds as finished is in the journal with the same numbers.
/// A file behind the journal (killed before its last checkpoint) agrees;
/// it is rewritten at the end anyway.
fn agrees(existing: &SweepFile, expected: &SweepFile) -> Result<(), String> {
    if existing.config_sha256 != expected.config_sha256 {
        return Err("it was written for another config".into());
    }
    let mut diffs = crate::compare::sweep_differences(existing, expected);
    // the limit states or their fitting (outside the config's hash): the
    // same jobs, refitted at the next write
    diffs.retain(|d| d != crate::compare::SPECS_DIFFER);
    if !diffs.is_empty() {
        return Err(format!("it disagrees with its config, records and journal: {}", diffs.join("; ")));
    }
    let (a, b) = (&existing.results, &expected.results);
    for j in 0..a.status.len() {
        if a.status[j] == status::NOT_RUN {
            continue;
        }
        if b.status[j] == status::NOT_RUN {
            return Err(format!("it holds job {j}, which its journal does not"));
        }
        let same = a.status[j] == b.status[j]
            && a.messages[j] == b.messages[j]
            && (a.validity[j], &a.findings[j]) == (b.validity[j], &b.findings[j])
            && a.values.iter().zip(&b.values).all(|(x, y)| x[j].to_bits() == y[j].to_bits())
            && a.histories.get(&(j as u32)) == b.histories.get(&(j as u32))
            && a.joints.len() == b.joints.len()
            && a.joints.iter().zip(&b.joints).all(|(x, y)| x.same_job(y, j));
        if !same {
            return Err(format!("its job {j} differs from the journal's"));
        }
    }
    Ok(())
}

/// The output on disk measured against `expected` (the plan's file with
/// the journal's results): `Ok(behind)` if it agrees (`behind`: it lacks
/// some of the journal's jobs or the current run limits), else what is
/// wrong with it, in words.
pub(super) fn output_state(output: &Path, expected: &SweepFile) -> Result<OutputState, String> {
    if !output.exists() {
        return if expected.results.finished() > 0 {
            Err("it is missing".into())
        } else {
            Ok(OutputState { behind: false, refit: false, memo: None })
        };
    }
    let existing = read_sweep(output).map_err(|e| format!("it cannot be read ({})", e.message))?;
    agrees(&existing, expected)?;
    let refit = match (&existing.fragility, &expected.fragility) {
        (Some(a), Some(b)) => a.spec != b.spec,
        _ => false,
    };
    // run limits raised since (they are outside the config's hash) are
    // written into the cases' configs
    Ok(OutputState {
        behind: existing.results.finished() < expected.results.finished()
            || existing.case_configs != expected.case_configs,
        refit,
        memo: existing.fragility.map(|f| f.memo),
    })
}

/// How an output that agrees with its journal stands.
pub(super) struct OutputState {
    /// It lacks jobs the journal holds, or run limits raised since: it is
    /// rewritten.
    pub behind: bool,
    /// Its limit states or their fitting (`[sweep.fragility]`, outside the
    /// config's hash) are not the config's: it is refitted and rewritten.
    pub refit: bool,
    /// The bootstrap intervals it holds, by their inputs' keys (a
    /// multiple-stripe sweep): the run takes them instead of resampling.
    pub memo: Option<std::sync::Arc<crate::fragility::Memo>>,
}

/// An existing file at the output name without a journal is not a sweep's
/// output (a finished merge, another program's file, a journal itself).
pub(super) fn not_an_output(output: &Path) -> SweepError {
    let what = describe(output);
    SweepError::Config {
        field: "--output".into(),
        message: format!(
            "{} exists and is {what}, not the output of this sweep (it has no journal): it is not overwritten; choose \
             another output name",
            output.display()
        ),
    }
}

/// The checks of an output before its lock is taken (they create nothing):
/// the shard, inputs that would be overwritten, a folder that does not
/// exist, an existing file that is not a sweep's output.
pub(super) fn check_output(plan: &Plan, opts: &SweepOptions) -> Result<(), SweepError> {
    if let Some((k, n)) = opts.shard {
        if n == 0 || k == 0 || k > n {
            return Err(SweepError::Config { field: "--shard".into(), message: format!("{k}/{n}: need 1 <= K <= N") });
        }
    }
    let output = &opts.output;
    quakejoint_io::files::check_name(output)
        .map_err(|message| SweepError::Config { field: "--output".into(), message })?;
    let mut inputs = vec![opts.config_path.clone()];
    inputs.extend(plan.records.iter().chain(&plan.record_y).map(|r| r.path.clone()));
    inputs.extend(plan.modal.iter().map(|m| m.path.clone()));
    inputs.extend(plan.fragility.iter().filter_map(|f| f.hazard.as_ref()?.file.clone()));
    check_not_an_input(output, &inputs)?;
    let dir = output.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if !dir.is_dir() {
        return Err(SweepError::Config {
            field: "--output".into(),
            message: format!("{}: the folder {} does not exist", output.display(), dir.display()),
        });
    }
    if output.exists() && !journal_path(output).exists() {
        return Err(not_an_output(output));
    }
    Ok(())
}

/// What a sweep would do, found without running or writing anything
/// (`quakejoint sweep --check`).
#[derive(Debug, Clone)]
pub struct Check {
    /// The HDF5 output.
    pub output: PathBuf,
    /// Jobs in the run's scope.
    pub jobs: usize,
    /// Of these, finished in the journal.
    pub done: usize,
    /// Of the finished, failed.
    pub failed: usize,
    /// Of the finished, flagged as outside the model's validity.
    pub flagged: usize,
    /// Whether a journal of this sweep exists.
    pub journal: bool,
    /// Estimated CPU time of the jobs to run \[s\] (cost model).
    pub cpu_seconds: f64,
    /// What the journal's reading noticed (damaged entries that a run
    /// skips); empty when nothing.
    pub notices: Vec<String>,
    /// What is wrong with the output on disk (damaged, missing,
    /// disagreeing with its journal): a run rebuilds it from the journal.
    pub output_problem: Option<String>,
}

/// Checks a sweep as [`run_sweep`] would before its first job: the config,
/// the records, the output and its journal (which must record this sweep),
/// and the output itself, read and verified against the journal and the
/// config as a run verifies it. Nothing is created, changed or locked.
///
/// [`run_sweep`]: super::run_sweep
pub fn check_sweep(plan: &Plan, opts: &SweepOptions) -> Result<Check, SweepError> {
    check_output(plan, opts)?;
    let jpath = journal_path(&opts.output);
    let scope = scope(plan, opts.shard);
    let mut status_of = std::collections::BTreeMap::new();
    let mut notices = Vec::new();
    let mut output_problem = None;
    let journal = jpath.exists();
    if journal {
        // a journal cut while it was being created holds nothing: a run
        // starts it afresh
        if let Some(contents) = crate::journal::read_started(&jpath)? {
            let diffs = contents.header.differences(&header(plan, opts.shard));
            if !diffs.is_empty() {
                return Err(crate::journal::another_sweep(&jpath, &diffs));
            }
            notices.extend(contents.notices(&jpath));
            let mut file = expected_file(plan, opts)?;
            for r in contents.latest() {
                if r.job as usize >= file.results.status.len() {
                    // as a run refuses it (Journal::continue_or_restart)
                    return Err(SweepError::Journal {
                        path: jpath.display().to_string(),
                        message: format!("job {} does not exist in this sweep", r.job),
                    });
                }
                let flagged = quakejoint_model::validity::Flags(r.validity).is_flagged();
                status_of.insert(r.job as usize, (r.status, flagged));
                file.results.insert(r);
            }
            output_problem = match output_state(&opts.output, &file) {
                Err(problem) => Some(format!(
                    "{}: {problem}; a run rebuilds it from the journal {}",
                    opts.output.display(),
                    jpath.display()
                )),
                Ok(OutputState { refit: true, .. }) => Some(format!(
                    "{}: its limit states or their fitting are not the config's ([sweep.fragility]); a run refits it \
                     from the journal {} without running a job",
                    opts.output.display(),
                    jpath.display()
                )),
                Ok(_) => None,
            };
        }
    } else if opts.resume {
        return Err(SweepError::Journal {
            path: jpath.display().to_string(),
            message: "--resume: there is no journal to continue".into(),
        });
    }
    let done = scope.iter().filter(|j| status_of.contains_key(j)).count();
    let failed = scope.iter().filter(|j| status_of.get(j).is_some_and(|&(s, _)| s != status::OK)).count();
    let flagged = scope.iter().filter(|j| status_of.get(j).is_some_and(|&(s, f)| s == status::OK && f)).count();
    // from +0 (an empty sum of floats is -0)
    let cpu_seconds = scope
        .iter()
        .filter(|j| !status_of.contains_key(j) || (opts.retry_failed && status_of[j].0 != status::OK))
        .map(|&j| plan.cost(plan.job(j)))
        .fold(0.0, |a, c| a + c);
    Ok(Check {
        output: opts.output.clone(),
        jobs: scope.len(),
        done,
        failed,
        flagged,
        journal,
        cpu_seconds,
        notices,
        output_problem,
    })
}
