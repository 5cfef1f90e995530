//! HDF5 output helpers. Every file is written under a temporary name beside
//! the target and renamed into place when complete, so the target name
//! never holds a half-written file. Every numeric value carries its unit:
//! numbers are datasets (scalar or arrays) with a `units` attribute (`1`
//! for ratios and counts); attributes hold text and integer counts only.

use std::path::{Path, PathBuf};

use hdf5::types::VarLenUnicode;

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

/// Reads a string attribute.
pub fn read_attr_str(loc: &hdf5::Location, name: &str) -> hdf5::Result<String> {
    Ok(loc.attr(name)?.read_scalar::<VarLenUnicode>()?.as_str().to_string())
}

/// Writes a string attribute.
pub fn attr_str(loc: &hdf5::Location, name: &str, value: &str) -> hdf5::Result<()> {
    let v: VarLenUnicode = value.parse().map_err(|e| hdf5::Error::from(format!("{e}")))?;
    loc.new_attr::<VarLenUnicode>().create(name)?.write_scalar(&v)
}

/// Writes a scalar f64 dataset with a `units` attribute.
pub fn scalar(group: &hdf5::Group, name: &str, value: f64, units: &str) -> hdf5::Result<()> {
    let ds = group.new_dataset::<f64>().create(name)?;
    ds.write_scalar(&value)?;
    attr_str(&ds, "units", units)
}

/// Writes a 1-D string dataset (variable-length UTF-8; h5py reads it as
/// bytes unless asked `.asstr()`).
pub fn strings_1d(group: &hdf5::Group, name: &str, data: &[String]) -> hdf5::Result<hdf5::Dataset> {
    let v: Vec<VarLenUnicode> = data.iter().map(|s| vlu(s)).collect::<hdf5::Result<_>>()?;
    group.new_dataset_builder().with_data(&v[..]).create(name)
}

/// A string as an HDF5 variable-length UTF-8 value.
pub fn vlu(s: &str) -> hdf5::Result<VarLenUnicode> {
    s.parse().map_err(|e| hdf5::Error::from(format!("{e}")))
}

// HDF5 dimension scales (the high-level library, which Debian's
// libhdf5-dev ships beside the main one).
#[link(name = "hdf5_hl")]
extern "C" {
    fn H5DSset_scale(dsid: i64, dimname: *const std::ffi::c_char) -> i32;
    fn H5DSattach_scale(did: i64, dsid: i64, idx: std::ffi::c_uint) -> i32;
    fn H5DSset_label(did: i64, idx: std::ffi::c_uint, label: *const std::ffi::c_char) -> i32;
}

/// Makes `scale` a dimension scale named `name` (readers such as h5py and
/// xarray then know what each axis of the datasets it is attached to means).
pub fn set_scale(scale: &hdf5::Dataset, name: &str) -> hdf5::Result<()> {
    let c = std::ffi::CString::new(name).map_err(|e| hdf5::Error::from(e.to_string()))?;
    let id = scale.id();
    // SAFETY: `id` is a valid, open dataset identifier for the duration of
    // the call, `c` a NUL-terminated string; the library's lock serialises
    // HDF5 calls.
    let rc = hdf5::sync::sync(|| unsafe { H5DSset_scale(id, c.as_ptr()) });
    if rc < 0 {
        return Err(hdf5::Error::from(format!("H5DSset_scale({name}) failed")));
    }
    Ok(())
}

/// Labels the axes of `data` and attaches one dimension scale per axis
/// (`scales[i]` for axis `i`, each made a scale by [`set_scale`]).
pub fn attach_scales(data: &hdf5::Dataset, scales: &[(&hdf5::Dataset, &str)]) -> hdf5::Result<()> {
    for (i, (scale, label)) in scales.iter().enumerate() {
        let c = std::ffi::CString::new(*label).map_err(|e| hdf5::Error::from(e.to_string()))?;
        let (did, sid) = (data.id(), scale.id());
        // SAFETY: both identifiers are valid, open datasets; `i` is an axis
        // of `data` (the caller passes one scale per axis).
        let rc = hdf5::sync::sync(|| unsafe {
            let a = H5DSattach_scale(did, sid, i as std::ffi::c_uint);
            if a < 0 {
                a
            } else {
                H5DSset_label(did, i as std::ffi::c_uint, c.as_ptr())
            }
        });
        if rc < 0 {
            return Err(hdf5::Error::from(format!("attaching the scale {label} failed")));
        }
    }
    Ok(())
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
