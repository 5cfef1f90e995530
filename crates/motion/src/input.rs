//! Reading an input file (a record, a config) safely: only a regular file
//! is read, and only up to a size limit, so that a FIFO (which would block
//! until something writes to it), a device (`/dev/zero` never ends) or a
//! folder is refused at once, with its kind named, instead of hanging or
//! filling the memory.

use std::io::{Error, ErrorKind, Read};
use std::path::Path;

/// Largest record file read \[bytes\]: a day at 1000 samples/s written with
/// 12 characters a value is about 1 GB.
pub const MAX_RECORD_BYTES: u64 = 1 << 30;

/// Largest config file read \[bytes\]: configs are a few kilobytes.
pub const MAX_CONFIG_BYTES: u64 = 16 << 20;

/// Largest modes file or hazard curve read \[bytes\]: a modes file of a
/// thousand modes at a hundred points is a few megabytes.
pub const MAX_TABLE_BYTES: u64 = 256 << 20;

/// What a path that is not a regular file is, in words.
fn kind(meta: &std::fs::Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    let t = meta.file_type();
    if t.is_dir() {
        "a folder"
    } else if t.is_fifo() {
        "a FIFO (named pipe)"
    } else if t.is_char_device() || t.is_block_device() {
        "a device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "not a regular file"
    }
}

/// The metadata of `path` if it is a regular file: a FIFO, a device, a
/// socket or a folder is refused without being opened (the error says
/// what it is). Every file the tool opens goes through this check, the
/// ones it reads whole ([`read_input`]) and the HDF5 files it opens.
pub fn regular_file(path: &Path) -> std::io::Result<std::fs::Metadata> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(Error::new(ErrorKind::InvalidInput, format!("it is {}, not a file that can be read", kind(&meta))));
    }
    Ok(meta)
}

/// The bytes of the regular file `path`, at most `max_bytes` of them: a
/// FIFO, a device, a socket or a folder is refused without being opened
/// ([`regular_file`]), and so is a larger file (the error says which limit).
pub fn read_input(path: &Path, max_bytes: u64) -> std::io::Result<Vec<u8>> {
    let meta = regular_file(path)?;
    let too_big = || {
        Error::new(ErrorKind::InvalidInput, format!("it is larger than {} MB, the most that is read", max_bytes >> 20))
    };
    if meta.len() > max_bytes {
        return Err(too_big());
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    std::fs::File::open(path)?.take(max_bytes + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_big());
    }
    Ok(bytes)
}

/// The text of the regular file `path` (as [`read_input`]), which must be
/// UTF-8.
pub fn read_input_text(path: &Path, max_bytes: u64) -> std::io::Result<String> {
    String::from_utf8(read_input(path, max_bytes)?).map_err(|e| {
        Error::new(ErrorKind::InvalidData, format!("it is not UTF-8 text (byte {})", e.utf8_error().valid_up_to()))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_folders_and_large_files_are_refused() {
        let e = read_input(Path::new("/dev/zero"), 10).unwrap_err().to_string();
        assert!(e.contains("a device"), "{e}");
        let e = read_input(Path::new("/"), 10).unwrap_err().to_string();
        assert!(e.contains("a folder"), "{e}");
        let dir = std::env::temp_dir().join(format!("qj-input-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("f.txt");
        std::fs::write(&file, "0123456789").unwrap();
        assert_eq!(read_input(&file, 10).unwrap().len(), 10);
        assert!(read_input(&file, 9).unwrap_err().to_string().contains("larger than"));
        let fifo = dir.join("fifo");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status().is_ok_and(|s| s.success());
        if made {
            assert!(read_input(&fifo, 10).unwrap_err().to_string().contains("FIFO"));
        }
        std::fs::write(&file, [0xffu8, b'a']).unwrap();
        assert!(read_input_text(&file, 10).unwrap_err().to_string().contains("not UTF-8"));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
