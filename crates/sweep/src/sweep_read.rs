//! Reading a sweep file back ([`read_sweep`]), for continuing a sweep,
//! `sweep --check`, `merge` and `compare`, and checking it on the way.
//!
//! Every dataset is read, and what can be derived from the rest is
//! checked against it, bit for bit: the reduction and the statistics
//! against the results, a history's period, damping, case, record and
//! validity against the grid and the results, a stored record's PGA
//! against its samples, the provenance of each record against the stored
//! record, the root attributes that count the jobs against the results. HDF5 checks each dataset's checksum on the way
//! ([`quakejoint_io::h5`]). A file that fails any of this is refused with the
//! dataset named: a damaged file is never taken for a good one.

use std::path::Path;

use hdf5::Group;

use crate::results::{Results, FIELDS, JOINT_FIELDS};
use crate::statistics::Statistics;
use crate::suite_h5::read_suite;
use crate::sweep_h5::{StoredModal, StoredRecord, SweepFile};
use quakejoint_io::h5::read_attr_str;
use quakejoint_io::read::{attr, attr_number, group, number, text, values};
use quakejoint_io::run_h5::{Provenance, RecordSource};
use quakejoint_io::OutputError;

/// Per-job fields that files written before schema 11 lack (read as NaN).
const SINCE_SCHEMA_11: [&str; 2] = ["peak_abutment_force", "max_impact_speed"];

/// Whether a run's or a joint's value is one that files written before
/// schema 14 lack (a fuse's: read as NaN, no joint had one).
fn since_schema_14(name: &str) -> bool {
    name.starts_with("fuse_")
}

/// Whether two arrays hold the same bits.
pub(crate) fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// The refusal of a dataset that disagrees with what it is derived from.
pub(crate) fn disagrees(what: &str, from: &str) -> hdf5::Error {
    hdf5::Error::from(format!(
        "{what} does not match {from} it is derived from: the file is damaged or was changed after it was written"
    ))
}

/// Reads what [`quakejoint_io::run_h5::write_provenance`] wrote.
fn read_provenance(file: &hdf5::File) -> hdf5::Result<Provenance> {
    let mut records = Vec::new();
    if file.link_exists("inputs") {
        let inputs = group(file, "inputs/records")?;
        for role in inputs.member_names()? {
            let g = group(&inputs, &role)?;
            records.push(RecordSource {
                name: attr(&g, "name")?,
                file: attr(&g, "file")?,
                sha256: attr(&g, "sha256")?,
                units: attr(&g, "file_units")?,
                samples: attr_number::<u64>(&g, "samples")? as usize,
                // absent in files written before channels were read
                channel: if g.attr("channel").is_ok() { attr(&g, "channel")? } else { String::new() },
                dt: number(&g, "dt")?,
                scale: number(&g, "scale")?,
                role,
            });
        }
    }
    Ok(Provenance {
        command: attr(file, "command")?,
        config_path: attr(file, "config_path")?,
        config_file: attr(file, "config_file")?,
        config: attr(file, "config")?,
        records,
        // absent in files of schema 3 written before warnings were kept
        warnings: read_attr_str(file, "warnings").map(|w| w.lines().map(str::to_string).collect()).unwrap_or_default(),
    })
}

/// The results with the joint and without it (`joints`: a bridge given by
/// its modes, with the names of its joints; `None`: a
/// single-DOF bridge).
fn read_results(spec: &Group, dims: [usize; 4], joints: Option<&[String]>) -> hdf5::Result<Results> {
    let mut results = match joints {
        Some(names) => Results::modal(dims, names),
        None => Results::new(dims),
    };
    let with = group(spec, "with_joint")?;
    for (k, name) in FIELDS.iter().enumerate() {
        results.values[k] = if (SINCE_SCHEMA_11.contains(name) || since_schema_14(name)) && !with.link_exists(name) {
            // not computed by the version that wrote the file
            vec![f64::NAN; dims.iter().product()]
        } else {
            values(&with, name)?
        };
    }
    results.status = values(&with, "status")?;
    results.messages = text(&with, "message")?;
    results.validity = values(&with, "validity")?;
    results.findings = text(&with, "findings")?;
    let without = group(spec, "without_joint")?;
    for (k, (name, _)) in quakejoint_model::fields::SPECTRAL.iter().enumerate() {
        results.without[k] = values(&without, name)?;
    }
    let n = dims.iter().product::<usize>();
    let m = if results.without_per_case { n } else { dims[1] * dims[2] * dims[3] };
    let sizes_ok = results.status.len() == n
        && results.values.iter().all(|v| v.len() == n)
        && results.messages.len() == n
        && results.validity.len() == n
        && results.findings.len() == n
        && results.without.iter().all(|v| v.len() == m);
    if !sizes_ok || dims.contains(&0) {
        return Err(hdf5::Error::from("the result arrays do not match the grid (case, record, damping, period)"));
    }
    Ok(results)
}

