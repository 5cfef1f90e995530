//! The crash-safe journal of a sweep: the truth for `--resume`.
//!
//! Layout: the magic `QJJOURN1`, then frames of `[length: u32 LE][CRC-32 of
//! the payload: u32 LE][payload]`, each payload a bincode (2.0, standard
//! config) encoding: first a [`Header`], then one [`JobResult`] per finished
//! job. Every frame is written with one `write_all`, flushed and fsynced
//! before the next job is acknowledged. A torn or corrupt last frame (a
//! crash during an append) is ignored on reading and cut off before new
//! frames are appended; a journal without a complete header (a crash while
//! it was being created, before any job finished) is started afresh. The
//! open journal is locked ([`File::try_lock`]), so that a second sweep into
//! the same output is refused while the first runs.

use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::SweepError;
use crate::results::JobResult;

const MAGIC: &[u8; 8] = b"QJJOURN1";
/// Frames longer than this are corrupt (a history of 40 s at 5 ms is ~0.5 MB).
const MAX_FRAME: u32 = 256 << 20;

/// What determines a sweep's results, checked on `--resume`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Header {
    /// Version of the journal format.
    pub schema: u32,
    /// Version of the program that wrote it.
    pub program_version: String,
    /// SHA-256 of the parsed config.
    pub config_sha256: String,
    /// Name and SHA-256 of each record file.
    pub records: Vec<(String, String)>,
    /// Number of jobs of the whole sweep.
    pub jobs: u64,
    /// The shard (k, n), if sharded.
    pub shard: Option<(u32, u32)>,
}

impl Header {
    /// What differs between a journal's header and the current run, in words.
    pub fn differences(&self, current: &Header) -> Vec<String> {
        let mut out = Vec::new();
        if self.program_version != current.program_version {
            out.push(format!(
                "the program version changed from {} to {}",
                self.program_version, current.program_version
            ));
        }
        if self.config_sha256 != current.config_sha256 {
            out.push("the config changed (its parameters, not only comments or layout)".to_string());
        }
        for (name, hash) in &current.records {
            match self.records.iter().find(|(n, _)| n == name) {
                Some((_, h)) if h != hash => out.push(format!("the contents of record {name:?} changed")),
                None => out.push(format!("record {name:?} is new")),
                _ => {}
            }
        }
        for (name, _) in &self.records {
            if !current.records.iter().any(|(n, _)| n == name) {
                out.push(format!("record {name:?} was removed"));
            }
        }
        if self.jobs != current.jobs && out.is_empty() {
            out.push(format!("the number of jobs changed from {} to {}", self.jobs, current.jobs));
        }
        if self.shard != current.shard {
            out.push(format!("the shard changed from {:?} to {:?}", self.shard, current.shard));
        }
        if self.schema != current.schema {
            out.push(format!("the journal format changed from {} to {}", self.schema, current.schema));
        }
        out
    }
}

/// An open journal, positioned for appending.
#[derive(Debug)]
pub struct Journal {
    path: PathBuf,
    file: File,
}

fn jerr(path: &Path, message: impl Into<String>) -> SweepError {
    SweepError::Journal { path: path.display().to_string(), message: message.into() }
}

/// A failure of the machine (disk full, permissions), not of the input.
fn io_error(path: &Path, message: String) -> SweepError {
    SweepError::Io { path: path.display().to_string(), message }
}

fn encode<T: Serialize>(value: &T) -> Vec<u8> {
    bincode::serde::encode_to_vec(value, bincode::config::standard()).expect("plain data encodes")
}

fn frame(payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(payload.len() + 8);
    out.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    out.extend_from_slice(&crc32fast::hash(payload).to_le_bytes());
    out.extend_from_slice(payload);
    out
}

/// Reads the frames of a journal: the payloads of the valid ones, and the
/// byte offset after the last valid frame.
fn read_frames(bytes: &[u8]) -> (Vec<&[u8]>, usize) {
    let mut at = MAGIC.len();
    let mut frames = Vec::new();
    while at + 8 <= bytes.len() {
        let len = u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
        let crc = u32::from_le_bytes(bytes[at + 4..at + 8].try_into().expect("4 bytes"));
        if len > MAX_FRAME || at + 8 + len as usize > bytes.len() {
            break;
        }
        let payload = &bytes[at + 8..at + 8 + len as usize];
        if crc32fast::hash(payload) != crc {
            break;
        }
        frames.push(payload);
        at += 8 + len as usize;
    }
    (frames, at)
}

