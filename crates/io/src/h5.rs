//! HDF5 output helpers. Every file is written under a temporary name beside
//! the target and renamed into place when complete, so the target name
//! never holds a half-written file. Every numeric value carries its unit:
//! numbers are datasets (scalar or arrays) with a `units` attribute (`1`
//! for ratios and counts); attributes hold text and integer counts only.
//!
//! Every dataset is under a checksum (`docs/hdf5-layout.md`, "Checksums"):
//! - every array dataset is chunked with HDF5's Fletcher32 checksum filter,
//!   which libhdf5 (the command, h5py, h5dump) verifies on every read;
//! - text datasets are arrays of fixed-length UTF-8 strings, so their bytes
//!   are inside the checksummed chunks (variable-length strings live in the
//!   global heap, which has no checksum);
//! - scalar datasets (which cannot be chunked) are stored compact, inside
//!   their object header, and files are written in the HDF5 1.10 format,
//!   whose object headers and indexes carry checksums too;
//! - attribute text is fixed-length ([`attr_str`]), so it is stored in the
//!   attribute's message, under the object header's checksum (or the dense
//!   attribute storage's), not in the global heap, which has none.
//!
//! The readers here ([`read_strings`], [`read_attr_str`]) read these and
//! the variable-length strings of files written before.

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
        let file = create(&tmp)?;
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

/// Creates `path` in the HDF5 1.10 file format, whose object headers,
/// superblock and chunk indexes carry checksums; libhdf5 1.10 and every
/// later version (h5py's) read it.
fn create(path: &Path) -> hdf5::Result<hdf5::File> {
    use hdf5::file::LibraryVersion;
    hdf5::File::with_options().with_fapl(|p| p.libver_bounds(LibraryVersion::V110, LibraryVersion::V110)).create(path)
}

/// `<path>.tmp` beside the target.
pub fn temporary_name(path: &Path) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(".tmp");
    PathBuf::from(name)
}

/// Reads a string attribute: fixed-length text as [`attr_str`] writes it,
/// or the variable-length text of files written before; text that is not
/// UTF-8 (a damaged attribute) is an error naming it.
pub fn read_attr_str(loc: &hdf5::Location, name: &str) -> hdf5::Result<String> {
    use hdf5::types::TypeDescriptor as TD;
    use hdf5_sys::h5a::H5Aread;
    let attr = loc.attr(name)?;
    let what = format!("attribute {name}");
    let dtype = attr.dtype()?;
    match dtype.to_descriptor()? {
        TD::VarLenUnicode => utf8(attr.read_scalar::<VarLenUnicode>()?.as_bytes(), &what),
        TD::VarLenAscii => utf8(attr.read_scalar::<hdf5::types::VarLenAscii>()?.as_bytes(), &what),
        TD::FixedUnicode(width) | TD::FixedAscii(width) => {
            if attr.space()?.size() != 1 || width > MAX_READ_BYTES {
                return Err(hdf5::Error::from(format!("{what}: not one text of at most 2 GiB")));
            }
            let mut bytes = vec![0u8; width];
            let (attr_id, type_id) = (attr.id(), dtype.id());
            // SAFETY: `bytes` holds one element of the attribute's own
            // type (width bytes), and the attribute holds one element.
            hdf5::sync::sync(|| hdf5::h5check(unsafe { H5Aread(attr_id, type_id, bytes.as_mut_ptr().cast()) }))?;
            utf8(trim_nul(&bytes), &what)
        }
        other => Err(hdf5::Error::from(format!("{what}: {other:?} where text was expected"))),
    }
}