/// `/spectrum/reduction` and `/spectrum/statistics` against the results.
fn check_derived(spec: &Group, results: &Results, schema: u32) -> hdf5::Result<()> {
    if !same_bits(&values(spec, "reduction")?, &results.reduction()) {
        return Err(disagrees("/spectrum/reduction", "the spectra with and without the joint"));
    }
    if !spec.link_exists("statistics") {
        // files of schema 8 and before stored none for one record
        if results.dims[1] == 1 && schema < 9 {
            return Ok(());
        }
        return Err(hdf5::Error::from("/spectrum/statistics is missing"));
    }
    let st = Statistics::of(results);
    let g = group(spec, "statistics")?;
    let arrays: [(&str, &[f64]); 10] = [
        ("with_joint/mean", &st.with_mean),
        ("with_joint/median", &st.with_median),
        ("with_joint/dispersion", &st.with_dispersion),
        ("without_joint/mean", &st.without_mean),
        ("without_joint/median", &st.without_median),
        ("without_joint/dispersion", &st.without_dispersion),
        ("reduction/mean", &st.reduction_mean),
        ("reduction/median", &st.reduction_median),
        ("reduction/std", &st.reduction_std),
        ("reduction/of_mean", &st.reduction_of_mean),
    ];
    for (name, expected) in arrays {
        if !same_bits(&values(&g, name)?, expected) {
            return Err(disagrees(&format!("/spectrum/statistics/{name}"), "the results"));
        }
    }
    for (name, expected) in [("count", &st.count), ("flagged", &st.flagged)] {
        if &values::<u32>(&g, name)? != expected {
            return Err(disagrees(&format!("/spectrum/statistics/{name}"), "the results"));
        }
    }
    Ok(())
}

/// The schema from which `/joints/<k>` holds every joint, k from 0 (before:
/// the joints after the first, k from 1).
const EVERY_JOINT_SINCE: u32 = 13;

/// The first `k` of `/joints/<k>` in a file of `schema`.
fn first_joint(schema: u32) -> usize {
    usize::from(schema < EVERY_JOINT_SINCE)
}

/// The names of the joints in `/joints/<k>`.
fn joint_names(file: &hdf5::File, schema: u32) -> hdf5::Result<Vec<String>> {
    if !file.link_exists("joints") {
        return Ok(Vec::new());
    }
    let g = group(file, "joints")?;
    let count = g.member_names()?.len();
    let first = first_joint(schema);
    (first..first + count)
        .map(|k| {
            let joint: Group = group(&g, &k.to_string())?;
            attr(&joint, "name")
        })
        .collect()
}

/// The arrays of the joints (`/joints/<k>`), into `results`; a file
/// written before schema 13 lacks each joint's own peak bushing, friction
/// and abutment forces and friction energy (NaN).
fn read_joints(file: &hdf5::File, results: &mut Results, schema: u32) -> hdf5::Result<()> {
    let n = results.status.len();
    let first = first_joint(schema);
    for (k, joint) in results.joints.iter_mut().enumerate() {
        let at = format!("joints/{}", k + first);
        let g = group(file, &at)?;
        for (values, (name, _)) in joint.values.iter_mut().zip(JOINT_FIELDS.iter()) {
            let before_13 = schema < EVERY_JOINT_SINCE && JOINT_FIELDS_SINCE_13.contains(name);
            // (a joint's fastest impact: since schema 15)
            let since_15 = *name == "max_impact_speed";
            *values = match (before_13 || since_schema_14(name) || since_15) && !g.link_exists(name) {
                true => vec![f64::NAN; n],
                false => quakejoint_io::read::values(&g, name)?,
            };
        }
        joint.validity = quakejoint_io::read::values(&g, "validity")?;
        if joint.validity.len() != n || joint.values.iter().any(|v| v.len() != n) {
            return Err(hdf5::Error::from(format!("/{at} does not match the grid")));
        }
    }
    Ok(())
}