/// Takes the journal's advisory lock, held until the file is closed (the
/// process ends, killed or not): one sweep writes an output at a time. Where
/// the file system cannot lock, the sweep goes on unlocked.
fn lock(file: &File, path: &Path) -> Result<(), SweepError> {
    match file.try_lock() {
        Ok(()) | Err(std::fs::TryLockError::Error(_)) => Ok(()),
        Err(std::fs::TryLockError::WouldBlock) => Err(jerr(
            path,
            "another quakejoint sweep is writing this output (its journal is locked): let it finish or stop it \
             first",
        )),
    }
}

/// A journal's contents: its header, its results, and the byte offset after
/// the last valid frame (a torn last frame lies beyond it).
struct Contents {
    header: Header,
    results: Vec<JobResult>,
    valid: usize,
}

/// Decodes a journal's bytes; `None` for a journal cut while it was being
/// created (only part of the magic, or no complete header: no job finished).
fn parse(bytes: &[u8], path: &Path) -> Result<Option<Contents>, SweepError> {
    if bytes.len() < MAGIC.len() && MAGIC.starts_with(bytes) {
        return Ok(None);
    }
    if bytes.len() < MAGIC.len() || &bytes[..MAGIC.len()] != MAGIC {
        return Err(jerr(path, "not a quakejoint journal"));
    }
    let (frames, valid) = read_frames(bytes);
    let Some((first, rest)) = frames.split_first() else { return Ok(None) };
    let header: Header = bincode::serde::decode_from_slice(first, bincode::config::standard())
        .map_err(|e| jerr(path, format!("unreadable header: {e}")))?
        .0;
    let results = rest
        .iter()
        .map(|payload| {
            bincode::serde::decode_from_slice(payload, bincode::config::standard())
                .map(|r| r.0)
                .map_err(|e| jerr(path, format!("unreadable job record: {e}")))
        })
        .collect::<Result<_, _>>()?;
    Ok(Some(Contents { header, results, valid }))
}

impl Journal {
    /// Creates a new journal (the file must not exist).
    pub fn create(path: &Path, header: &Header) -> Result<Self, SweepError> {
        let mut file = OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(path)
            .map_err(|e| io_error(path, format!("cannot create the journal: {e}")))?;
        lock(&file, path)?;
        let mut bytes = MAGIC.to_vec();
        bytes.extend(frame(&encode(header)));
        file.write_all(&bytes)
            .and_then(|_| file.sync_all())
            .map_err(|e| io_error(path, format!("cannot write the journal: {e}")))?;
        Ok(Self { path: path.to_path_buf(), file })
    }

    /// Opens an existing journal to resume: checks its header against
    /// `expected` (refusing, with what changed, if they differ), returns the
    /// journalled results and cuts off a torn last frame.
    pub fn resume(path: &Path, expected: &Header) -> Result<(Self, Vec<JobResult>), SweepError> {
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .open(path)
            .map_err(|e| jerr(path, format!("cannot open the journal to resume: {e}")))?;
        lock(&file, path)?;
        let mut bytes = Vec::new();
        file.read_to_end(&mut bytes).map_err(|e| jerr(path, e.to_string()))?;
        let Some(Contents { header, results, valid }) = parse(&bytes, path)? else {
            // killed while the journal was being created: nothing finished yet
            drop(file);
            std::fs::remove_file(path).map_err(|e| jerr(path, e.to_string()))?;
            return Ok((Self::create(path, expected)?, Vec::new()));
        };
        let diffs = header.differences(expected);
        if !diffs.is_empty() {
            return Err(jerr(
                path,
                format!(
                    "cannot resume: {}; start a new sweep (another output name, or delete this journal)",
                    diffs.join("; ")
                ),
            ));
        }
        if let Some(r) = results.iter().find(|r| r.job as u64 >= expected.jobs) {
            return Err(jerr(path, format!("job {} does not exist in this sweep", r.job)));
        }
        if valid < bytes.len() {
            file.set_len(valid as u64).map_err(|e| jerr(path, e.to_string()))?;
        }
        file.seek(SeekFrom::Start(valid as u64)).map_err(|e| jerr(path, e.to_string()))?;
        Ok((Self { path: path.to_path_buf(), file }, results))
    }

