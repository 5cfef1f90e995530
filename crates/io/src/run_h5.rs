//! The HDF5 files of single runs (`quakejoint simulate`, `service`,
//! `model --sparsity`; layout in `docs/hdf5-layout.md`), and the provenance
//! every output file carries: the command, the config as read and as used
//! after command-line overrides, and each record file with its hash.

use std::path::Path;

use quakejoint_model::run::{Histories, RunResult};
use quakejoint_model::service::ServiceResult;
use quakejoint_motion::Record;

use crate::error::OutputError;
use crate::h5::{array, attr_str, dataset_1d, dataset_2d, scalar, strings_1d, write_atomically, VERSION};

/// A record as used by a run: enough to find the very file again and to
/// know how its numbers were read.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordSource {
    /// Its role: `x` or `y` in a run, the record's name in a sweep.
    pub role: String,
    /// The record's name.
    pub name: String,
    /// The file as the config names it.
    pub file: String,
    /// SHA-256 of the file's bytes.
    pub sha256: String,
    /// Units of the numbers in the file (`g`, `m/s2`, `cm/s2`).
    pub units: String,
    /// Total factor from the file's numbers to m/s^2 [m/s^2 per file unit].
    pub scale: f64,
    /// Time step \[s\].
    pub dt: f64,
    /// Samples.
    pub samples: usize,
    /// The channel of the file read (`channel 2 of 3 (360°)`), empty for
    /// formats that do not say.
    pub channel: String,
}

impl RecordSource {
    /// The source of a loaded record.
    pub fn of(role: &str, record: &Record, sha256: &str) -> Self {
        Self {
            role: role.to_string(),
            name: record.name.clone(),
            file: record.source.clone(),
            sha256: sha256.to_string(),
            units: record.units.name().to_string(),
            scale: record.scale,
            dt: record.dt,
            samples: record.acceleration.len(),
            channel: record.channel.as_ref().map(|c| c.describe()).unwrap_or_default(),
        }
    }
}

/// What produced an output file.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Provenance {
    /// The command line.
    pub command: String,
    /// The config file's path.
    pub config_path: String,
    /// The config file's text as read.
    pub config_file: String,
    /// The config as used: after command-line overrides (a record, a
    /// period, service options), in TOML.
    pub config: String,
    /// The records read.
    pub records: Vec<RecordSource>,
    /// The warnings printed while reading the inputs and running (root
    /// attribute `warnings`, one per line; empty if none).
    pub warnings: Vec<String>,
}

/// Root attributes and `/inputs` of every file.
pub fn write_provenance(file: &hdf5::File, kind: &str, p: &Provenance) -> hdf5::Result<()> {
    attr_str(file, "quakejoint_version", VERSION)?;
    attr_str(file, "kind", kind)?;
    attr_str(file, "created", &crate::time::utc_now())?;
    attr_str(file, "command", &p.command)?;
    attr_str(file, "config_path", &p.config_path)?;
    attr_str(file, "config_file", &p.config_file)?;
    attr_str(file, "config", &p.config)?;
    attr_str(file, "warnings", &p.warnings.join("\n"))?;
    if p.records.is_empty() {
        return Ok(());
    }
    let inputs = file.create_group("inputs")?.create_group("records")?;
    for r in &p.records {
        let g = inputs.create_group(&r.role)?;
        attr_str(&g, "name", &r.name)?;
        attr_str(&g, "file", &r.file)?;
        attr_str(&g, "sha256", &r.sha256)?;
        attr_str(&g, "file_units", &r.units)?;
        attr_str(&g, "channel", &r.channel)?;
        g.new_attr::<u64>().create("samples")?.write_scalar(&(r.samples as u64))?;
        scalar(&g, "dt", r.dt, "s")?;
        scalar(&g, "scale", r.scale, "m/s^2 per file unit")?;
    }
    Ok(())
}

/// Writes the validity of a run as root attributes.
fn write_validity(file: &hdf5::File, v: &quakejoint_model::validity::Validity) -> hdf5::Result<()> {
    file.new_attr::<u32>().create("validity")?.write_scalar(&v.flags.0)?;
    attr_str(file, "validity_label", &v.flags.label())?;
    attr_str(file, "validity_meaning", &quakejoint_model::validity::Flags::legend())?;
    attr_str(file, "findings", &v.message())
}