/// Each joint's values that files written before schema 13 lack.
const JOINT_FIELDS_SINCE_13: [&str; 4] =
    ["peak_abutment_force", "peak_bushing_force", "peak_friction_force", "friction_energy"];

/// The records stored in `/records`, each checked against its own PGA.
fn read_records(file: &hdf5::File, names: &[String]) -> hdf5::Result<Vec<StoredRecord>> {
    let recs = group(file, "records")?;
    let mut records = Vec::new();
    for name in names {
        let g = group(&recs, name)?;
        let r = StoredRecord {
            name: name.clone(),
            source: attr(&g, "source")?,
            sha256: attr(&g, "sha256")?,
            file_units: attr(&g, "file_units")?,
            dt: number(&g, "dt")?,
            scale: number(&g, "scale")?,
            pga: number(&g, "pga")?,
            acceleration: values(&g, "acceleration")?,
        };
        let pga = r.acceleration.iter().fold(0.0f64, |m, a| m.max(a.abs()));
        if pga.to_bits() != r.pga.to_bits() {
            return Err(disagrees(&format!("/records/{name}/pga"), "the record's acceleration"));
        }
        records.push(r);
    }
    Ok(records)
}

/// The provenance of each stored record must describe it.
fn check_inputs(provenance: &Provenance, records: &[StoredRecord]) -> hdf5::Result<()> {
    for r in records {
        let Some(p) = provenance.records.iter().find(|p| p.role == r.name) else {
            return Err(hdf5::Error::from(format!("/inputs/records has no entry for the record {}", r.name)));
        };
        let same = p.dt.to_bits() == r.dt.to_bits()
            && p.scale.to_bits() == r.scale.to_bits()
            && p.samples == r.acceleration.len()
            && (&p.sha256, &p.units, &p.file) == (&r.sha256, &r.file_units, &r.source);
        if !same {
            return Err(disagrees(&format!("/inputs/records/{}", r.name), "the stored record"));
        }
    }
    Ok(())
}

/// The root attributes that count the jobs, against the results.
fn check_counts(file: &hdf5::File, f: &SweepFile) -> hdf5::Result<()> {
    let r = &f.results;
    let complete = f.scope.iter().all(|&j| r.status[j as usize] != crate::results::status::NOT_RUN);
    for (name, expected) in [
        ("jobs_total", r.status.len() as u64),
        ("jobs_in_scope", f.scope.len() as u64),
        ("jobs_finished", r.finished() as u64),
        ("jobs_failed", r.failed() as u64),
        ("jobs_flagged", r.flagged() as u64),
    ] {
        if attr_number::<u64>(file, name)? != expected {
            return Err(disagrees(&format!("the root attribute {name}"), "the results"));
        }
    }
    if attr_number::<u8>(file, "complete")? != u8::from(complete) {
        return Err(disagrees("the root attribute complete", "the results"));
    }
    Ok(())
}

/// The histories in `/histories`, each checked against the grid and the
/// job's results.
fn read_histories(file: &hdf5::File, f: &mut SweepFile) -> hdf5::Result<()> {
    if !file.link_exists("histories") {
        return Ok(());
    }
    let hist = group(file, "histories")?;
    let d = f.results.dims;
    for name in hist.member_names()? {
        let g = group(&hist, &name)?;
        let job = attr_number::<u64>(&g, "job")?;
        if name != format!("job_{job}") || job >= f.results.status.len() as u64 {
            return Err(hdf5::Error::from(format!("/histories/{name} names job {job}, not its own")));
        }
        let j = job as usize;
        let (c, r, z, t) = (j / (d[1] * d[2] * d[3]), j / (d[2] * d[3]) % d[1], j / d[3] % d[2], j % d[3]);
        let axis_ok = match &f.modal {
            Some(m) => number(&g, "period_scale")?.to_bits() == m.period_scales[t].to_bits(),
            None => number(&g, "period")?.to_bits() == f.periods[t].to_bits(),
        };
        let meta_ok = attr(&g, "case")? == f.cases[c]
            && attr(&g, "record")? == f.records[r].name
            && number(&g, "damping")?.to_bits() == f.damping[z].to_bits()
            && axis_ok
            && attr_number::<u32>(&g, "validity")? == f.results.validity[j]
            && attr(&g, "validity_label")? == quakejoint_model::validity::Flags(f.results.validity[j]).label()
            && attr(&g, "findings")? == f.results.findings[j];
        if !meta_ok {
            return Err(disagrees(&format!("/histories/{name}"), "the grid and the job's results"));
        }
        let h = quakejoint_io::run_h5::read_history(&g)?;
        f.results.histories.insert(job as u32, h);
    }
    Ok(())
}