/// Writes a string attribute as fixed-length UTF-8 text (as long as the
/// text, at least one byte, padded with a NUL): the text is then stored in
/// the attribute's message, inside the object header (or the dense
/// attribute storage), both under HDF5's metadata checksums, where
/// variable-length text would live in the global heap, which has none.
/// h5py reads it as bytes (`.decode()` gives `str`).
pub fn attr_str(loc: &hdf5::Location, name: &str, value: &str) -> hdf5::Result<()> {
    use hdf5_sys::h5a::H5Awrite;
    let width = value.len().max(1);
    let dtype = hdf5::Datatype::from_descriptor(&hdf5::types::TypeDescriptor::FixedUnicode(width))?;
    let attr = loc.new_attr_builder().empty_as(&dtype).create(name)?;
    let mut bytes = value.as_bytes().to_vec();
    bytes.resize(width, 0);
    let (attr_id, type_id) = (attr.id(), dtype.id());
    // SAFETY: both identifiers are open; `bytes` holds exactly one element
    // of `dtype` (width bytes), the attribute's one element.
    hdf5::sync::sync(|| hdf5::h5check(unsafe { H5Awrite(attr_id, type_id, bytes.as_ptr().cast()) }))?;
    Ok(())
}

/// `bytes` without the NULs that pad fixed-length text.
fn trim_nul(bytes: &[u8]) -> &[u8] {
    &bytes[..bytes.iter().rposition(|&c| c != 0).map_or(0, |i| i + 1)]
}

/// Largest chunk [bytes]: the arrays of a sweep are mostly one chunk.
const CHUNK_BYTES: usize = 1 << 20;

/// The chunk shape of an array of `shape` with elements of `size` bytes:
/// the whole array up to [`CHUNK_BYTES`], else halved along the leading
/// axes first (every axis at least 1).
fn chunk_shape(shape: &[usize], size: usize) -> Vec<usize> {
    let mut chunk: Vec<usize> = shape.iter().map(|&n| n.max(1)).collect();
    let bytes = |c: &[usize]| c.iter().product::<usize>().saturating_mul(size);
    for axis in 0..chunk.len() {
        while bytes(&chunk) > CHUNK_BYTES && chunk[axis] > 1 {
            chunk[axis] = chunk[axis].div_ceil(2);
        }
    }
    chunk
}

/// Writes an array dataset (any number of axes, at least one), chunked with
/// the Fletcher32 checksum; an empty array gets resizable extents, since a
/// chunk cannot be larger than a fixed axis of length 0.
pub fn array<'d, T: hdf5::H5Type + Clone, D: ndarray::Dimension>(
    group: &hdf5::Group,
    name: &str,
    data: impl Into<ndarray::ArrayView<'d, T, D>>,
) -> hdf5::Result<hdf5::Dataset> {
    let view = data.into();
    let shape = view.shape().to_vec();
    if shape.is_empty() {
        return Err(hdf5::Error::from(format!("{name}: a scalar is written by `scalar`, not as an array")));
    }
    let chunk = chunk_shape(&shape, std::mem::size_of::<T>());
    if shape.contains(&0) {
        let extents = hdf5::SimpleExtents::resizable(shape);
        return group.new_dataset::<T>().shape(extents).chunk(chunk).fletcher32().create(name);
    }
    let standard = view.as_standard_layout();
    group.new_dataset_builder().with_data(&standard).chunk(chunk).fletcher32().create(name)
}