/// Writes the time histories and scalar results of one earthquake run
/// (`quakejoint simulate --output`).
pub fn write_run(path: &Path, provenance: &Provenance, result: &RunResult) -> Result<(), OutputError> {
    write_atomically(path, |file| {
        write_provenance(file, "simulate", provenance)?;
        attr_str(file, "method", if result.exact_linear { "exact linear, without the joint" } else { "multibody" })?;
        write_validity(file, &result.validity)?;
        if let Some(p) = result.pounding.peak_contact_place {
            let released = result.joints.first().and_then(|j| j.fuse).and_then(|f| f.released());
            attr_str(file, "peak_contact_place", &p.describe_after(released, result.pounding.peak_contact_time))?;
        }
        let res = file.create_group("result")?;
        for (name, value, units) in result.scalars() {
            scalar(&res, name, value, units)?;
        }
        write_points(file, result)?;
        write_joints(file, result)?;
        if let Some(h) = &result.histories {
            write_history(&file.create_group("history")?, h)?;
            if !h.contact_force.is_empty() {
                let imp = file.create_group("impacts")?;
                let col =
                    |f: fn(&quakejoint_model::pounding::Impact) -> f64| h.impacts.iter().map(f).collect::<Vec<_>>();
                dataset_1d(&imp, "time", &col(|i| i.time), "s")?;
                dataset_1d(&imp, "gap", &col(|i| i.place.gap as f64), "1")?;
                dataset_1d(&imp, "end", &col(|i| i.place.end as f64), "1")?;
                dataset_1d(&imp, "speed", &col(|i| i.speed), "m/s")?;
            }
        }
        Ok(())
    })
}

/// A modal bridge's points (`/points`): their names and peaks with the
/// joints and without, and the base shear.
fn write_points(file: &hdf5::File, r: &RunResult) -> hdf5::Result<()> {
    if r.points.is_empty() {
        return Ok(());
    }
    let g = file.create_group("points")?;
    let names: Vec<String> = r.points.iter().map(|p| p.name.clone()).collect();
    strings_1d(&g, "name", &names)?;
    // (a column per peak, in PointPeaks::scalars' order)
    for (k, (name, _, units)) in quakejoint_model::modal::PointPeaks::default().scalars().into_iter().enumerate() {
        let column: Vec<f64> = r.points.iter().map(|p| p.scalars()[k].1).collect();
        dataset_1d(&g, name, &column, units)?;
    }
    scalar(&g, "base_shear", r.base_shear.unwrap_or(f64::NAN), "N")?;
    if let Some((check, warnings)) = &r.mode_check {
        dataset_1d(&g, "flexibility_captured", &check.flexibility, "1")?;
        scalar(&g, "mass_ratio", check.mass_ratio.unwrap_or(f64::NAN), "1")?;
        attr_str(&g, "warnings", &warnings.join("\n"))?;
    }
    scalar(&g, "base_shear_without_joint", r.base_shear_without.unwrap_or(f64::NAN), "N")?;
    Ok(())
}

/// Every joint of the run (`/joints/<k>`, k from 0 in the order of
/// `[[joints]]`): name, peaks, validity and histories (the first joint's
/// are the run's `/history`).
fn write_joints(file: &hdf5::File, r: &RunResult) -> hdf5::Result<()> {
    if r.joints.is_empty() {
        return Ok(());
    }
    let all = file.create_group("joints")?;
    for (k, j) in r.joints.iter().enumerate() {
        let g = all.create_group(&k.to_string())?;
        attr_str(&g, "name", &j.name)?;
        for (name, value, units) in j.scalars() {
            scalar(&g, name, value, units)?;
        }
        scalar(&g, "validity", f64::from(j.validity.flags.0), "1")?;
        attr_str(&g, "validity_label", &j.validity.flags.label())?;
        attr_str(&g, "validity_findings", &j.validity.message())?;
        if let Some(h) = &j.histories {
            write_history(&g.create_group("history")?, h)?;
        }
    }
    Ok(())
}

/// Writes the series of `h` into `g`, each with its units: those a run did
/// not compute (empty) are left out. A run's `/history` and a sweep's
/// `/histories/job_<j>` are written by it.
pub fn write_history(g: &hdf5::Group, h: &Histories) -> hdf5::Result<()> {
    for s in quakejoint_model::history::SERIES {
        let data = (s.of)(h);
        if !data.is_empty() {
            dataset_1d(g, s.name, data, s.units)?;
        }
    }
    for table in quakejoint_model::history::TABLES {
        let rows = (table.of)(h);
        if !rows.is_empty() {
            dataset_2d(g, table.name, rows, table.units)?;
        }
    }
    Ok(())
}

