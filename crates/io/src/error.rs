//! The error of writing or reading an output file.

use std::path::Path;

use thiserror::Error;

/// Writing an output file failed.
#[derive(Debug, Error)]
#[error("{path}: {message}")]
pub struct OutputError {
    /// The file.
    pub path: String,
    /// What went wrong.
    pub message: String,
}

impl OutputError {
    /// A failed file operation on `path`.
    pub fn io(path: &Path, e: std::io::Error) -> Self {
        Self { path: path.display().to_string(), message: e.to_string() }
    }
    /// A failed HDF5 operation on `path`, in the user's words.
    pub fn hdf5(path: &Path, e: hdf5::Error) -> Self {
        Self { path: path.display().to_string(), message: in_words(&e.to_string()) }
    }
}

/// An HDF5 error in the user's words: a failed system call as the
/// operating system says it (`File too large (os error 27)`, `No space
/// left on device (os error 28)`), not the library's internals (buffer
/// addresses, `bytes actually written = 18446744073709551615`); other
/// messages as they are, after `HDF5: `.
fn in_words(text: &str) -> String {
    let errno =
        text.split("errno = ").nth(1).and_then(|r| r.split(',').next()).and_then(|n| n.trim().parse::<i32>().ok());
    let said = text.split("error message = '").nth(1).and_then(|r| r.split('\'').next());
    match (errno, said) {
        (Some(n), Some(m)) => {
            let action = if text.contains("write") { "writing" } else { "reading" };
            format!("{action} failed: {m} (os error {n})")
        }
        _ => format!("HDF5: {}", text.trim()),
    }
}

#[cfg(test)]
mod tests {
    use super::in_words;

    #[test]
    fn system_errors_are_said_as_the_system_says_them() {
        let e = "H5Fflush(): unable to flush file's cached information: file write failed: time = Thu Nov 26 \
                 14:57:59 2026\n, filename = 'r.h5.tmp', file descriptor = 3, errno = 28, error message = 'No space \
                 left on device', buf = 0x560e712aad46, total write size = 1498, bytes this sub-write = 1498, bytes \
                 actually written = 18446744073709551615, offset = 0";
        assert_eq!(in_words(e), "writing failed: No space left on device (os error 28)");
        assert_eq!(in_words("/spectrum/reduction is damaged"), "HDF5: /spectrum/reduction is damaged");
    }
}
