//! HDF5 output. Every file is written under a temporary name beside the
//! target and renamed into place when complete, so the target name never
//! holds a half-written file.

use std::path::{Path, PathBuf};

use hdf5::types::VarLenUnicode;
use quakejoint_model::run::RunResult;
use quakejoint_model::service::ServiceResult;

use crate::error::OutputError;

/// Version of the program, written into every file.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// Writes a file through `write` under a temporary name, then renames it
/// into place (removing the temporary file on failure).
pub fn write_atomically(path: &Path, write: impl FnOnce(&hdf5::File) -> hdf5::Result<()>) -> Result<(), OutputError> {
    let tmp = temporary_name(path);
    let result = (|| {
        let file = hdf5::File::create(&tmp)?;
        write(&file)?;
        file.flush()?;
        file.close()
    })();
    match result {
        Ok(()) => {
            // on disk before it takes the name: a power cut after the
            // rename must not leave a file that cannot be opened
            let synced = std::fs::File::open(&tmp).and_then(|f| f.sync_all());
            synced.and_then(|_| std::fs::rename(&tmp, path)).map_err(|e| {
                let _ = std::fs::remove_file(&tmp);
                OutputError::io(path, e)
            })
        }
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(OutputError::hdf5(path, e))
        }
    }
}

/// `<path>.tmp` beside the target.
pub fn temporary_name(path: &Path) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(".tmp");
    PathBuf::from(name)
}

/// Writes a string attribute.
pub fn attr_str(loc: &hdf5::Location, name: &str, value: &str) -> hdf5::Result<()> {
    let v: VarLenUnicode = value.parse().map_err(|e| hdf5::Error::from(format!("{e}")))?;
    loc.new_attr::<VarLenUnicode>().create(name)?.write_scalar(&v)
}

/// Writes a scalar f64 attribute.
pub fn attr_f64(loc: &hdf5::Location, name: &str, value: f64) -> hdf5::Result<()> {
    loc.new_attr::<f64>().create(name)?.write_scalar(&value)
}

/// Writes a 1-D f64 dataset with a `units` attribute.
pub fn dataset_1d(group: &hdf5::Group, name: &str, data: &[f64], units: &str) -> hdf5::Result<()> {
    let ds = group.new_dataset_builder().with_data(data).create(name)?;
    attr_str(&ds, "units", units)
}

/// Writes a 2-D f64 dataset (row-major `rows x cols`) with a `units` attribute.
pub fn dataset_2d(group: &hdf5::Group, name: &str, rows: &[Vec<f64>], units: &str) -> hdf5::Result<()> {
    let cols = rows.first().map_or(0, Vec::len);
    let flat: Vec<f64> = rows.iter().flat_map(|r| r.iter().copied()).collect();
    let arr =
        ndarray::Array2::from_shape_vec((rows.len(), cols), flat).map_err(|e| hdf5::Error::from(e.to_string()))?;
    let ds = group.new_dataset_builder().with_data(&arr).create(name)?;
    attr_str(&ds, "units", units)
}

/// Root attributes common to every file.
pub fn root_attributes(file: &hdf5::File, kind: &str, config_text: &str) -> hdf5::Result<()> {
    attr_str(file, "quakejoint_version", VERSION)?;
    attr_str(file, "kind", kind)?;
    attr_str(file, "config", config_text)?;
    attr_str(file, "created", &crate::time::utc_now())
}

/// Writes the time histories and scalar results of one earthquake run
/// (`quakejoint simulate --output`), with the exact response of the bridge
/// alone at the same times (`without`, if given); layout in
/// `docs/hdf5-layout.md`.
pub fn write_run(
    path: &Path,
    config_text: &str,
    record: &str,
    result: &RunResult,
    without: Option<&[f64]>,
) -> Result<(), OutputError> {
    write_atomically(path, |file| {
        root_attributes(file, "simulate", config_text)?;
        attr_str(file, "record", record)?;
        let res = file.create_group("result")?;
        for (name, value) in scalar_results(result) {
            attr_f64(&res, name, value)?;
        }
        if let Some(h) = &result.histories {
            let g = file.create_group("history")?;
            dataset_1d(&g, "t", &h.t, "s")?;
            dataset_1d(&g, "ag", &h.ag, "m/s^2")?;
            dataset_1d(&g, "u", &h.u, "m")?;
            dataset_1d(&g, "v", &h.v, "m/s")?;
            dataset_1d(&g, "a_abs", &h.a_abs, "m/s^2")?;
            dataset_1d(&g, "joint_force", &h.joint_force, "N")?;
            dataset_1d(&g, "friction_power", &h.friction_power, "W")?;
            if let Some(w) = without {
                let mut w = w[..w.len().min(h.t.len())].to_vec();
                w.resize(h.t.len(), f64::NAN);
                dataset_1d(&g, "a_abs_without_joint", &w, "m/s^2")?;
            }
            if !h.center_beam_dx.is_empty() {
                dataset_2d(&g, "center_beam_dx", &h.center_beam_dx, "m")?;
            }
        }
        Ok(())
    })
}

