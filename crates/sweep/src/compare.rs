//! Comparing two sweep files (`quakejoint compare`): are their results the
//! same, bit for bit? The run-specific fields are left out: the wall times
//! ([`MACHINE_DEPENDENT`]), the creation time, the shard and the config's
//! text (its parameters are compared through their hash).

use crate::results::{FIELDS, MACHINE_DEPENDENT};
use crate::sweep_h5::SweepFile;

/// How many differences of one kind are listed before the rest is counted.
const SHOWN: usize = 5;

fn bits_equal(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// The differences between two sweep files, in words (empty: identical).
pub fn differences(a: &SweepFile, b: &SweepFile) -> Vec<String> {
    let mut out = Vec::new();
    if a.config_sha256 != b.config_sha256 {
        out.push("the configs differ (their parameters)".to_string());
    }
    if !bits_equal(&a.periods, &b.periods) || !bits_equal(&a.damping, &b.damping) || a.cases != b.cases {
        out.push("the grids differ (periods, damping ratios or cases)".to_string());
        return out;
    }
    if a.records != b.records {
        out.push("the records differ".to_string());
        return out;
    }
    let (ra, rb) = (&a.results, &b.results);
    // a job that ran in one file only is reported once, and left out of
    // the comparison of values
    let n = ra.status.len();
    let not_run = |r: &crate::results::Results, j: usize| r.status[j] == crate::results::status::NOT_RUN;
    let only_a: Vec<usize> = (0..n).filter(|&j| !not_run(ra, j) && not_run(rb, j)).collect();
    let only_b: Vec<usize> = (0..n).filter(|&j| not_run(ra, j) && !not_run(rb, j)).collect();
    for (jobs, has, lacks) in [(&only_a, "the first", "the second"), (&only_b, "the second", "the first")] {
        if !jobs.is_empty() {
            out.push(format!(
                "{} jobs have results in {has} file only ({lacks} is partial or a shard: `complete` = 0), e.g. {}",
                jobs.len(),
                a.describe_job(jobs[0])
            ));
        }
    }
    let both: Vec<usize> = (0..n).filter(|&j| not_run(ra, j) == not_run(rb, j)).collect();
    let mut per_field = |name: &str, jobs: Vec<usize>| {
        if !jobs.is_empty() {
            let shown: Vec<String> = jobs.iter().take(SHOWN).map(|&j| a.describe_job(j)).collect();
            let more = if jobs.len() > SHOWN { format!(" and {} more", jobs.len() - SHOWN) } else { String::new() };
            out.push(format!("{name} differs in {} jobs: {}{more}", jobs.len(), shown.join(", ")));
        }
    };
    let differ = |f: &dyn Fn(usize) -> bool| both.iter().copied().filter(|&j| f(j)).collect::<Vec<_>>();
    per_field("status", differ(&|j| ra.status[j] != rb.status[j]));
    per_field("message", differ(&|j| ra.messages[j] != rb.messages[j]));
    per_field("validity", differ(&|j| ra.validity[j] != rb.validity[j]));
    per_field("findings", differ(&|j| ra.findings[j] != rb.findings[j]));
    for (k, name) in FIELDS.iter().enumerate() {
        if MACHINE_DEPENDENT.contains(name) {
            continue;
        }
        per_field(name, differ(&|j| ra.values[k][j].to_bits() != rb.values[k][j].to_bits()));
    }
    per_field("histories", differ(&|j| ra.histories.get(&(j as u32)) != rb.histories.get(&(j as u32))));
    for (k, name) in ["sa", "psa", "sd", "sv"].iter().enumerate() {
        if !bits_equal(&ra.without[k], &rb.without[k]) {
            out.push(format!("the spectrum without the joint ({name}) differs"));
        }
    }
    out
}
