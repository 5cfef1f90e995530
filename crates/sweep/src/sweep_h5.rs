//! The HDF5 file of a sweep (layout in `docs/hdf5-layout.md`): written from
//! a plan and its results (read back by [`crate::sweep_read`]).

use std::path::Path;

use ndarray::{ArrayView3, ArrayView4};

use quakejoint_model::run::Histories;

use crate::results::{Results, FIELDS, JOINT_FIELDS, UNITS};
use crate::statistics::Statistics;
use crate::suite_h5::{write_statistics, write_suite, StoredSuite};
pub use crate::sweep_read::read_sweep;
use quakejoint_io::h5::{array, attr_str, label_axes, scalar, strings, strings_1d, write_atomically};
use quakejoint_io::run_h5::{write_provenance, Provenance};
use quakejoint_io::OutputError;

/// Version of the sweep file layout (10: sweeps over a bridge given by
/// its modes; 11: `/fragility`, and the per-job fields
/// `peak_abutment_force` and `max_impact_speed`; 12: attribute text
/// fixed-length, under the metadata checksums, and each fragility curve's
/// bootstrap key and counts; 13: `/joints/<k>` holds every joint of a
/// bridge given by its modes, k from 0, each with its own peak bushing,
/// friction and abutment forces and friction energy; 14: each joint's
/// fuse, `fuse_*`, per job and per joint, read as NaN from older files;
/// 15: each joint's `max_impact_speed`, read as NaN from older files).
pub const SCHEMA_VERSION: u32 = 15;

/// What a sweep over a bridge given by its modes stores beside the grid.
#[derive(Debug, Clone, PartialEq)]
pub struct StoredModal {
    /// The swept factors on every period of the modes [-]
    /// (`/spectrum/period_scale`).
    pub period_scales: Vec<f64>,
    /// The modes file as the config names it (root attribute `modes_file`).
    pub modes_file: String,
    /// SHA-256 of its bytes (root attribute `modes_sha256`).
    pub modes_sha256: String,
}

/// A record as stored in `/records/<name>`.
#[derive(Debug, Clone, PartialEq)]
pub struct StoredRecord {
    /// Name.
    pub name: String,
    /// File it was read from.
    pub source: String,
    /// SHA-256 of the file's bytes.
    pub sha256: String,
    /// Units of the numbers in the file.
    pub file_units: String,
    /// Time step \[s\].
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
    /// The command, the config (as read: a sweep has no overrides) and
    /// every record file with its hash (the x records and `[record_y]`).
    pub provenance: Provenance,
    /// SHA-256 of the parsed config, as in the journal's header (shards of
    /// one sweep share it).
    pub config_sha256: String,
    /// `"k/n"` for a shard, `"all"` for a whole sweep or a complete merge,
    /// `"partial"` for a merge with jobs missing.
    pub shard: String,
    /// The jobs this file is responsible for (flat indices): its shard's,
    /// or every job.
    pub scope: Vec<u32>,
    /// Bridge periods \[s\] (a bridge given by its modes: its longest kept
    /// period at each period scale, `/spectrum/longest_period`).
    pub periods: Vec<f64>,
    /// A bridge given by its modes: the swept period scales (the period
    /// axis) and the modes file.
    pub modal: Option<StoredModal>,
    /// Damping ratios [-].
    pub damping: Vec<f64>,
    /// Case names.
    pub cases: Vec<String>,
    /// The full config of each case (TOML, base config with the case's
    /// overrides merged in).
    pub case_configs: Vec<String>,
    /// Records.
    pub records: Vec<StoredRecord>,
    /// The suite's target and scaling, when the records are a suite.
    pub suite: Option<StoredSuite>,
    /// The stripes and the limit states fitted on them, when the sweep is
    /// a multiple-stripe analysis (`/fragility`).
    pub fragility: Option<crate::fragility::StoredFragility>,
    /// The result arrays.
    pub results: Results,
}

fn shape_err(e: ndarray::ShapeError) -> hdf5::Error {
    hdf5::Error::from(e.to_string())
}

/// The four axes of the result arrays: sizes and names.
struct Axes {
    dims: [usize; 4],
    labels: [&'static str; 4],
}

/// The label of the period axis: `period`, or for a bridge given by its
/// modes `period_scale`.
fn period_axis(f: &SweepFile) -> &'static str {
    if f.modal.is_some() {
        "period_scale"
    } else {
        "period"
    }
}

impl Axes {
    /// Writes a (case, record, damping, period) array with its axes.
    fn ds4<T: hdf5::H5Type + Clone>(&self, g: &hdf5::Group, name: &str, data: &[T]) -> hdf5::Result<hdf5::Dataset> {
        let d = self.dims;
        let view = ArrayView4::from_shape((d[0], d[1], d[2], d[3]), data).map_err(shape_err)?;
        let ds = array(g, name, view)?;
        label_axes(&ds, &self.labels)?;
        Ok(ds)
    }