/// Why a sweep file is refused, with what to do about it, in the words
/// every reader uses (the command line's `compare`, Python's `read_sweep`).
pub fn refusal(e: &OutputError) -> String {
    format!(
        "{}: not a readable sweep file ({}) (a sweep's output: run the sweep again, which rebuilds it from its \
         journal; a merged file: merge its shards again)",
        e.path, e.message
    )
}

/// Reads a sweep file written by [`crate::sweep_h5::write_sweep`], every
/// dataset of it, and checks what is derived against what it is derived
/// from (module doc).
pub fn read_sweep(path: &Path) -> Result<SweepFile, OutputError> {
    let inner = || -> hdf5::Result<SweepFile> {
        let file = quakejoint_io::read::open(path)?;
        quakejoint_io::read::check_attributes(&file)?;
        if attr(&file, "kind")? != "sweep" {
            return Err(hdf5::Error::from("not a sweep file (attribute kind != sweep)"));
        }
        let spec = group(&file, "spectrum")?;
        // a bridge given by its modes: the period axis is its period scales
        let modal = if spec.link_exists("period_scale") {
            Some(StoredModal {
                period_scales: values(&spec, "period_scale")?,
                modes_file: attr(&file, "modes_file")?,
                modes_sha256: attr(&file, "modes_sha256")?,
            })
        } else {
            None
        };
        let periods: Vec<f64> = values(&spec, if modal.is_some() { "longest_period" } else { "period" })?;
        if modal.as_ref().is_some_and(|m| m.period_scales.len() != periods.len()) {
            return Err(hdf5::Error::from("/spectrum/longest_period does not match /spectrum/period_scale"));
        }
        let damping: Vec<f64> = values(&spec, "damping")?;
        let record_names = text(&spec, "record")?;
        let cases = text(&spec, "case")?;
        let scope: Vec<u32> = values(&spec, "scope")?;
        let dims = [cases.len(), record_names.len(), damping.len(), periods.len()];
        let schema = attr_number::<u32>(&file, "schema_version")?;
        let joints = joint_names(&file, schema)?;
        let mut results = read_results(&spec, dims, modal.is_some().then_some(&joints[..]))?;
        if modal.is_none() && !joints.is_empty() {
            return Err(hdf5::Error::from("/joints: the joints of a sweep belong to a bridge given by its modes"));
        }
        read_joints(&file, &mut results, schema)?;
        let n = results.status.len();
        if let Some(&j) = scope.iter().find(|&&j| j as usize >= n) {
            return Err(hdf5::Error::from(format!("/spectrum/scope names job {j}, beyond the sweep's jobs")));
        }
        check_derived(&spec, &results, schema)?;
        let records = read_records(&file, &record_names)?;
        let provenance = read_provenance(&file)?;
        check_inputs(&provenance, &records)?;
        let case_configs = text(&spec, "case_config")?;
        if case_configs.len() != cases.len() {
            return Err(hdf5::Error::from("/spectrum/case_config does not match the cases"));
        }
        let mut f = SweepFile {
            provenance,
            case_configs,
            config_sha256: attr(&file, "config_sha256")?,
            shard: attr(&file, "shard")?,
            scope,
            periods,
            modal,
            damping,
            cases,
            records,
            suite: read_suite(&file)?,
            fragility: None,
            results,
        };
        f.fragility = crate::fragility::read_fragility(&file, &f.results)?;
        read_histories(&file, &mut f)?;
        check_counts(&file, &f)?;
        Ok(f)
    };
    inner().map_err(|e| OutputError::hdf5(path, e))
}
