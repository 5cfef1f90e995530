//! The HDF5 file of a sweep (layout in `docs/hdf5-layout.md`): written from
//! a plan and its results, and read back for `quakejoint merge`.

use std::path::Path;

use hdf5::types::VarLenUnicode;
use ndarray::{ArrayView1, ArrayView3, ArrayView4};

use crate::error::OutputError;
use crate::h5::{attr_f64, attr_str, write_atomically, VERSION};
use crate::results::{JobHistory, Results, FIELDS, UNITS};

/// Version of the sweep file layout.
pub const SCHEMA_VERSION: u32 = 2;

/// A record as stored in `/records/<name>`.
#[derive(Debug, Clone, PartialEq)]
pub struct StoredRecord {
    /// Name.
    pub name: String,
    /// File it was read from.
    pub source: String,
    /// Time step [s].
    pub dt: f64,
    /// Scale factor applied (file numbers to m/s^2).
    pub scale: f64,
    /// Peak ground acceleration [m/s^2].
    pub pga: f64,
    /// Acceleration [m/s^2].
    pub acceleration: Vec<f64>,
}

/// Everything in a sweep file.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepFile {
    /// The config's TOML text.
    pub config: String,
    /// SHA-256 of the parsed config, as in the journal's header (shards of
    /// one sweep share it).
    pub config_sha256: String,
    /// `"k/n"` for a shard, `"all"` for a whole sweep, `"merged"` for a
    /// merge of shards.
    pub shard: String,
    /// The jobs this file is responsible for (flat indices): its shard's,
    /// or every job.
    pub scope: Vec<u32>,
    /// Bridge periods [s].
    pub periods: Vec<f64>,
    /// Damping ratios [-].
    pub damping: Vec<f64>,
    /// Case names.
    pub cases: Vec<String>,
    /// Records.
    pub records: Vec<StoredRecord>,
    /// The result arrays.
    pub results: Results,
}

fn vlu(s: &str) -> hdf5::Result<VarLenUnicode> {
    s.parse().map_err(|e| hdf5::Error::from(format!("{e}")))
}

fn strings(data: &[String]) -> hdf5::Result<Vec<VarLenUnicode>> {
    data.iter().map(|s| vlu(s)).collect()
}

fn ds4(g: &hdf5::Group, name: &str, dims: [usize; 4], data: &[f64], units: &str) -> hdf5::Result<()> {
    let view = ArrayView4::from_shape((dims[0], dims[1], dims[2], dims[3]), data)
        .map_err(|e| hdf5::Error::from(e.to_string()))?;
    let ds = g.new_dataset_builder().with_data(view).create(name)?;
    attr_str(&ds, "units", units)
}