/// Scalar results of a run, by name.
pub fn scalar_results(r: &RunResult) -> Vec<(&'static str, f64)> {
    let opt = |x: Option<f64>| x.unwrap_or(f64::NAN);
    vec![
        ("omega", r.omega),
        ("period", 2.0 * std::f64::consts::PI / r.omega),
        ("sa", r.sa),
        ("t_sa", r.t_sa),
        ("psa", r.psa),
        ("sd", r.sd),
        ("t_sd", r.t_sd),
        ("sv", r.sv),
        ("t_sv", r.t_sv),
        ("peak_joint_force", r.peak_joint_force),
        ("peak_bushing_force", r.peak_bushing_force),
        ("peak_friction_force", r.peak_friction_force),
        ("friction_energy", r.friction_energy),
        ("damping_energy", r.damping_energy),
        ("earthquake_work", r.earthquake_work),
        ("min_subgap", opt(r.min_subgap)),
        ("max_subgap", opt(r.max_subgap)),
        ("max_subgap_deviation", opt(r.max_subgap_deviation)),
        ("energy_error", r.energy_error),
        ("max_constraint_residual", r.max_constraint_residual()),
        ("steps", r.stats.steps as f64),
        ("rejected_steps", r.stats.rejected as f64),
        ("wall_time_s", r.wall_time_s),
    ]
}

/// Writes the hysteresis loop of a service run (`quakejoint service --output`).
pub fn write_service(path: &Path, config_text: &str, result: &ServiceResult) -> Result<(), OutputError> {
    write_atomically(path, |file| {
        root_attributes(file, "service", config_text)?;
        let g = file.create_group("service")?;
        dataset_1d(&g, "t", &result.t, "s")?;
        dataset_1d(&g, "u", &result.u, "m")?;
        dataset_1d(&g, "joint_force", &result.joint_force, "N")?;
        attr_f64(&g, "period", result.period)?;
        attr_f64(&g, "friction_work_per_cycle", result.friction_work_per_cycle)?;
        attr_f64(&g, "loop_work_per_cycle", result.loop_work_per_cycle)?;
        attr_f64(&g, "hand_calculation", result.hand_calculation)?;
        attr_f64(&g, "peak_joint_force", result.peak_joint_force)?;
        Ok(())
    })
}

/// Writes the sparsity pattern of a model's iteration matrix
/// (`quakejoint model --sparsity`): `/sparsity/row`, `/sparsity/col` in
/// natural numbering (coordinates, then constraint equations).
pub fn write_sparsity(
    path: &Path,
    config_text: &str,
    asm: &quakejoint_solver::Assembly,
    body_names: &[String],
) -> Result<(), OutputError> {
    let pattern = asm.jacobian_pattern();
    let rows: Vec<u32> = pattern.iter().map(|p| p.0).collect();
    let cols: Vec<u32> = pattern.iter().map(|p| p.1).collect();
    write_atomically(path, |file| {
        root_attributes(file, "sparsity", config_text)?;
        let g = file.create_group("sparsity")?;
        g.new_dataset_builder().with_data(&rows[..]).create("row")?;
        g.new_dataset_builder().with_data(&cols[..]).create("col")?;
        g.new_dataset_builder().with_data(&asm.coordinate_bodies()[..]).create("coordinate_body")?;
        let names: Vec<VarLenUnicode> = body_names
            .iter()
            .map(|n| n.parse())
            .collect::<Result<_, _>>()
            .map_err(|e| hdf5::Error::from(format!("{e}")))?;
        g.new_dataset_builder().with_data(&names[..]).create("body_name")?;
        g.new_attr::<u64>().create("coordinates")?.write_scalar(&(asm.coordinates() as u64))?;
        g.new_attr::<u64>().create("equations")?.write_scalar(&(asm.equations() as u64))?;
        g.new_attr::<u64>().create("nnz")?.write_scalar(&(pattern.len() as u64))?;
        Ok(())
    })
}