    /// Appends one result, durably (the frame is written in two halves, with
    /// a fault-injection point between them, [`crate::fault`]).
    pub fn append(&mut self, result: &JobResult) -> Result<(), SweepError> {
        let bytes = frame(&encode(result));
        let (first, second) = bytes.split_at(bytes.len() / 2);
        let write = |file: &mut File, part: &[u8]| file.write_all(part).and_then(|_| file.sync_data());
        write(&mut self.file, first)
            .and_then(|_| {
                crate::fault::point(crate::fault::Point::Journal, &self.path);
                write(&mut self.file, second)
            })
            .map_err(|e| io_error(&self.path, format!("cannot append to the journal: {e}")))
    }

    /// The journal's path.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// Reads the results of a journal without opening it for writing (for
/// inspection and tests).
pub fn read(path: &Path) -> Result<(Header, Vec<JobResult>), SweepError> {
    let bytes = std::fs::read(path).map_err(|e| jerr(path, e.to_string()))?;
    let contents =
        parse(&bytes, path)?.ok_or_else(|| jerr(path, "no header: the journal was cut while it was being created"))?;
    Ok((contents.header, contents.results))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> Header {
        Header {
            schema: 1,
            program_version: "0.1.0".into(),
            config_sha256: "abc".into(),
            records: vec![("r".into(), "h".into())],
            jobs: 10,
            shard: None,
        }
    }

    fn result(job: u32) -> JobResult {
        JobResult { job, status: 0, message: String::new(), values: vec![job as f64; 3], history: None }
    }

    #[test]
    fn torn_last_frame_is_ignored_and_cut_off() {
        let dir = std::env::temp_dir().join(format!("qj-journal-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("torn.journal");
        let _ = std::fs::remove_file(&path);
        let mut j = Journal::create(&path, &header()).unwrap();
        j.append(&result(3)).unwrap();
        j.append(&result(7)).unwrap();
        drop(j);
        // a crash in the middle of the third append
        let full = std::fs::read(&path).unwrap();
        let mut torn = full.clone();
        torn.extend_from_slice(&frame(&encode(&result(9)))[..10]);
        std::fs::write(&path, &torn).unwrap();
        let (mut j, got) = Journal::resume(&path, &header()).unwrap();
        assert_eq!(got, vec![result(3), result(7)]);
        assert_eq!(std::fs::metadata(&path).unwrap().len(), full.len() as u64);
        j.append(&result(9)).unwrap();
        drop(j);
        let (_, all) = read(&path).unwrap();
        assert_eq!(all.len(), 3);
        // a flipped byte in the payload of the last frame
        let mut bad = std::fs::read(&path).unwrap();
        let n = bad.len();
        bad[n - 2] ^= 0xff;
        std::fs::write(&path, &bad).unwrap();
        let (_, got) = Journal::resume(&path, &header()).unwrap();
        assert_eq!(got.len(), 2);
    }

    #[test]
    fn a_journal_torn_while_being_created_starts_afresh() {
        let dir = std::env::temp_dir().join(format!("qj-journal-new-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("new.journal");
        let mut whole = MAGIC.to_vec();
        whole.extend(frame(&encode(&header())));
        for cut in [0, 3, MAGIC.len(), MAGIC.len() + 5, whole.len() - 1] {
            std::fs::write(&path, &whole[..cut]).unwrap();
            let (mut j, got) = Journal::resume(&path, &header()).unwrap();
            assert!(got.is_empty(), "cut at {cut}");
            j.append(&result(4)).unwrap();
            drop(j);
            let (h, all) = read(&path).unwrap();
            assert_eq!((h, all), (header(), vec![result(4)]), "cut at {cut}");
        }
        // not a journal at all: refused, not overwritten
        std::fs::write(&path, b"something else entirely").unwrap();
        assert!(Journal::resume(&path, &header()).unwrap_err().to_string().contains("not a quakejoint journal"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_second_writer_is_refused_while_the_first_holds_the_journal() {
        let dir = std::env::temp_dir().join(format!("qj-journal-lock-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("locked.journal");
        let _ = std::fs::remove_file(&path);
        let first = Journal::create(&path, &header()).unwrap();
        let err = Journal::resume(&path, &header()).unwrap_err().to_string();
        assert!(err.contains("another quakejoint sweep is writing this output"), "{err}");
        drop(first);
        assert!(Journal::resume(&path, &header()).is_ok(), "the lock ends with the first writer");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_changed_config_or_record_is_named() {
        let mut other = header();
        other.config_sha256 = "def".into();
        other.records[0].1 = "x".into();
        let d = header().differences(&other);
        assert!(d.iter().any(|s| s.contains("config changed")), "{d:?}");
        assert!(d.iter().any(|s| s.contains("record \"r\" changed")), "{d:?}");
        assert!(header().differences(&header()).is_empty());
    }
}