/// Writes a sweep file atomically.
pub fn write_sweep(path: &Path, f: &SweepFile) -> Result<(), OutputError> {
    write_atomically(path, |file| {
        attr_str(file, "quakejoint_version", VERSION)?;
        file.new_attr::<u32>().create("schema_version")?.write_scalar(&SCHEMA_VERSION)?;
        attr_str(file, "kind", "sweep")?;
        attr_str(file, "config", &f.config)?;
        attr_str(file, "created", &crate::time::utc_now())?;
        attr_str(file, "config_sha256", &f.config_sha256)?;
        attr_str(file, "shard", &f.shard)?;
        let r = &f.results;
        file.new_attr::<u64>().create("jobs_total")?.write_scalar(&(r.status.len() as u64))?;
        file.new_attr::<u64>().create("jobs_in_scope")?.write_scalar(&(f.scope.len() as u64))?;
        file.new_attr::<u64>().create("jobs_finished")?.write_scalar(&(r.finished() as u64))?;
        file.new_attr::<u64>().create("jobs_failed")?.write_scalar(&(r.failed() as u64))?;
        let complete = f.scope.iter().all(|&j| r.status[j as usize] != crate::results::status::NOT_RUN);
        file.new_attr::<u8>().create("complete")?.write_scalar(&u8::from(complete))?;

        let spec = file.create_group("spectrum")?;
        crate::h5::dataset_1d(&spec, "period", &f.periods, "s")?;
        crate::h5::dataset_1d(&spec, "damping", &f.damping, "-")?;
        let names: Vec<String> = f.records.iter().map(|r| r.name.clone()).collect();
        spec.new_dataset_builder().with_data(ArrayView1::from(&strings(&names)?)).create("record")?;
        spec.new_dataset_builder().with_data(ArrayView1::from(&strings(&f.cases)?)).create("case")?;
        let scope = spec.new_dataset_builder().with_data(ArrayView1::from(&f.scope)).create("scope")?;
        attr_str(&scope, "meaning", "flat indices of the jobs this file is responsible for (its shard's, or all)")?;

        let d = r.dims;
        let without = spec.create_group("without_joint")?;
        for (k, name) in ["sa", "psa", "sd", "sv"].iter().enumerate() {
            let view = ArrayView3::from_shape((d[1], d[2], d[3]), &r.without[k])
                .map_err(|e| hdf5::Error::from(e.to_string()))?;
            let ds = without.new_dataset_builder().with_data(view).create(*name)?;
            attr_str(&ds, "units", ["m/s^2", "m/s^2", "m", "m/s"][k])?;
        }
        let with = spec.create_group("with_joint")?;
        for (k, name) in FIELDS.iter().enumerate() {
            ds4(&with, name, d, &r.values[k], UNITS[k])?;
        }
        let status = ArrayView4::from_shape((d[0], d[1], d[2], d[3]), &r.status)
            .map_err(|e| hdf5::Error::from(e.to_string()))?;
        let ds = with.new_dataset_builder().with_data(status).create("status")?;
        attr_str(&ds, "meaning", "0 ok, 1 simulation failed, 2 invalid parameters, 3 time or step limit, -1 not run")?;
        let msgs = strings(&r.messages)?;
        let msgs =
            ArrayView4::from_shape((d[0], d[1], d[2], d[3]), &msgs).map_err(|e| hdf5::Error::from(e.to_string()))?;
        with.new_dataset_builder().with_data(msgs).create("message")?;
        ds4(&spec, "reduction", d, &r.reduction(), "-")?;
        crate::fault::point(crate::fault::Point::Checkpoint, path);

        let recs = file.create_group("records")?;
        for rec in &f.records {
            let g = recs.create_group(&rec.name)?;
            let ds = g.new_dataset_builder().with_data(ArrayView1::from(&rec.acceleration)).create("acceleration")?;
            attr_str(&ds, "units", "m/s^2")?;
            attr_f64(&ds, "dt", rec.dt)?;
            attr_str(&ds, "source", &rec.source)?;
            attr_f64(&ds, "scale", rec.scale)?;
            attr_f64(&ds, "pga", rec.pga)?;
        }
        if !r.histories.is_empty() {
            let hist = file.create_group("histories")?;
            for (&job, h) in &r.histories {
                write_history(&hist, job, d, f, h)?;
            }
        }
        Ok(())
    })
}

fn write_history(hist: &hdf5::Group, job: u32, d: [usize; 4], f: &SweepFile, h: &JobHistory) -> hdf5::Result<()> {
    let j = job as usize;
    let (c, rr, z, t) = (j / (d[1] * d[2] * d[3]), j / (d[2] * d[3]) % d[1], j / d[3] % d[2], j % d[3]);
    let g = hist.create_group(&format!("job_{job}"))?;
    attr_str(&g, "case", &f.cases[c])?;
    attr_str(&g, "record", &f.records[rr].name)?;
    attr_f64(&g, "damping", f.damping[z])?;
    attr_f64(&g, "period", f.periods[t])?;
    g.new_attr::<u64>().create("job")?.write_scalar(&(job as u64))?;
    crate::h5::dataset_1d(&g, "t", &h.t, "s")?;
    crate::h5::dataset_1d(&g, "ag", &h.ag, "m/s^2")?;
    crate::h5::dataset_1d(&g, "u", &h.u, "m")?;
    crate::h5::dataset_1d(&g, "a_abs", &h.a_abs, "m/s^2")?;
    crate::h5::dataset_1d(&g, "a_abs_without_joint", &h.a_abs_without_joint, "m/s^2")?;
    crate::h5::dataset_1d(&g, "joint_force", &h.joint_force, "N")?;
    crate::h5::dataset_1d(&g, "friction_power", &h.friction_power, "W")
}

fn read_strings(ds: &hdf5::Dataset) -> hdf5::Result<Vec<String>> {
    Ok(ds.read_raw::<VarLenUnicode>()?.iter().map(|s| s.as_str().to_string()).collect())
}

fn read_attr_str(loc: &hdf5::Location, name: &str) -> hdf5::Result<String> {
    Ok(loc.attr(name)?.read_scalar::<VarLenUnicode>()?.as_str().to_string())
}

