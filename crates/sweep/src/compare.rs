//! Comparing two sweep files (`quakejoint compare`): are their results the
//! same, bit for bit? Every dataset is compared (the derived ones, the
//! reduction and the statistics, are checked against the results when the
//! files are read, [`crate::sweep_read`]). The run-specific fields are
//! left out: the wall times ([`MACHINE_DEPENDENT`]), the creation time, the
//! command, the shard and the config's text and each case's (their
//! parameters are compared through the config's hash).

use quakejoint_model::run::Histories;

use crate::results::{FIELDS, JOINT_FIELDS, MACHINE_DEPENDENT};
use crate::suite_h5::StoredSuite;
use crate::sweep_h5::{StoredRecord, SweepFile};
use crate::sweep_read::same_bits as bits_equal;
use quakejoint_io::run_h5::RecordSource;

/// How many differences of one kind are listed before the rest is counted.
const SHOWN: usize = 5;

fn records_equal(a: &[StoredRecord], b: &[StoredRecord]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            (&x.name, &x.source, &x.sha256, &x.file_units) == (&y.name, &y.source, &y.sha256, &y.file_units)
                && bits_equal(&[x.dt, x.scale, x.pga], &[y.dt, y.scale, y.pga])
                && bits_equal(&x.acceleration, &y.acceleration)
        })
}

/// The records' provenance, by role: HDF5 lists a group's members in the
/// order of its name index, which is not the config's order once a group
/// holds more than 8 (dense storage, hashed names).
fn inputs_equal(a: &[RecordSource], b: &[RecordSource]) -> bool {
    let by_role = |v: &[RecordSource]| {
        let mut v: Vec<RecordSource> = v.to_vec();
        v.sort_by(|x, y| x.role.cmp(&y.role));
        v
    };
    let (a, b) = (by_role(a), by_role(b));
    a.len() == b.len()
        && a.iter().zip(&b).all(|(x, y)| {
            (&x.role, &x.name, &x.file, &x.sha256, &x.units, x.samples)
                == (&y.role, &y.name, &y.file, &y.sha256, &y.units, y.samples)
                // files written before channels were read do not say
                && (x.channel == y.channel || x.channel.is_empty() || y.channel.is_empty())
                && bits_equal(&[x.dt, x.scale], &[y.dt, y.scale])
        })
}

fn suites_equal(a: &Option<StoredSuite>, b: &Option<StoredSuite>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(x), Some(y)) => {
            (&x.target, &x.target_config, &x.rule, x.ec8_satisfied)
                == (&y.target, &y.target_config, &y.rule, y.ec8_satisfied)
                && bits_equal(&x.range, &y.range)
                && bits_equal(&x.factors, &y.factors)
                && bits_equal(&[x.rule_factor, x.pga_ratio], &[y.rule_factor, y.pga_ratio])
                && bits_equal(&x.min_ratio, &y.min_ratio)
                && bits_equal(&x.fit_periods, &y.fit_periods)
                && bits_equal(&x.fit_target, &y.fit_target)
                && bits_equal(&x.fit_mean, &y.fit_mean)
                && bits_equal(&x.target_sa, &y.target_sa)
        }
        _ => false,
    }
}

/// Whether two jobs' histories are the same; the wider ends of the
/// sub-gaps only where both files hold them (files written before they were
/// stored do not).
pub(crate) fn histories_equal(a: Option<&Histories>, b: Option<&Histories>) -> bool {
    match (a, b) {
        (Some(x), Some(y)) if x.subgaps_wide.is_empty() != y.subgaps_wide.is_empty() => {
            let strip = |h: &Histories| Histories { subgaps_wide: Vec::new(), ..h.clone() };
            strip(x) == strip(y)
        }
        _ => a == b,
    }
}

/// What [`sweep_differences`] says of two multiple-stripe sweeps fitted
/// with other limit states or fitting.
pub const SPECS_DIFFER: &str = "the limit states or their fitting (/fragility attribute config) differ";

/// The differences between two sweep files in everything but the jobs'
/// results: the config (its parameters, by their hash: each case's config
/// as text also holds the run limits, which may change), the grids, the
/// records and their provenance, the suite and the spectra without the
/// joint (empty: the same sweep). A grid that differs is reported alone.
pub fn sweep_differences(a: &SweepFile, b: &SweepFile) -> Vec<String> {
    let mut out = Vec::new();
    if a.config_sha256 != b.config_sha256 {
        out.push("the configs differ (their parameters)".to_string());
    }
    let scales = |f: &SweepFile| f.modal.as_ref().map(|m| m.period_scales.clone());
    let same_scales = match (scales(a), scales(b)) {
        (Some(x), Some(y)) => bits_equal(&x, &y),
        (x, y) => x.is_none() && y.is_none(),
    };
    let names = |f: &SweepFile| f.results.joints.iter().map(|j| j.name.clone()).collect::<Vec<_>>();
    if !bits_equal(&a.periods, &b.periods)
        || !same_scales
        || !bits_equal(&a.damping, &b.damping)
        || a.cases != b.cases
        || names(a) != names(b)
    {
        out.push("the grids differ (periods or period scales, damping ratios, cases or joints)".to_string());
        return out;
    }
    if a.modal.as_ref().map(|m| &m.modes_sha256) != b.modal.as_ref().map(|m| &m.modes_sha256) {
        out.push("the modes files differ (their contents)".to_string());
    }
    if !records_equal(&a.records, &b.records) {
        out.push("the records (/records) differ".to_string());
    }
    if !inputs_equal(&a.provenance.records, &b.provenance.records) {
        out.push("the records' provenance (/inputs/records) differs".to_string());
    }
    if !suites_equal(&a.suite, &b.suite) {
        out.push("the suites (/suite) differ".to_string());
    }
    match (&a.fragility, &b.fragility) {
        (Some(x), Some(y)) => {
            if x.stripes != y.stripes {
                out.push("the stripes (/fragility: levels, records, factors) differ".to_string());
            }
            if x.spec != y.spec {
                out.push(SPECS_DIFFER.to_string());
            }
        }
        (None, None) => {}
        _ => out.push("one file is a multiple-stripe sweep (/fragility), the other is not".to_string()),
    }
    for (k, (name, _)) in quakejoint_model::fields::SPECTRAL.iter().enumerate() {
        if !bits_equal(&a.results.without[k], &b.results.without[k]) {
            out.push(format!("the spectrum without the joint ({name}) differs"));
        }
    }
    out
}

/// The differences between two sweep files, in words (empty: identical).
pub fn differences(a: &SweepFile, b: &SweepFile) -> Vec<String> {
    let mut out = sweep_differences(a, b);
    if out.iter().any(|d| d.starts_with("the grids differ")) {
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
    per_field("histories", differ(&|j| !histories_equal(ra.histories.get(&(j as u32)), rb.histories.get(&(j as u32)))));
    // every joint (the grids' check made their names equal)
    for (ja, jb) in ra.joints.iter().zip(&rb.joints) {
        for (k, (name, _)) in JOINT_FIELDS.iter().enumerate() {
            let what = format!("joint {:?}: {name}", ja.name);
            per_field(&what, differ(&|j| ja.values[k][j].to_bits() != jb.values[k][j].to_bits()));
        }
        per_field(&format!("joint {:?}: validity", ja.name), differ(&|j| ja.validity[j] != jb.validity[j]));
    }
    out
}
