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
    let mut per_field = |name: &str, jobs: Vec<usize>| {
        if !jobs.is_empty() {
            let shown: Vec<String> = jobs.iter().take(SHOWN).map(|&j| a.describe_job(j)).collect();
            let more = if jobs.len() > SHOWN { format!(" and {} more", jobs.len() - SHOWN) } else { String::new() };
            out.push(format!("{name} differs in {} jobs: {}{more}", jobs.len(), shown.join(", ")));
        }
    };
    let n = ra.status.len();
    per_field("status", (0..n).filter(|&j| ra.status[j] != rb.status[j]).collect());
    per_field("message", (0..n).filter(|&j| ra.messages[j] != rb.messages[j]).collect());
    per_field("validity", (0..n).filter(|&j| ra.validity[j] != rb.validity[j]).collect());
    per_field("findings", (0..n).filter(|&j| ra.findings[j] != rb.findings[j]).collect());
    for (k, name) in FIELDS.iter().enumerate() {
        if MACHINE_DEPENDENT.contains(name) {
            continue;
        }
        per_field(name, (0..n).filter(|&j| ra.values[k][j].to_bits() != rb.values[k][j].to_bits()).collect());
    }
    per_field(
        "histories",
        (0..n).filter(|&j| ra.histories.get(&(j as u32)) != rb.histories.get(&(j as u32))).collect(),
    );
    for (k, name) in ["sa", "psa", "sd", "sv"].iter().enumerate() {
        if !bits_equal(&ra.without[k], &rb.without[k]) {
            out.push(format!("the spectrum without the joint ({name}) differs"));
        }
    }
    out
}
