//! Combining the outputs of shards (`quakejoint merge`).
//!
//! Shards of one sweep share the config, the records and the grids; each
//! holds the results of its own jobs (the others marked not run). The merged
//! file takes every job from the shard that ran it. Its numeric datasets are
//! identical to those of an unsharded run (except the machine-dependent wall
//! times).
//!
//! A merge is strict by default:
//! - every input must be a readable sweep file: each one that is missing or
//!   unreadable is named, and nothing is written;
//! - the result must be complete: if a job has not run, the missing shards
//!   and jobs are named and nothing is written, unless the caller accepts a
//!   partial result ([`MergeOptions::allow_partial`]: the file then says
//!   `complete = 0`);
//! - the same file given twice is read once; two files claiming the same
//!   shard are refused; a job present in two inputs (overlapping shards of
//!   different splits) is kept once if its results are bit-identical, and
//!   refused otherwise. Each of these is reported.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use crate::error::SweepError;
use crate::lock::OutputLock;
use crate::results::{status, Results, FIELDS, MACHINE_DEPENDENT};
use crate::runner::journal_path;
use crate::sweep_h5::{read_sweep, write_sweep, SweepFile};
use quakejoint_io::files::{describe, same_file};

/// How to merge.
#[derive(Debug, Clone, Default)]
pub struct MergeOptions {
    /// Write the merged file even if some jobs have not run (they stay
    /// marked not run, and the file says `complete = 0`).
    pub allow_partial: bool,
    /// The command line, for the merged file's provenance.
    pub command: String,
    /// The config hash the shards must carry (the current config's), if
    /// known: shards of an earlier version of the config are refused.
    pub expected: Option<String>,
    /// The config's limit states and fitting (`[sweep.fragility]`, which
    /// the hash leaves out), if known: a multiple-stripe sweep is fitted
    /// with them, whatever its shards were fitted with.
    pub fragility: Option<crate::fragility::FragilitySpec>,
}

/// What a merge produced.
#[derive(Debug, Clone)]
pub struct MergeSummary {
    /// The merged file.
    pub output: PathBuf,
    /// Jobs of the sweep.
    pub jobs: usize,
    /// Jobs with a result (any status but not run).
    pub finished: usize,
    /// Jobs that failed.
    pub failed: usize,
    /// Finished jobs outside the model's validity.
    pub flagged: usize,
    /// Jobs without a result (only with [`MergeOptions::allow_partial`]).
    pub missing: usize,
    /// What the merge noticed and dealt with (duplicates, overlaps, a
    /// partial result).
    pub notices: Vec<String>,
    /// The failed jobs, each in words with its message.
    pub failed_jobs: Vec<String>,
    /// The flagged jobs, each in words with its findings.
    pub flagged_jobs: Vec<String>,
    /// The shards `(k, n)` whose failed jobs the merged file holds (to run
    /// them again with `--retry-failed`).
    pub failed_shards: Vec<(usize, usize)>,
    /// A multiple-stripe sweep: its stripes and the fitted curves of the
    /// merged results.
    pub fragility: Option<(crate::fragility::StoredFragility, Vec<crate::fragility::CurveRow>)>,
    /// With target frequencies: the choice among the cases (docs/design.md).
    pub design: Vec<crate::fragility::design::Design>,
}

/// `(k, n)` of a shard name `"k/n"`.
fn shard_of(name: &str) -> Option<(usize, usize)> {
    let (k, n) = name.split_once('/')?;
    Some((k.parse().ok()?, n.parse().ok()?))
}

/// Reads every input, naming each one that cannot be used.
fn read_all(inputs: &[PathBuf], notices: &mut Vec<String>) -> Result<Vec<(PathBuf, SweepFile)>, SweepError> {
    let mut unique: Vec<&PathBuf> = Vec::new();
    for path in inputs {
        if let Some(first) = unique.iter().find(|u| same_file(u, path)) {
            notices.push(format!("{} was given twice (as {}): read once", first.display(), path.display()));
        } else {
            unique.push(path);
        }
    }
    let mut files = Vec::new();
    let mut problems = Vec::new();
    for path in unique {
        if !path.exists() {
            problems.push(format!("{}: no such file (has its shard run?)", path.display()));
            continue;
        }
        match read_sweep(path) {
            Ok(f) => files.push((path.clone(), f)),
            Err(e) => problems.push(format!(
                "{}: not a readable sweep file ({}){}",
                path.display(),
                e.message,
                if journal_path(path).exists() {
                    "; its journal is beside it: running its shard's `quakejoint sweep` command again rebuilds it \
                     from the journal"
                } else {
                    ""
                }
            )),
        }
    }
    if !problems.is_empty() {
        return Err(SweepError::Merge(format!("cannot merge:\n  {}", problems.join("\n  "))));
    }
    Ok(files)
}

