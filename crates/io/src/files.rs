//! Which file is which: identity of paths and what an existing file is, for
//! refusing to overwrite inputs and files that are not outputs.

use std::path::Path;

/// Whether two paths name the same file (by device and inode when both
/// exist, else by their absolute, normalised names).
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    if let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) {
        use std::os::unix::fs::MetadataExt;
        return (ma.dev(), ma.ino()) == (mb.dev(), mb.ino());
    }
    let normal = |p: &Path| {
        let abs = std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
        match (abs.parent().and_then(|d| std::fs::canonicalize(d).ok()), abs.file_name()) {
            (Some(dir), Some(name)) => dir.join(name),
            _ => abs,
        }
    };
    normal(a) == normal(b)
}

/// What an existing file is, in words (for refusing to overwrite it).
pub fn describe(path: &Path) -> String {
    let head = quakejoint_motion::regular_file(path)
        .and_then(|_| std::fs::File::open(path))
        .and_then(|mut f| {
            let mut b = [0u8; 8];
            std::io::Read::read(&mut f, &mut b).map(|n| b[..n].to_vec())
        })
        .unwrap_or_default();
    if head.starts_with(b"QJJOURN1") {
        "a quakejoint journal".into()
    } else if head.starts_with(b"\x89HDF\r\n\x1a\n") {
        match kind_of(path) {
            Some(kind) => format!("the HDF5 output of a quakejoint {kind}"),
            None => "an HDF5 file".into(),
        }
    } else {
        "a file that is not a sweep output".into()
    }
}

/// The `kind` attribute of a quakejoint HDF5 file, if `path` is one.
pub fn kind_of(path: &Path) -> Option<String> {
    let file = crate::read::open(path).ok()?;
    crate::h5::read_attr_str(&file, "kind").ok()
}

/// Refuses an output name the HDF5 library cannot take (it needs UTF-8),
/// before anything runs.
pub fn check_name(path: &Path) -> Result<(), String> {
    if path.to_str().is_none() {
        return Err(format!(
            "{}: the HDF5 library takes only UTF-8 file names, and this one is not; choose another name",
            path.display()
        ));
    }
    Ok(())
}

/// Refuses to write the output `path` (of the given kind: `simulate`,
/// `service`, `sparsity`) over an input, or over an existing file that is
/// not an earlier output of the same kind.
pub fn check_overwrite(path: &Path, kind: &str, inputs: &[&Path]) -> Result<(), String> {
    check_name(path)?;
    if let Some(input) = inputs.iter().find(|i| same_file(path, i)) {
        return Err(format!("{}: writing there would overwrite the input {}", path.display(), input.display()));
    }
    if path.exists() && kind_of(path).as_deref() != Some(kind) {
        return Err(format!(
            "{} exists and is {}, not an earlier `{kind}` output: it is not overwritten",
            path.display(),
            describe(path)
        ));
    }
    Ok(())
}
