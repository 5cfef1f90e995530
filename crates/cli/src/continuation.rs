//! What to run next when a sweep or a merge has not finished everything: the
//! command that continues an interrupted sweep, the one that runs its failed
//! jobs again, and, in a job of `scripts/slurm_array.sh`, the resubmission of
//! shards (never a `quakejoint sweep` to run on the login node).
//!
//! `QUAKEJOINT_RESUBMIT`, set by `scripts/slurm_array.sh` for its tasks and
//! its merge job, is the command that resubmits shards of the sweep (e.g.
//! `scripts/slurm_array.sh configs/paper.toml 16`); the advice appends
//! `--tasks K,..` and, where failed jobs are to run again, `--retry-failed`.
//! Without it, a process inside a SLURM job (`SLURM_JOB_ID` set) is told to
//! run the printed command as a job again.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// The environment variable naming the resubmission command.
const RESUBMIT: &str = "QUAKEJOINT_RESUBMIT";

/// The resubmission command of `scripts/slurm_array.sh`, if set.
fn resubmit() -> Option<String> {
    std::env::var(RESUBMIT).ok().map(|s| s.trim().to_string()).filter(|s| !s.is_empty())
}

/// Whether this process runs inside a SLURM job.
pub fn in_slurm() -> bool {
    ["SLURM_JOB_ID", "SLURM_ARRAY_TASK_ID"].iter().any(|v| std::env::var_os(v).is_some())
}

/// `3,5,6`.
fn task_list(shards: &[usize]) -> String {
    shards.iter().map(usize::to_string).collect::<Vec<_>>().join(",")
}

/// The resubmission of `shards` (`retry`: their failed jobs run again), if
/// this process runs for `scripts/slurm_array.sh`.
pub fn resubmit_shards(shards: &[usize], retry: bool) -> Option<String> {
    let mut command = resubmit()?;
    if !shards.is_empty() {
        command.push_str(&format!(" --tasks {}", task_list(shards)));
    }
    if retry {
        command.push_str(" --retry-failed");
    }
    Some(command)
}

/// How to go on with a sweep: the command, and where to run it.
pub struct Next {
    /// The command.
    pub command: String,
    /// Where to run it (`None`: here, in a shell).
    pub note: Option<&'static str>,
}

impl std::fmt::Display for Next {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.note {
            Some(note) => write!(f, "  {}\n  ({note})", self.command),
            None => write!(f, "  {}", self.command),
        }
    }
}

/// The command that goes on with this sweep (of `shard`): with `retry`, it
/// runs the failed jobs again (`--retry-failed`); with `resume`, it insists
/// on the journal (`--resume`). `words` is the command line that ran.
pub fn sweep_next(words: &[OsString], shard: Option<(usize, usize)>, retry: bool, resume: bool) -> Next {
    if let Some(command) = resubmit_shards(&shard.map(|(k, _)| vec![k]).unwrap_or_default(), retry) {
        let note = if resume {
            "on the login node, in the directory slurm_array.sh was run from: it submits the shard again, and a new \
             merge; a task stopped by its time limit needs a larger QJ_TIME"
        } else {
            "on the login node, in the directory slurm_array.sh was run from: it submits the shard again, and a new \
             merge"
        };
        return Next { command, note: Some(note) };
    }
    let mut words: Vec<OsString> = words.iter().filter(|w| w.as_os_str() != "--retry-failed").cloned().collect();
    if retry {
        words.push("--retry-failed".into());
    }
    if resume && !words.iter().any(|w| w == "--resume") {
        words.push("--resume".into());
    }
    let note = in_slurm().then_some("as a SLURM job like this one, not on the login node");
    Next { command: crate::commands::shell_words(&words), note }
}

/// The shard of a file named as `scripts/slurm_array.sh` names them
/// (`<name>-<K>-of-<N>.h5`).
fn shard_in_name(path: &Path) -> Option<usize> {
    let stem = path.file_name()?.to_str()?.strip_suffix(".h5")?;
    let (head, n) = stem.rsplit_once("-of-")?;
    let (_, k) = head.rsplit_once('-')?;
    n.parse::<usize>().ok()?;
    k.parse().ok()
}

/// A merge's error with, in a job of `scripts/slurm_array.sh`, the shards
/// to resubmit in place of the advice to run `quakejoint sweep`: those
/// with jobs not run and those whose files are missing or unreadable (a
/// resubmitted shard rebuilds its file from its journal).
pub fn merge_error(err: quakejoint_sweep::SweepError, files: &[PathBuf], command: &str) -> anyhow::Error {
    use quakejoint_sweep::SweepError;
    let Some(prefix) = resubmit() else { return err.into() };
    let (text, shards) = match &err {
        SweepError::Incomplete { report, shards } => {
            let ks: Vec<usize> = shards.iter().map(|&(k, _)| k).collect();
            (format!("merge: the result would be incomplete: {report}"), ks)
        }
        _ => {
            let unreadable = |p: &&PathBuf| !p.exists() || quakejoint_sweep::sweep_h5::read_sweep(p).is_err();
            let mut ks: Vec<usize> = files.iter().filter(unreadable).filter_map(|p| shard_in_name(p)).collect();
            ks.sort_unstable();
            ks.dedup();
            (err.to_string(), ks)
        }
    };
    if shards.is_empty() {
        return err.into();
    }
    let again = resubmit_shards(&shards, false).unwrap_or(prefix);
    crate::commands::InputError(format!(
        "{text}\nresubmit the shards that are not done (each continues its journal; a new merge follows), on the \
         login node, in the directory slurm_array.sh was run from:\n  {again}\nor write a partial result (complete = \
         0): {command} --allow-partial"
    ))
    .into()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_are_read_from_the_script_s_file_names() {
        assert_eq!(shard_in_name(Path::new("shards/paper-3-of-16.h5")), Some(3));
        assert_eq!(shard_in_name(Path::new("shards/my-study-12-of-16.h5")), Some(12));
        assert_eq!(shard_in_name(Path::new("shards/paper.h5")), None);
        assert_eq!(shard_in_name(Path::new("shards/paper-3-of-16.h5.journal")), None);
    }
}