/// The merged file may replace an earlier merge or nothing, never an input
/// or the output of a sweep (which has a journal).
/// An earlier merge that no longer reads (a damaged file) is replaced, with
/// the notice returned.
fn check_output(output: &Path, inputs: &[PathBuf]) -> Result<Option<String>, SweepError> {
    quakejoint_io::files::check_name(output).map_err(SweepError::Merge)?;
    if let Some(i) = inputs.iter().find(|i| same_file(output, i)) {
        return Err(SweepError::Merge(format!(
            "the output {} is one of the inputs ({})",
            output.display(),
            i.display()
        )));
    }
    if journal_path(output).exists() {
        return Err(SweepError::Merge(format!(
            "{} is the output of a sweep (it has a journal): write the merge elsewhere",
            output.display()
        )));
    }
    if !output.exists() {
        return Ok(None);
    }
    match read_sweep(output) {
        Ok(_) => Ok(None),
        // a quakejoint sweep file without a journal: an earlier merge
        Err(e) if quakejoint_io::files::kind_of(output).as_deref() == Some("sweep") => Ok(Some(format!(
            "{}: the earlier merge there cannot be read ({}); it is replaced",
            output.display(),
            e.message
        ))),
        Err(_) => Err(SweepError::Merge(format!(
            "{} exists and is {}: it is not overwritten",
            output.display(),
            describe(output)
        ))),
    }
}

/// Refuses shards computed from another version of the config than
/// `expected` (its SHA-256).
fn check_versions(files: &[(PathBuf, SweepFile)], expected: Option<&str>) -> Result<(), SweepError> {
    if let Some(expected) = expected {
        let stale: Vec<String> =
            files.iter().filter(|(_, f)| f.config_sha256 != expected).map(|(p, _)| p.display().to_string()).collect();
        if !stale.is_empty() {
            return Err(SweepError::Merge(format!(
                "these shards were computed from another version of the config: {}; run their shards again (into \
                 new files, or after deleting these and their journals)",
                stale.join(", ")
            )));
        }
    }
    Ok(())
}

/// Combines every input's results into `merged`, refusing inputs that are
/// not shards of one sweep and a shard given twice; how many jobs were in
/// more than one input (identical). `config_fits`: the config's limit
/// states are written, so the shards' own fits need not agree.
fn combine_all(merged: &mut SweepFile, files: &[(PathBuf, SweepFile)], config_fits: bool) -> Result<usize, SweepError> {
    let first_path = &files[0].0;
    let mut claimed: Vec<(String, &Path)> = Vec::new();
    let mut overlaps = 0;
    for (path, other) in files {
        // the same config, grids, records, provenance, suite and spectra
        // without the joint, bit for bit, as `compare` checks them
        let mut diffs = crate::compare::sweep_differences(merged, other);
        if config_fits {
            // the shards' own fits do not matter: the config's are written
            diffs.retain(|d| d != crate::compare::SPECS_DIFFER);
        }
        if !diffs.is_empty() {
            let hint = if diffs.iter().any(|d| d == crate::compare::SPECS_DIFFER) {
                " (give the config with --config: the merged file is then fitted with its [sweep.fragility])"
            } else {
                ""
            };
            return Err(SweepError::Merge(format!(
                "{} and {} are not shards of one sweep: {}{hint}",
                first_path.display(),
                path.display(),
                diffs.join("; ")
            )));
        }
        if other.shard != "all" && other.shard != "merged" {
            if let Some((_, p)) = claimed.iter().find(|(s, _)| *s == other.shard) {
                return Err(SweepError::Merge(format!(
                    "{} and {} both hold shard {}: give each shard once",
                    p.display(),
                    path.display(),
                    other.shard
                )));
            }
            claimed.push((other.shard.clone(), path));
        }
        overlaps += combine(&mut merged.results, &other.results, &path.display().to_string())?;
    }
    Ok(overlaps)
}