    /// Writes a (case, record, damping, period) array of text with its axes.
    fn text4(&self, g: &hdf5::Group, name: &str, data: &[String]) -> hdf5::Result<hdf5::Dataset> {
        let ds = strings(g, name, data, &self.dims)?;
        label_axes(&ds, &self.labels)?;
        Ok(ds)
    }

    /// Writes a (record, damping, period) array with its axes.
    fn ds3(&self, g: &hdf5::Group, name: &str, data: &[f64]) -> hdf5::Result<hdf5::Dataset> {
        let d = self.dims;
        let view = ArrayView3::from_shape((d[1], d[2], d[3]), data).map_err(shape_err)?;
        let ds = array(g, name, view)?;
        label_axes(&ds, &self.labels[1..])?;
        Ok(ds)
    }
}

/// Writes a sweep file atomically.
pub fn write_sweep(path: &Path, f: &SweepFile) -> Result<(), OutputError> {
    write_atomically(path, |file| {
        write_provenance(file, "sweep", &f.provenance)?;
        file.new_attr::<u32>().create("schema_version")?.write_scalar(&SCHEMA_VERSION)?;
        attr_str(file, "config_sha256", &f.config_sha256)?;
        attr_str(file, "shard", &f.shard)?;
        let r = &f.results;
        file.new_attr::<u64>().create("jobs_total")?.write_scalar(&(r.status.len() as u64))?;
        file.new_attr::<u64>().create("jobs_in_scope")?.write_scalar(&(f.scope.len() as u64))?;
        file.new_attr::<u64>().create("jobs_finished")?.write_scalar(&(r.finished() as u64))?;
        file.new_attr::<u64>().create("jobs_failed")?.write_scalar(&(r.failed() as u64))?;
        file.new_attr::<u64>().create("jobs_flagged")?.write_scalar(&(r.flagged() as u64))?;
        let complete = f.scope.iter().all(|&j| r.status[j as usize] != crate::results::status::NOT_RUN);
        file.new_attr::<u8>().create("complete")?.write_scalar(&u8::from(complete))?;

        let spec = file.create_group("spectrum")?;
        let names: Vec<String> = f.records.iter().map(|r| r.name.clone()).collect();
        let case = strings_1d(&spec, "case", &f.cases)?;
        let record = strings_1d(&spec, "record", &names)?;
        let damping = array(&spec, "damping", &f.damping[..])?;
        attr_str(&damping, "units", "1")?;
        let axis = period_axis(f);
        let period = match &f.modal {
            None => {
                let period = array(&spec, "period", &f.periods[..])?;
                attr_str(&period, "units", "s")?;
                period
            }
            Some(m) => {
                // the swept axis is a factor, not a period
                let scale = array(&spec, "period_scale", &m.period_scales[..])?;
                attr_str(&scale, "units", "1")?;
                attr_str(
                    &scale,
                    "meaning",
                    "the factor on every period of the modes file (bridge.modal.period_scale)",
                )?;
                attr_str(file, "modes_file", &m.modes_file)?;
                attr_str(file, "modes_sha256", &m.modes_sha256)?;
                scale
            }
        };
        for (ds, name) in [(&case, "case"), (&record, "record"), (&damping, "damping"), (&period, axis)] {
            label_axes(ds, &[name])?;
        }
        if f.modal.is_some() {
            let longest = array(&spec, "longest_period", &f.periods[..])?;
            attr_str(&longest, "units", "s")?;
            attr_str(&longest, "meaning", "the bridge's longest kept period at each period scale")?;
            label_axes(&longest, &[axis])?;
        }
        strings_1d(&spec, "case_config", &f.case_configs)?;
        let scope = array(&spec, "scope", &f.scope[..])?;
        attr_str(&scope, "meaning", "flat indices of the jobs this file is responsible for (its shard's, or all)")?;
        let axes = Axes { dims: r.dims, labels: ["case", "record", "damping", axis] };

        let without = spec.create_group("without_joint")?;
        for (k, (name, units)) in quakejoint_model::fields::SPECTRAL.iter().enumerate() {
            let ds = if r.without_per_case {
                axes.ds4(&without, name, &r.without[k])?
            } else {
                axes.ds3(&without, name, &r.without[k])?
            };
            attr_str(&ds, "units", units)?;
        }
        let with = spec.create_group("with_joint")?;
        for (k, name) in FIELDS.iter().enumerate() {
            let ds = axes.ds4(&with, name, &r.values[k])?;
            attr_str(&ds, "units", UNITS[k])?;
        }
        let ds = axes.ds4(&with, "status", &r.status)?;
        attr_str(&ds, "meaning", "0 ok, 1 simulation failed, 2 invalid parameters, 3 time or step limit, -1 not run")?;
        axes.text4(&with, "message", &r.messages)?;
        let ds = axes.ds4(&with, "validity", &r.validity)?;
        attr_str(&ds, "meaning", &quakejoint_model::validity::Flags::legend())?;
        axes.text4(&with, "findings", &r.findings)?;
        let ds = axes.ds4(&spec, "reduction", &r.reduction())?;
        attr_str(&ds, "units", "1")?;
        {
            write_statistics(&spec, &Statistics::of(r), r.dims, axis, r.without_per_case)?;
        }
        if let Some(suite) = &f.suite {
            write_suite(file, suite, axis)?;
        }
        if let Some(fragility) = &f.fragility {
            crate::fragility::write_fragility(file, fragility, r, ["case", "record", "damping", axis])?;
            let rows = crate::fragility::rows(fragility, r, &|_, _, _| String::new());
            let candidates = crate::fragility::design::candidates_of(&f.cases, &f.case_configs);
            let designs = crate::fragility::design::designs(fragility, &rows, &candidates);
            crate::fragility::design::write_design(&file.group("fragility")?, &designs, r.dims)?;
        }
        write_joints(file, r, &axes)?;
        crate::fault::point(crate::fault::Point::Checkpoint, path);

        write_records(file, &f.records)?;
        if !r.histories.is_empty() {
            let hist = file.create_group("histories")?;
            for (&job, h) in &r.histories {
                write_history(&hist, job, r.dims, f, h)?;
            }
        }
        Ok(())
    })
}