/// Writes an array dataset of text of the given `shape` (row-major `data`)
/// as fixed-length UTF-8 strings (as long as the longest, padded with
/// NULs), chunked, deflated and with the Fletcher32 checksum: the text
/// itself is under the checksum. h5py reads them as bytes (`.asstr()` gives `str`).
pub fn strings(group: &hdf5::Group, name: &str, data: &[String], shape: &[usize]) -> hdf5::Result<hdf5::Dataset> {
    use hdf5_sys::{h5d::H5Dwrite, h5p::H5P_DEFAULT, h5s::H5S_ALL};
    if shape.is_empty() || shape.iter().product::<usize>() != data.len() {
        return Err(hdf5::Error::from(format!("{name}: {} strings do not fill the shape {shape:?}", data.len())));
    }
    let width = data.iter().map(String::len).max().unwrap_or(0).max(1);
    let dtype = hdf5::Datatype::from_descriptor(&hdf5::types::TypeDescriptor::FixedUnicode(width))?;
    let chunk = chunk_shape(shape, width);
    let extents = if data.is_empty() {
        hdf5::SimpleExtents::resizable(shape.to_vec())
    } else {
        hdf5::SimpleExtents::new(shape.to_vec())
    };
    // padded to the longest, text compresses well: deflated (where the
    // library has zlib, as Debian's and h5py's do), then checksummed
    let builder = group.new_dataset_builder().empty_as(&dtype).shape(extents).chunk(chunk);
    let builder = if hdf5::filters::deflate_available() { builder.deflate(4) } else { builder };
    let ds = builder.fletcher32().create(name)?;
    if data.is_empty() {
        return Ok(ds);
    }
    let mut bytes = vec![0u8; data.len() * width];
    for (slot, s) in bytes.chunks_exact_mut(width).zip(data) {
        slot[..s.len()].copy_from_slice(s.as_bytes());
    }
    let (ds_id, type_id) = (ds.id(), dtype.id());
    // SAFETY: both identifiers are open; `bytes` holds exactly one element
    // of `dtype` (width bytes) for every element of the dataset's extent.
    hdf5::sync::sync(|| {
        hdf5::h5check(unsafe { H5Dwrite(ds_id, type_id, H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes.as_ptr().cast()) })
    })?;
    Ok(ds)
}

/// Most bytes a dataset of an output may hold when it is read back (2 GiB;
/// the largest sweep arrays are tens of megabytes): a damaged or foreign
/// file's extent is refused instead of allocated.
pub const MAX_READ_BYTES: usize = 1 << 31;

/// Refuses a dataset larger than [`MAX_READ_BYTES`] before it is read.
pub fn check_extent(ds: &hdf5::Dataset) -> hdf5::Result<()> {
    let n = ds.space()?.size();
    let element = ds.dtype()?.size();
    match n.checked_mul(element) {
        Some(len) if len <= MAX_READ_BYTES => Ok(()),
        _ => Err(hdf5::Error::from(format!("{}: {n} elements: not a dataset this program wrote", ds.name()))),
    }
}

/// Reads a text dataset: fixed-length strings as [`strings`] writes them,
/// or the variable-length strings of older files; text that is not UTF-8
/// (a damaged file) is an error naming the dataset.
pub fn read_strings(ds: &hdf5::Dataset) -> hdf5::Result<Vec<String>> {
    use hdf5::types::TypeDescriptor as TD;
    use hdf5_sys::{h5d::H5Dread, h5p::H5P_DEFAULT, h5s::H5S_ALL};
    let name = ds.name();
    let dtype = ds.dtype()?;
    match dtype.to_descriptor()? {
        TD::VarLenUnicode => ds.read_raw::<VarLenUnicode>()?.iter().map(|s| utf8(s.as_bytes(), &name)).collect(),
        TD::FixedUnicode(width) | TD::FixedAscii(width) => {
            // the extent as the dataspace says it (0 for a null one), and a
            // buffer of exactly extent x width bytes, refused when that
            // overflows or exceeds what an output holds
            let n = ds.space()?.size();
            let len = n.checked_mul(width).filter(|&len| len <= MAX_READ_BYTES).ok_or_else(|| {
                hdf5::Error::from(format!("{name}: {n} strings of {width} bytes: not a dataset this program wrote"))
            })?;
            if len == 0 {
                return Ok(vec![String::new(); n]);
            }
            let mut bytes = vec![0u8; len];
            let (ds_id, type_id) = (ds.id(), dtype.id());
            // SAFETY: `bytes` holds one element of the dataset's own type
            // (width bytes) for each of the n elements of its extent, and
            // the whole extent is read (H5S_ALL).
            hdf5::sync::sync(|| {
                hdf5::h5check(unsafe {
                    H5Dread(ds_id, type_id, H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes.as_mut_ptr().cast())
                })
            })?;
            bytes.chunks_exact(width).map(|b| utf8(trim_nul(b), &name)).collect()
        }
        other => Err(hdf5::Error::from(format!("{name}: {other:?} where text was expected"))),
    }
}