/// Merges shard files into `output`.
pub fn merge(inputs: &[PathBuf], output: &Path, options: MergeOptions) -> Result<MergeSummary, SweepError> {
    if inputs.is_empty() {
        return Err(SweepError::Merge("no input files".into()));
    }
    let replaced = check_output(output, inputs)?;
    let _lock = OutputLock::acquire(output)?;
    let mut notices: Vec<String> = replaced.into_iter().collect();
    let files = read_all(inputs, &mut notices)?;
    check_versions(&files, options.expected.as_deref())?;
    let first = &files[0].1;
    let results = first.results.empty_like();
    let mut merged = SweepFile { results, scope: Vec::new(), ..first.clone() };
    // the config's limit states and fitting, when it is given: the shards'
    // own (fitted at their last write) do not matter then
    if let (Some(spec), Some(fr)) = (&options.fragility, &mut merged.fragility) {
        if &fr.spec != spec {
            notices.push(
                "the shards were fitted with other limit states or fitting than the config's ([sweep.fragility]): \
                 the merged file is fitted with the config's"
                    .to_string(),
            );
            fr.spec = spec.clone();
        }
    }
    let overlaps = combine_all(&mut merged, &files, options.fragility.is_some())?;
    if overlaps > 0 {
        notices.push(format!("{overlaps} jobs were in more than one input with identical results: kept once"));
    }
    let r = &merged.results;
    let missing: Vec<usize> = (0..r.status.len()).filter(|&j| r.status[j] == status::NOT_RUN).collect();
    if !missing.is_empty() {
        let report = incomplete(&merged, &files, &missing);
        if !options.allow_partial {
            return Err(SweepError::Incomplete { report, shards: unfinished(&files) });
        }
        notices.push(format!("partial result written (complete = 0): {report}"));
    }
    merged.shard = if missing.is_empty() { "all".into() } else { "partial".into() };
    merged.provenance.command = options.command.clone();
    merged.scope = (0..r.status.len() as u32).collect();
    write_sweep(output, &merged)?;
    let results = &merged.results;
    let n = results.status.len();
    let failed_jobs = (0..n)
        .filter(|&j| !matches!(results.status[j], status::OK | status::NOT_RUN))
        .map(|j| format!("{}: {}", merged.describe_job(j), results.messages[j]))
        .collect();
    let flagged_jobs = (0..n)
        .filter(|&j| {
            results.status[j] == status::OK && quakejoint_model::validity::Flags(results.validity[j]).is_flagged()
        })
        .map(|j| format!("{}: {}", merged.describe_job(j), results.findings[j]))
        .collect();
    // the input each failed job was taken from (the first that holds it)
    let failed_shards: BTreeSet<(usize, usize)> = (0..n)
        .filter(|&j| !matches!(results.status[j], status::OK | status::NOT_RUN))
        .filter_map(|j| files.iter().find(|(_, f)| f.results.status[j] == results.status[j]))
        .filter_map(|(_, f)| shard_of(&f.shard))
        .collect();
    let fragility = merged.fragility.as_ref().map(|f| {
        let label = |c: usize, z: usize, t: usize| {
            let axis = match &merged.modal {
                Some(m) => format!("period scale {}", m.period_scales[t]),
                None => format!("T {:.4} s", merged.periods[t]),
            };
            format!("{} / {axis} / damping {}", merged.cases[c], merged.damping[z])
        };
        (f.clone(), crate::fragility::rows(f, &merged.results, &label))
    });
    let design = fragility.as_ref().map_or_else(Vec::new, |(f, rows)| {
        let candidates = crate::fragility::design::candidates_of(&merged.cases, &merged.case_configs);
        crate::fragility::design::designs(f, rows, &candidates)
    });
    Ok(MergeSummary {
        fragility,
        design,
        failed_shards: failed_shards.into_iter().collect(),
        failed_jobs,
        flagged_jobs,
        output: output.to_path_buf(),
        jobs: results.status.len(),
        finished: results.finished(),
        failed: results.failed(),
        flagged: results.flagged(),
        missing: missing.len(),
        notices,
    })
}

