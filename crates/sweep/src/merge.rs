//! Combining the outputs of shards (`quakejoint merge`).
//!
//! Shards of one sweep share the config, the records and the grids; each
//! holds the results of its own jobs (the others marked not run). The merged
//! file takes every job from the shard that ran it; a job run by two shards
//! must have the same numbers (the runs are deterministic). Its numeric
//! datasets are identical to those of an unsharded run (except the
//! machine-dependent wall times).

use std::path::{Path, PathBuf};

use crate::error::SweepError;
use crate::results::{status, Results, FIELDS, MACHINE_DEPENDENT};
use crate::sweep_h5::{read_sweep, write_sweep};

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
}

fn same_bits(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits()
}

/// Merges shard files into `output`.
pub fn merge(inputs: &[PathBuf], output: &Path) -> Result<MergeSummary, SweepError> {
    let first = inputs.first().ok_or_else(|| SweepError::Merge("no input files".into()))?;
    let mut merged = read_sweep(first)?;
    for path in &inputs[1..] {
        let other = read_sweep(path)?;
        let what = |field: &str| {
            SweepError::Merge(format!(
                "{} and {} are not shards of one sweep: their {field} differ",
                first.display(),
                path.display()
            ))
        };
        if other.config != merged.config {
            return Err(what("configs"));
        }
        if other.periods != merged.periods || other.damping != merged.damping {
            return Err(what("periods or damping ratios"));
        }
        if other.cases != merged.cases {
            return Err(what("cases"));
        }
        if other.records != merged.records {
            return Err(what("records"));
        }
        let r = &other.results;
        for (k, (a, b)) in merged.results.without.iter().zip(&r.without).enumerate() {
            if a.iter().zip(b).any(|(x, y)| !same_bits(*x, *y)) {
                return Err(what(&format!("spectra without the joint ({})", ["sa", "psa", "sd", "sv"][k])));
            }
        }
        combine(&mut merged.results, r, &path.display().to_string())?;
    }
    let results = &merged.results;
    merged.shard = if results.finished() == results.status.len() { "all".into() } else { "merged".into() };
    write_sweep(output, &merged)?;
    Ok(MergeSummary {
        output: output.to_path_buf(),
        jobs: results.status.len(),
        finished: results.finished(),
        failed: results.failed(),
    })
}

fn combine(into: &mut Results, from: &Results, source: &str) -> Result<(), SweepError> {
    for j in 0..from.status.len() {
        if from.status[j] == status::NOT_RUN {
            continue;
        }
        if into.status[j] != status::NOT_RUN {
            let differs = FIELDS
                .iter()
                .enumerate()
                .filter(|(_, name)| !MACHINE_DEPENDENT.contains(name))
                .any(|(k, _)| !same_bits(into.values[k][j], from.values[k][j]));
            if differs || into.status[j] != from.status[j] {
                return Err(SweepError::Merge(format!("job {j} was run twice with different results ({source})")));
            }
            continue;
        }
        for k in 0..FIELDS.len() {
            into.values[k][j] = from.values[k][j];
        }
        into.status[j] = from.status[j];
        into.messages[j] = from.messages[j].clone();
        if let Some(h) = from.histories.get(&(j as u32)) {
            into.histories.insert(j as u32, h.clone());
        }
    }
    Ok(())
}
