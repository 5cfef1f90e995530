//! The output lock: one sweep (or merge) writes an output at a time.
//!
//! The lock is an advisory `flock` on `<output>.lock`, a file created if
//! missing and never deleted or renamed (deleting a lock file lets a second
//! process lock a new file of the same name). It is taken before anything
//! else of the output is created, read for continuing or deleted, and held
//! until the lock is dropped or the process ends, killed or not.

use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};

use crate::error::SweepError;

/// A held lock on an output.
#[derive(Debug)]
pub struct OutputLock {
    _file: File,
    /// Where locking is impossible (a file system without `flock`), why.
    pub unsupported: Option<String>,
}

/// `<output>.lock`.
pub fn lock_path(output: &Path) -> PathBuf {
    let mut s = output.as_os_str().to_owned();
    s.push(".lock");
    PathBuf::from(s)
}

impl OutputLock {
    /// Takes the lock of `output`, or says who holds it.
    pub fn acquire(output: &Path) -> Result<Self, SweepError> {
        let path = lock_path(output);
        let file =
            OpenOptions::new().create(true).truncate(false).write(true).open(&path).map_err(|e| SweepError::Io {
                path: output.display().to_string(),
                message: format!("the output location is not writable ({}: {e})", path.display()),
            })?;
        match file.try_lock() {
            Ok(()) => Ok(Self { _file: file, unsupported: None }),
            Err(std::fs::TryLockError::WouldBlock) => Err(SweepError::Journal {
                path: output.display().to_string(),
                message: "another quakejoint process is writing this output (its lock file is held): let it \
                          finish or stop it first"
                    .into(),
            }),
            Err(std::fs::TryLockError::Error(e)) => Ok(Self {
                _file: file,
                unsupported: Some(format!(
                    "{}: the file system cannot lock files ({e}); make sure no other sweep writes this output",
                    path.display()
                )),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_holder_is_refused_until_the_first_lets_go() {
        let dir = std::env::temp_dir().join(format!("qj-lock-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("out.h5");
        let first = OutputLock::acquire(&out).unwrap();
        let err = OutputLock::acquire(&out).unwrap_err().to_string();
        assert!(err.contains("another quakejoint process is writing this output"), "{err}");
        drop(first);
        let _again = OutputLock::acquire(&out).unwrap();
        assert!(lock_path(&out).exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