/// The shards `(k, n)` to run or continue: those of the split the inputs
/// share that no input holds, and those with jobs not run.
fn unfinished(files: &[(PathBuf, SweepFile)]) -> Vec<(usize, usize)> {
    let shards: BTreeSet<(usize, usize)> = files.iter().filter_map(|(_, f)| shard_of(&f.shard)).collect();
    let ns: BTreeSet<usize> = shards.iter().map(|&(_, n)| n).collect();
    let mut out = BTreeSet::new();
    if let (1, Some(&n)) = (ns.len(), ns.first()) {
        out.extend((1..=n).filter(|k| !shards.contains(&(*k, n))).map(|k| (k, n)));
    }
    for (_, f) in files {
        if f.scope.iter().any(|&j| f.results.status[j as usize] == status::NOT_RUN) {
            out.extend(shard_of(&f.shard));
        }
    }
    out.into_iter().collect()
}

/// Which shards and jobs are missing, in words.
fn incomplete(merged: &SweepFile, files: &[(PathBuf, SweepFile)], missing: &[usize]) -> String {
    let mut parts = Vec::new();
    let shards: BTreeSet<(usize, usize)> = files.iter().filter_map(|(_, f)| shard_of(&f.shard)).collect();
    let ns: BTreeSet<usize> = shards.iter().map(|&(_, n)| n).collect();
    if let (1, Some(&n)) = (ns.len(), ns.first()) {
        let absent: Vec<String> = (1..=n).filter(|k| !shards.contains(&(*k, n))).map(|k| format!("{k}/{n}")).collect();
        if !absent.is_empty() {
            parts.push(format!("missing shards: {}", absent.join(", ")));
        }
    }
    for (path, f) in files {
        let not_run = f.scope.iter().filter(|&&j| f.results.status[j as usize] == status::NOT_RUN).count();
        if not_run > 0 {
            parts.push(format!(
                "{} (shard {}) has {not_run} of its {} jobs not run",
                path.display(),
                f.shard,
                f.scope.len()
            ));
        }
    }
    const SHOWN: usize = 10;
    let listed: Vec<String> = missing.iter().take(SHOWN).map(|&j| merged.describe_job(j)).collect();
    let more = if missing.len() > SHOWN { format!(" and {} more", missing.len() - SHOWN) } else { String::new() };
    parts.push(format!(
        "{} of {} jobs have no result: {}{more}",
        missing.len(),
        merged.results.status.len(),
        listed.join(", ")
    ));
    parts.join("; ")
}

/// Adds the finished jobs of `from`; returns how many were already present
/// with identical results.
fn combine(into: &mut Results, from: &Results, source: &str) -> Result<usize, SweepError> {
    let mut overlaps = 0;
    for j in 0..from.status.len() {
        if from.status[j] == status::NOT_RUN {
            continue;
        }
        if into.status[j] != status::NOT_RUN {
            let differs = FIELDS
                .iter()
                .enumerate()
                .filter(|(_, name)| !MACHINE_DEPENDENT.contains(name))
                .any(|(k, _)| into.values[k][j].to_bits() != from.values[k][j].to_bits());
            let joints_differ = into.joints.len() != from.joints.len()
                || into.joints.iter().zip(&from.joints).any(|(a, b)| !a.same_job(b, j));
            if differs || joints_differ || into.status[j] != from.status[j] || into.validity[j] != from.validity[j] {
                return Err(SweepError::Merge(format!("job {j} was run twice with different results ({source})")));
            }
            overlaps += 1;
            continue;
        }
        for k in 0..FIELDS.len() {
            into.values[k][j] = from.values[k][j];
        }
        into.status[j] = from.status[j];
        into.messages[j] = from.messages[j].clone();
        into.validity[j] = from.validity[j];
        into.findings[j] = from.findings[j].clone();
        for (a, b) in into.joints.iter_mut().zip(&from.joints) {
            a.copy_job(b, j);
        }
        if let Some(h) = from.histories.get(&(j as u32)) {
            into.histories.insert(j as u32, h.clone());
        }
    }
    Ok(overlaps)
}