/// Every joint of a bridge given by its modes, as a run's `/joints/<k>`
/// (k from 0).
fn write_joints(file: &hdf5::File, r: &Results, axes: &Axes) -> hdf5::Result<()> {
    if !r.joints.is_empty() {
        let joints = file.create_group("joints")?;
        for (k, joint) in r.joints.iter().enumerate() {
            let g = joints.create_group(&k.to_string())?;
            attr_str(&g, "name", &joint.name)?;
            for (values, (name, units)) in joint.values.iter().zip(JOINT_FIELDS.iter()) {
                let ds = axes.ds4(&g, name, values)?;
                attr_str(&ds, "units", units)?;
            }
            let ds = axes.ds4(&g, "validity", &joint.validity)?;
            attr_str(&ds, "meaning", &quakejoint_model::validity::Flags::legend())?;
        }
    }
    Ok(())
}

/// `/records`: each record's acceleration and provenance.
fn write_records(file: &hdf5::File, records: &[StoredRecord]) -> hdf5::Result<()> {
    let recs = file.create_group("records")?;
    for rec in records {
        let g = recs.create_group(&rec.name)?;
        let ds = array(&g, "acceleration", &rec.acceleration[..])?;
        attr_str(&ds, "units", "m/s^2")?;
        attr_str(&g, "source", &rec.source)?;
        attr_str(&g, "sha256", &rec.sha256)?;
        attr_str(&g, "file_units", &rec.file_units)?;
        scalar(&g, "dt", rec.dt, "s")?;
        scalar(&g, "scale", rec.scale, "m/s^2 per file unit")?;
        scalar(&g, "pga", rec.pga, "m/s^2")?;
    }
    Ok(())
}

fn write_history(hist: &hdf5::Group, job: u32, d: [usize; 4], f: &SweepFile, h: &Histories) -> hdf5::Result<()> {
    let j = job as usize;
    let (c, rr, z, t) = (j / (d[1] * d[2] * d[3]), j / (d[2] * d[3]) % d[1], j / d[3] % d[2], j % d[3]);
    let g = hist.create_group(&format!("job_{job}"))?;
    attr_str(&g, "case", &f.cases[c])?;
    attr_str(&g, "record", &f.records[rr].name)?;
    scalar(&g, "damping", f.damping[z], "1")?;
    match &f.modal {
        Some(m) => scalar(&g, "period_scale", m.period_scales[t], "1")?,
        None => scalar(&g, "period", f.periods[t], "s")?,
    }
    g.new_attr::<u64>().create("job")?.write_scalar(&(job as u64))?;
    let flags = quakejoint_model::validity::Flags(f.results.validity[j]);
    g.new_attr::<u32>().create("validity")?.write_scalar(&flags.0)?;
    attr_str(&g, "validity_label", &flags.label())?;
    attr_str(&g, "findings", &f.results.findings[j])?;
    quakejoint_io::run_h5::write_history(&g, h)
}

impl SweepFile {
    /// A job in words: `case / record / damping / period`.
    pub fn describe_job(&self, job: usize) -> String {
        let d = self.results.dims;
        let (c, r, z, t) = (job / (d[1] * d[2] * d[3]), job / (d[2] * d[3]) % d[1], job / d[3] % d[2], job % d[3]);
        match &self.modal {
            Some(m) => format!(
                "job {job} ({} / {} / period scale {})",
                self.cases[c], self.records[r].name, m.period_scales[t]
            ),
            None => format!(
                "job {job} ({} / {} / damping {} / T {} s)",
                self.cases[c], self.records[r].name, self.damping[z], self.periods[t]
            ),
        }
    }
}