/// `bytes` as a string, or an error naming `what`.
fn utf8(bytes: &[u8], what: &str) -> hdf5::Result<String> {
    String::from_utf8(bytes.to_vec()).map_err(|_| hdf5::Error::from(format!("{what}: the text is not UTF-8 (damaged)")))
}

/// Writes a scalar f64 dataset with a `units` attribute, stored compact
/// (inside its checksummed object header: a scalar cannot be chunked).
pub fn scalar(group: &hdf5::Group, name: &str, value: f64, units: &str) -> hdf5::Result<()> {
    let ds = group.new_dataset::<f64>().layout(hdf5::dataset::Layout::Compact).create(name)?;
    ds.write_scalar(&value)?;
    attr_str(&ds, "units", units)
}

/// Writes a 1-D string dataset (see [`strings`]).
pub fn strings_1d(group: &hdf5::Group, name: &str, data: &[String]) -> hdf5::Result<hdf5::Dataset> {
    strings(group, name, data, &[data.len()])
}

/// The attributes HDF5's dimension scales (`H5DS`) kept on the arrays of
/// files written before schema 12: `CLASS`, `NAME`, `REFERENCE_LIST`,
/// `DIMENSION_LIST` (references) and `DIMENSION_LABELS`. The last two
/// live in the global heap, which has no checksum, and libhdf5 1.10 reads
/// a damaged record of it past its end (a segmentation fault): readers
/// leave them alone, and files are written without dimension scales
/// ([`label_axes`] instead).
pub const SCALE_ATTRIBUTES: [&str; 5] = ["CLASS", "NAME", "REFERENCE_LIST", "DIMENSION_LIST", "DIMENSION_LABELS"];

/// Names the axes of `data` in its text attribute `dims`, comma-separated
/// (`case, record, damping, period`): each name is that of the array that
/// holds the axis' coordinates (`/spectrum/period`, `/fragility/levels` for
/// `stripe`). Text under the object header's checksum, unlike HDF5's
/// dimension scales (their references and labels live in the global heap).
pub fn label_axes(data: &hdf5::Dataset, labels: &[&str]) -> hdf5::Result<()> {
    attr_str(data, "dims", &labels.join(", "))
}

/// Writes a 1-D f64 dataset with a `units` attribute.
pub fn dataset_1d(group: &hdf5::Group, name: &str, data: &[f64], units: &str) -> hdf5::Result<()> {
    let ds = array(group, name, data)?;
    attr_str(&ds, "units", units)
}

/// Writes a 2-D f64 dataset (row-major `rows x cols`) with a `units` attribute.
pub fn dataset_2d(group: &hdf5::Group, name: &str, rows: &[Vec<f64>], units: &str) -> hdf5::Result<()> {
    let cols = rows.first().map_or(0, Vec::len);
    let flat: Vec<f64> = rows.iter().flat_map(|r| r.iter().copied()).collect();
    let arr =
        ndarray::Array2::from_shape_vec((rows.len(), cols), flat).map_err(|e| hdf5::Error::from(e.to_string()))?;
    let ds = array(group, name, &arr)?;
    attr_str(&ds, "units", units)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_are_the_whole_array_up_to_a_megabyte() {
        assert_eq!(chunk_shape(&[8000], 8), vec![8000]);
        assert_eq!(chunk_shape(&[0, 3], 8), vec![1, 3]);
        assert_eq!(chunk_shape(&[1 << 20], 8), vec![1 << 17]);
        let c = chunk_shape(&[4, 7, 2, 50_000], 8);
        assert!(c.iter().product::<usize>() * 8 <= CHUNK_BYTES && c[3] == 50_000, "{c:?}");
    }
}