/// Reads what [`write_history`] wrote (a series that is absent is empty).
pub fn read_history(g: &hdf5::Group) -> hdf5::Result<Histories> {
    use crate::read::{rows, values};
    let series = |name: &str| -> hdf5::Result<Vec<f64>> {
        if g.link_exists(name) {
            values(g, name)
        } else {
            Ok(Vec::new())
        }
    };
    let mut h = Histories::default();
    for s in quakejoint_model::history::SERIES {
        *(s.of_mut)(&mut h) = series(s.name)?;
    }
    for table in quakejoint_model::history::TABLES {
        *(table.of_mut)(&mut h) = rows(g, table.name)?;
    }
    Ok(h)
}

/// Writes the hysteresis loop of a service run (`quakejoint service --output`).
pub fn write_service(path: &Path, provenance: &Provenance, result: &ServiceResult) -> Result<(), OutputError> {
    write_atomically(path, |file| {
        write_provenance(file, "service", provenance)?;
        write_validity(file, &result.validity)?;
        let g = file.create_group("service")?;
        dataset_1d(&g, "t", &result.t, "s")?;
        dataset_1d(&g, "u", &result.u, "m")?;
        dataset_1d(&g, "joint_force", &result.joint_force, "N")?;
        let [dx, dy, dphi] = &result.center_beams;
        if !dx.is_empty() {
            dataset_2d(&g, "center_beam_dx", dx, "m")?;
            dataset_2d(&g, "center_beam_dy", dy, "m")?;
            dataset_2d(&g, "center_beam_dphi", dphi, "rad")?;
        }
        g.new_attr::<u32>().create("cycles")?.write_scalar(&result.cycles)?;
        attr_str(&g, "warnings", &result.warnings.join("; "))?;
        scalar(&g, "period", result.period, "s")?;
        scalar(&g, "friction_work_per_cycle", result.friction_work_per_cycle, "J")?;
        scalar(&g, "loop_work_per_cycle", result.loop_work_per_cycle, "J")?;
        scalar(&g, "hand_calculation", result.hand_calculation, "J")?;
        scalar(&g, "compliance_deficit", result.compliance_deficit.unwrap_or(f64::NAN), "J")?;
        scalar(&g, "damping_work_per_cycle", result.damping_work_per_cycle, "J")?;
        scalar(&g, "contact_work_per_cycle", result.contact_work_per_cycle, "J")?;
        scalar(&g, "min_subgap", result.min_subgap, "m")?;
        scalar(&g, "max_subgap", result.max_subgap, "m")?;
        scalar(&g, "peak_joint_force", result.peak_joint_force, "N")?;
        scalar(&g, "energy_error", result.energy_error, "1")?;
        let r = &result.residuals;
        scalar(&g, "max_position_residual", r.position, "m")?;
        scalar(&g, "max_angle_residual", r.angle, "rad")?;
        scalar(&g, "max_velocity_residual", r.velocity, "m/s")?;
        scalar(&g, "max_angular_velocity_residual", r.angular_velocity, "rad/s")?;
        Ok(())
    })
}

/// Writes the sparsity pattern of a model's iteration matrix
/// (`quakejoint model --sparsity`): `/sparsity/row`, `/sparsity/col` in
/// natural numbering (coordinates, then constraint equations).
pub fn write_sparsity(
    path: &Path,
    provenance: &Provenance,
    asm: &quakejoint_solver::Assembly,
    body_names: &[String],
) -> Result<(), OutputError> {
    let pattern = asm.jacobian_pattern();
    let rows: Vec<u32> = pattern.iter().map(|p| p.0).collect();
    let cols: Vec<u32> = pattern.iter().map(|p| p.1).collect();
    write_atomically(path, |file| {
        write_provenance(file, "sparsity", provenance)?;
        let g = file.create_group("sparsity")?;
        array(&g, "row", &rows[..])?;
        array(&g, "col", &cols[..])?;
        array(&g, "coordinate_body", &asm.coordinate_bodies()[..])?;
        crate::h5::strings_1d(&g, "body_name", body_names)?;
        g.new_attr::<u64>().create("coordinates")?.write_scalar(&(asm.coordinates() as u64))?;
        g.new_attr::<u64>().create("equations")?.write_scalar(&(asm.equations() as u64))?;
        g.new_attr::<u64>().create("nnz")?.write_scalar(&(pattern.len() as u64))?;
        Ok(())
    })
}
