//! Reading an output file back, each object named in the errors: a failed
//! checksum says the file is damaged and which dataset (`/spectrum/reduction
//! is damaged: its checksum fails`), and an array larger than any output
//! holds is refused before it is allocated.

use hdf5::{Dataset, Group, H5Type};

use crate::h5::{read_attr_str, read_strings};

/// An error about one object of the file, in words: a failed checksum
/// says the file is damaged.
pub fn about(what: &str, e: hdf5::Error) -> hdf5::Error {
    let text = e.to_string();
    if text.contains("checksum") || text.contains("filter returned failure") {
        hdf5::Error::from(format!("{what} is damaged: its checksum fails"))
    } else if text.starts_with(what) {
        e
    } else {
        hdf5::Error::from(format!("{what}: {text}"))
    }
}

/// `group/name`, as HDF5 names it.
pub fn path_of(g: &Group, name: &str) -> String {
    format!("{}/{name}", g.name().trim_end_matches('/'))
}

/// The dataset `name` of `g`.
pub fn dataset(g: &Group, name: &str) -> hdf5::Result<Dataset> {
    g.dataset(name).map_err(|e| about(&path_of(g, name), e))
}

/// The group `name` of `g`.
pub fn group(g: &Group, name: &str) -> hdf5::Result<Group> {
    g.group(name).map_err(|e| about(&path_of(g, name), e))
}

/// The values of a dataset, in row-major order.
pub fn values<T: H5Type>(g: &Group, name: &str) -> hdf5::Result<Vec<T>> {
    let ds = dataset(g, name)?;
    crate::h5::check_extent(&ds).and_then(|_| ds.read_raw()).map_err(|e| about(&path_of(g, name), e))
}

/// A scalar dataset.
pub fn number(g: &Group, name: &str) -> hdf5::Result<f64> {
    dataset(g, name)?.read_scalar().map_err(|e| about(&path_of(g, name), e))
}

/// A text dataset.
pub fn text(g: &Group, name: &str) -> hdf5::Result<Vec<String>> {
    read_strings(&dataset(g, name)?).map_err(|e| about(&path_of(g, name), e))
}

/// A string attribute.
pub fn attr(g: &hdf5::Location, name: &str) -> hdf5::Result<String> {
    read_attr_str(g, name).map_err(|e| about(&format!("{} attribute {name}", g.name()), e))
}

/// A numeric attribute.
pub fn attr_number<T: H5Type>(g: &hdf5::Location, name: &str) -> hdf5::Result<T> {
    g.attr(name).and_then(|a| a.read_scalar()).map_err(|e| about(&format!("{} attribute {name}", g.name()), e))
}

/// The rows of a 2-D dataset (empty if it is absent).
pub fn rows(g: &Group, name: &str) -> hdf5::Result<Vec<Vec<f64>>> {
    if !g.link_exists(name) {
        return Ok(Vec::new());
    }
    let ds = dataset(g, name)?;
    let a: ndarray::Array2<f64> =
        crate::h5::check_extent(&ds).and_then(|_| ds.read_2d()).map_err(|e| about(&path_of(g, name), e))?;
    Ok(a.rows().into_iter().map(|r| r.to_vec()).collect())
}