/// Reads a sweep file written by [`write_sweep`].
pub fn read_sweep(path: &Path) -> Result<SweepFile, OutputError> {
    let inner = || -> hdf5::Result<SweepFile> {
        let file = hdf5::File::open(path)?;
        if read_attr_str(&file, "kind")? != "sweep" {
            return Err(hdf5::Error::from("not a sweep file (attribute kind != sweep)"));
        }
        let spec = file.group("spectrum")?;
        let periods: Vec<f64> = spec.dataset("period")?.read_raw()?;
        let damping: Vec<f64> = spec.dataset("damping")?.read_raw()?;
        let record_names = read_strings(&spec.dataset("record")?)?;
        let cases = read_strings(&spec.dataset("case")?)?;
        let scope: Vec<u32> = spec.dataset("scope")?.read_raw()?;
        let dims = [cases.len(), record_names.len(), damping.len(), periods.len()];
        let mut results = Results::new(dims);
        let with = spec.group("with_joint")?;
        for (k, name) in FIELDS.iter().enumerate() {
            results.values[k] = with.dataset(name)?.read_raw()?;
        }
        results.status = with.dataset("status")?.read_raw()?;
        results.messages = read_strings(&with.dataset("message")?)?;
        let without = spec.group("without_joint")?;
        for (k, name) in ["sa", "psa", "sd", "sv"].iter().enumerate() {
            results.without[k] = without.dataset(name)?.read_raw()?;
        }
        let (n, m) = (dims.iter().product::<usize>(), dims[1] * dims[2] * dims[3]);
        let sizes_ok = results.status.len() == n
            && results.values.iter().all(|v| v.len() == n)
            && results.messages.len() == n
            && results.without.iter().all(|v| v.len() == m);
        if !sizes_ok || dims.contains(&0) {
            return Err(hdf5::Error::from("the result arrays do not match the grid (case, record, damping, period)"));
        }
        if let Some(&j) = scope.iter().find(|&&j| j as usize >= n) {
            return Err(hdf5::Error::from(format!("scope names job {j}, beyond the sweep's jobs")));
        }
        let recs = file.group("records")?;
        let mut records = Vec::new();
        for name in &record_names {
            let ds = recs.group(name)?.dataset("acceleration")?;
            records.push(StoredRecord {
                name: name.clone(),
                source: read_attr_str(&ds, "source")?,
                dt: ds.attr("dt")?.read_scalar()?,
                scale: ds.attr("scale")?.read_scalar()?,
                pga: ds.attr("pga")?.read_scalar()?,
                acceleration: ds.read_raw()?,
            });
        }
        if let Ok(hist) = file.group("histories") {
            for name in hist.member_names()? {
                let g = hist.group(&name)?;
                let job: u64 = g.attr("job")?.read_scalar()?;
                if job >= n as u64 {
                    return Err(hdf5::Error::from(format!("history {name} names job {job}, beyond the sweep's jobs")));
                }
                let read = |n: &str| -> hdf5::Result<Vec<f64>> { g.dataset(n)?.read_raw() };
                results.histories.insert(
                    job as u32,
                    JobHistory {
                        t: read("t")?,
                        ag: read("ag")?,
                        u: read("u")?,
                        a_abs: read("a_abs")?,
                        a_abs_without_joint: read("a_abs_without_joint")?,
                        joint_force: read("joint_force")?,
                        friction_power: read("friction_power")?,
                    },
                );
            }
        }
        Ok(SweepFile {
            config: read_attr_str(&file, "config")?,
            config_sha256: read_attr_str(&file, "config_sha256")?,
            shard: read_attr_str(&file, "shard")?,
            scope,
            periods,
            damping,
            cases,
            records,
            results,
        })
    };
    inner().map_err(|e| OutputError::hdf5(path, e))
}

impl SweepFile {
    /// A job in words: `case / record / damping / period`.
    pub fn describe_job(&self, job: usize) -> String {
        let d = self.results.dims;
        let (c, r, z, t) = (job / (d[1] * d[2] * d[3]), job / (d[2] * d[3]) % d[1], job / d[3] % d[2], job % d[3]);
        format!(
            "job {job} ({} / {} / damping {} / T {} s)",
            self.cases[c], self.records[r].name, self.damping[z], self.periods[t]
        )
    }
}
