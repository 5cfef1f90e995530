//! Reading an output file back, each object named in the errors: a failed
//! checksum says the file is damaged and which dataset (`/spectrum/reduction
//! is damaged: its checksum fails`), and an array larger than any output
//! holds is refused before it is allocated.

use std::path::Path;

use hdf5::{Dataset, Group, H5Type};

use crate::h5::{read_attr_str, read_strings};

/// Opens an HDF5 file to read: only a regular file is opened (a FIFO
/// would block the library until something writes to it, a device never
/// ends), through [`quakejoint_motion::regular_file`], the check of every
/// input the tool opens.
pub fn open(path: &Path) -> hdf5::Result<hdf5::File> {
    quakejoint_motion::regular_file(path).map_err(|e| hdf5::Error::from(e.to_string()))?;
    hdf5::File::open(path)
}

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

/// The value of an attribute: text, or a number.
#[derive(Debug, Clone, PartialEq)]
pub enum AttrValue {
    /// Text.
    Text(String),
    /// A signed whole number.
    Int(i64),
    /// An unsigned whole number.
    UInt(u64),
    /// A real number.
    Float(f64),
}

/// Every attribute of `loc`, read (text checked as UTF-8), in name order,
/// but the dimension scales' of files before schema 12
/// ([`crate::h5::SCALE_ATTRIBUTES`]); a damaged one named.
pub fn attributes(loc: &hdf5::Location) -> hdf5::Result<Vec<(String, AttrValue)>> {
    use hdf5::types::TypeDescriptor as TD;
    let mut names = loc.attr_names().map_err(|e| about(&format!("{} attributes", loc.name()), e))?;
    names.retain(|n| !crate::h5::SCALE_ATTRIBUTES.contains(&n.as_str()));
    names.sort();
    names
        .into_iter()
        .map(|name| {
            let what = format!("{} attribute {name}", loc.name());
            let a = loc.attr(&name).map_err(|e| about(&what, e))?;
            let value = match a.dtype().and_then(|t| t.to_descriptor()).map_err(|e| about(&what, e))? {
                TD::Integer(_) => AttrValue::Int(a.read_scalar().map_err(|e| about(&what, e))?),
                TD::Unsigned(_) | TD::Boolean => AttrValue::UInt(a.read_scalar().map_err(|e| about(&what, e))?),
                TD::Float(_) => AttrValue::Float(a.read_scalar().map_err(|e| about(&what, e))?),
                _ => AttrValue::Text(attr(loc, &name)?),
            };
            Ok((name, value))
        })
        .collect()
}

/// Reads every attribute of every object in `group` and below (the
/// attributes a reader does not use itself too): attribute text is under
/// HDF5's metadata checksums (`crate::h5::attr_str`), which a read checks,
/// so a damaged attribute anywhere is named.
pub fn check_attributes(group: &Group) -> hdf5::Result<()> {
    group.loc_info().map_err(|e| about(&group.name(), e))?;
    attributes(group)?;
    for name in group.member_names().map_err(|e| about(&group.name(), e))? {
        let path = path_of(group, &name);
        // the object's kind from its header, once: libhdf5 1.10 refuses a
        // damaged header the first time it is loaded, but opening it again
        // after that failure succeeds (the header stays in its cache
        // unverified), so an object is never opened a second time after a
        // failed attempt
        // (the full information: every chunk of the object's header is
        // loaded and checked, also those that hold nothing the reader
        // asks for)
        match group.loc_info_by_name(&name).map_err(|e| about(&path, e))?.loc_type {
            hdf5::LocationType::Group => check_attributes(&group.group(&name).map_err(|e| about(&path, e))?)?,
            _ => {
                let ds = group.dataset(&name).map_err(|e| about(&path, e))?;
                attributes(&ds)?;
            }
        }
    }
    Ok(())
}
