//! The crash-safe journal of a sweep: the truth for resuming.
//!
//! Layout: the magic `QJJOURN1`, then frames of `[length: u32 LE][CRC-32 of
//! the payload: u32 LE][payload]`, each payload a bincode (2.0, standard
//! config) encoding: first a [`Header`], then one [`JobResult`] per finished
//! job. Every frame is written with one `write_all`, flushed and fsynced
//! before the next job is acknowledged. A job may appear more than once (a
//! failed job retried with `--retry-failed`): the last entry wins.
//!
//! Reading is forgiving and never silent:
//! - a torn last frame (a crash during an append) is cut off before new
//!   frames are appended;
//! - a corrupt frame in the middle (a flipped bit on disk) is skipped: the
//!   reader searches for the next frame whose checksum holds, keeps every
//!   entry after it, and reports the byte offset and size of what it
//!   skipped ([`Contents::notices`]); a resume then rewrites the journal
//!   without the damaged bytes (under a temporary name, renamed into
//!   place), so the warning is given once;
//! - a journal without a complete header (a crash while it was being
//!   created, before any job finished) is started afresh.
//!
//! The journal is not locked itself: the sweep holds the output's lock
//! ([`crate::lock`]) before it creates, reads or rewrites it.

use std::fs::{File, OpenOptions};
use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::SweepError;
use crate::results::JobResult;

const MAGIC: &[u8; 8] = b"QJJOURN1";
/// Frames longer than this are corrupt (a history of 40 s at 5 ms is ~0.5 MB).
const MAX_FRAME: u32 = 256 << 20;

/// What determines a sweep's results, checked when a sweep continues.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Header {
    /// Version of the journal format.
    pub schema: u32,
    /// Version of the program that wrote it.
    pub program_version: String,
    /// SHA-256 of the parsed config (without the per-job limits, which
    /// change no finished result; with the modes file's contents of a
    /// bridge given by its modes).
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
                "it was written by quakejoint {}, this is {}",
                self.program_version, current.program_version
            ));
        }
        if self.config_sha256 != current.config_sha256 {
            out.push(
                "its config differs in its parameters, the defaults of this version included (or in the contents of the \
                 modes file of its [bridge.modal]), not only in comments or layout"
                    .to_string(),
            );
        }
        for (name, hash) in &current.records {
            match self.records.iter().find(|(n, _)| n == name) {
                Some((_, h)) if h != hash => out.push(format!("the contents of record {name:?} differ")),
                None => out.push(format!("record {name:?} is not in it")),
                _ => {}
            }
        }
        for (name, _) in &self.records {
            if !current.records.iter().any(|(n, _)| n == name) {
                out.push(format!("it has record {name:?}, this sweep does not"));
            }
        }
        if self.jobs != current.jobs && out.is_empty() {
            out.push(format!("it has {} jobs, this sweep {}", self.jobs, current.jobs));
        }
        if self.shard != current.shard {
            let name =
                |s: Option<(u32, u32)>| s.map_or("the whole sweep".to_string(), |(k, n)| format!("shard {k}/{n}"));
            out.push(format!("it was written for {}, this run is {}", name(self.shard), name(current.shard)));
        }
        if self.schema != current.schema {
            out.push(format!("its journal format is {}, this program's {}", self.schema, current.schema));
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

fn decode<T: serde::de::DeserializeOwned>(payload: &[u8]) -> Result<T, bincode::error::DecodeError> {
    bincode::serde::decode_from_slice(payload, bincode::config::standard()).map(|r| r.0)
}

fn frame(payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(payload.len() + 8);
    out.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    out.extend_from_slice(&crc32fast::hash(payload).to_le_bytes());
    out.extend_from_slice(payload);
    out
}

/// The payload of the frame starting at `at` and the offset after it, if
/// a whole frame with a matching checksum starts there.
fn frame_at(bytes: &[u8], at: usize) -> Option<(&[u8], usize)> {
    let head = bytes.get(at..at.checked_add(8)?)?;
    let len = u32::from_le_bytes(head[..4].try_into().expect("4 bytes"));
    let crc = u32::from_le_bytes(head[4..].try_into().expect("4 bytes"));
    if len > MAX_FRAME {
        return None;
    }
    let end = at + 8 + len as usize;
    let payload = bytes.get(at + 8..end)?;
    (crc32fast::hash(payload) == crc).then_some((payload, end))
}

/// What a journal holds.
#[derive(Debug, Clone, PartialEq)]
pub struct Contents {
    /// The header.
    pub header: Header,
    /// Every entry in file order (a retried job appears more than once; the
    /// last entry wins, [`Contents::latest`]).
    pub results: Vec<JobResult>,
    /// Damaged byte ranges in the middle that were skipped: (offset, length).
    pub damaged: Vec<(usize, usize)>,
    /// Byte offset after the last valid frame.
    pub valid: usize,
    /// Whether a torn last frame lies beyond `valid`.
    pub torn_tail: bool,
}

impl Contents {
    /// The last entry of every job, in order of job index.
    pub fn latest(&self) -> Vec<JobResult> {
        latest(&self.results)
    }

    /// Warnings about damage, naming the journal and the byte offsets.
    pub fn notices(&self, path: &Path) -> Vec<String> {
        self.damaged
            .iter()
            .map(|&(offset, len)| {
                format!(
                    "{}: {len} damaged bytes at byte offset {offset} failed their checksum and were skipped (the \
                     entries after them were kept); the jobs recorded there, if any, run again",
                    path.display()
                )
            })
            .collect()
    }
}

/// The last entry of every job, in order of job index.
pub fn latest(results: &[JobResult]) -> Vec<JobResult> {
    let mut by_job = std::collections::BTreeMap::new();
    for r in results {
        by_job.insert(r.job, r);
    }
    by_job.into_values().cloned().collect()
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
    let Some((first, mut at)) = frame_at(bytes, MAGIC.len()) else {
        // no header frame: torn while being created, unless entries follow
        if (MAGIC.len() + 1..bytes.len()).any(|s| next_entry(bytes, s)) {
            return Err(jerr(
                path,
                "the journal's header is damaged, so it cannot be matched to a config: remove it (and the output) \
                 to start the sweep over",
            ));
        }
        return Ok(None);
    };
    let header: Header = decode(first).map_err(|e| jerr(path, format!("unreadable header: {e}")))?;
    let (mut results, mut damaged, mut valid, mut torn_tail) = (Vec::new(), Vec::new(), at, false);
    while at < bytes.len() {
        match frame_at(bytes, at).map(|(p, end)| (decode::<JobResult>(p), end)) {
            Some((Ok(r), end)) => {
                results.push(r);
                at = end;
                valid = end;
            }
            // a frame whose checksum holds but that does not decode: an
            // entry of another journal format, which its header names (and
            // the sweep refuses the journal for it: Header::differences),
            // or written by something else: refuse rather than guess
            Some((Err(_), _)) if header.schema != crate::runner::JOURNAL_SCHEMA => {
                return Ok(Some(Contents { header, results, damaged, valid: at, torn_tail: false }));
            }
            Some((Err(e), _)) => return Err(jerr(path, format!("unreadable job record at byte {at}: {e}"))),
            None => match (at + 1..bytes.len()).find(|&s| next_entry(bytes, s)) {
                Some(s) => {
                    damaged.push((at, s - at));
                    at = s;
                }
                None => {
                    torn_tail = true;
                    break;
                }
            },
        }
    }
    Ok(Some(Contents { header, results, damaged, valid, torn_tail }))
}

/// Whether a whole, checksummed job entry starts at `at`.
fn next_entry(bytes: &[u8], at: usize) -> bool {
    frame_at(bytes, at).is_some_and(|(p, _)| decode::<JobResult>(p).is_ok())
}

/// Writes `bytes` to `path` through a temporary file, fsynced and renamed
/// into place (the directory fsynced too), so that `path` holds either the
/// old or the new bytes after a crash.
fn replace_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".rewrite");
    let tmp = PathBuf::from(tmp);
    let mut f = OpenOptions::new().write(true).create(true).truncate(true).open(&tmp)?;
    f.write_all(bytes)?;
    f.sync_all()?;
    std::fs::rename(&tmp, path)?;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        File::open(dir)?.sync_all()?;
    }
    Ok(())
}

/// The error for a journal written by a different sweep than this one.
pub fn another_sweep(path: &Path, diffs: &[String]) -> SweepError {
    let output = path.display().to_string();
    let output = output.trim_end_matches(".journal");
    jerr(
        path,
        format!(
            "{output} holds the results of a different sweep ({}): choose another --output for this one (or delete \
             {output} and its journal if those results are no longer needed)",
            diffs.join("; ")
        ),
    )
}

/// A journal opened to continue a sweep.
#[derive(Debug)]
pub struct Continued {
    /// The journal, positioned for appending.
    pub journal: Journal,
    /// The last entry of every journalled job.
    pub results: Vec<JobResult>,
    /// Warnings for the user (damage found and skipped).
    pub notices: Vec<String>,
}

impl Journal {
    /// Creates a new journal (the file must not exist: `O_EXCL`).
    pub fn create(path: &Path, header: &Header) -> Result<Self, SweepError> {
        let mut file = OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(path)
            .map_err(|e| io_error(path, format!("cannot create the journal: {e}")))?;
        let mut bytes = MAGIC.to_vec();
        bytes.extend(frame(&encode(header)));
        file.write_all(&bytes)
            .and_then(|_| file.sync_all())
            .map_err(|e| io_error(path, format!("cannot write the journal: {e}")))?;
        Ok(Self { path: path.to_path_buf(), file })
    }

    /// Opens an existing journal to continue its sweep (the caller holds the
    /// output's lock): checks its header against `expected` (refusing, with
    /// what changed, if they differ), returns the journalled results, cuts
    /// off a torn last frame and rewrites a journal with damage in the
    /// middle. A journal cut while it was being created is started afresh.
    pub fn continue_or_restart(path: &Path, expected: &Header) -> Result<Continued, SweepError> {
        let bytes = read_bytes(path).map_err(|e| jerr(path, format!("cannot read the journal: {e}")))?;
        let Some(contents) = parse(&bytes, path)? else {
            // killed while the journal was being created: nothing finished yet
            std::fs::remove_file(path).map_err(|e| io_error(path, e.to_string()))?;
            return Ok(Continued { journal: Self::create(path, expected)?, results: Vec::new(), notices: Vec::new() });
        };
        let diffs = contents.header.differences(expected);
        if !diffs.is_empty() {
            return Err(another_sweep(path, &diffs));
        }
        if let Some(r) = contents.results.iter().find(|r| r.job as u64 >= expected.jobs) {
            return Err(jerr(path, format!("job {} does not exist in this sweep", r.job)));
        }
        let results = contents.latest();
        let notices = contents.notices(path);
        if !contents.damaged.is_empty() {
            let mut clean = MAGIC.to_vec();
            clean.extend(frame(&encode(&contents.header)));
            for r in &results {
                clean.extend(frame(&encode(r)));
            }
            replace_atomically(path, &clean)
                .map_err(|e| io_error(path, format!("cannot rewrite the damaged journal: {e}")))?;
        }
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .open(path)
            .map_err(|e| jerr(path, format!("cannot open the journal: {e}")))?;
        let end = if contents.damaged.is_empty() {
            if contents.torn_tail {
                file.set_len(contents.valid as u64).map_err(|e| io_error(path, e.to_string()))?;
            }
            contents.valid as u64
        } else {
            file.metadata().map_err(|e| io_error(path, e.to_string()))?.len()
        };
        file.seek(SeekFrom::Start(end)).map_err(|e| io_error(path, e.to_string()))?;
        Ok(Continued { journal: Self { path: path.to_path_buf(), file }, results, notices })
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

/// A journal's bytes: a regular file only (a FIFO or a device in its place
/// is refused, not read), of any size.
fn read_bytes(path: &Path) -> std::io::Result<Vec<u8>> {
    quakejoint_motion::read_input(path, u64::MAX - 1)
}

/// Reads a journal without opening it for writing (for inspection and
/// tests): every entry in file order.
pub fn read(path: &Path) -> Result<(Header, Vec<JobResult>), SweepError> {
    let c = read_contents(path)?;
    Ok((c.header, c.results))
}

/// Reads a journal's contents, damage included, without changing it;
/// `None` for a journal cut while it was being created (which a sweep
/// starts afresh, [`Journal::continue_or_restart`]).
pub fn read_started(path: &Path) -> Result<Option<Contents>, SweepError> {
    let bytes = read_bytes(path).map_err(|e| jerr(path, e.to_string()))?;
    parse(&bytes, path)
}

/// Reads a journal's contents, damage included, without changing it.
pub fn read_contents(path: &Path) -> Result<Contents, SweepError> {
    let bytes = read_bytes(path).map_err(|e| jerr(path, e.to_string()))?;
    parse(&bytes, path)?.ok_or_else(|| jerr(path, "no header: the journal was cut while it was being created"))
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
        JobResult {
            job,
            status: 0,
            message: String::new(),
            values: vec![job as f64; 3],
            validity: 0,
            findings: String::new(),
            history: None,
            joints: Vec::new(),
        }
    }

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("qj-journal-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn torn_last_frame_is_ignored_and_cut_off() {
        let dir = scratch("torn");
        let path = dir.join("torn.journal");
        let mut j = Journal::create(&path, &header()).unwrap();
        j.append(&result(3)).unwrap();
        j.append(&result(7)).unwrap();
        drop(j);
        // a crash in the middle of the third append
        let full = std::fs::read(&path).unwrap();
        let mut torn = full.clone();
        torn.extend_from_slice(&frame(&encode(&result(9)))[..10]);
        std::fs::write(&path, &torn).unwrap();
        let c = Journal::continue_or_restart(&path, &header()).unwrap();
        assert_eq!(c.results, vec![result(3), result(7)]);
        assert!(c.notices.is_empty(), "a torn tail is a normal crash: {:?}", c.notices);
        assert_eq!(std::fs::metadata(&path).unwrap().len(), full.len() as u64);
        let mut j = c.journal;
        j.append(&result(9)).unwrap();
        drop(j);
        let (_, all) = read(&path).unwrap();
        assert_eq!(all.len(), 3);
        // a flipped byte in the payload of the last frame
        let mut bad = std::fs::read(&path).unwrap();
        let n = bad.len();
        bad[n - 2] ^= 0xff;
        std::fs::write(&path, &bad).unwrap();
        assert_eq!(Journal::continue_or_restart(&path, &header()).unwrap().results.len(), 2);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_damaged_entry_in_the_middle_is_named_and_the_later_ones_are_kept() {
        let dir = scratch("flip");
        let path = dir.join("flip.journal");
        let mut j = Journal::create(&path, &header()).unwrap();
        for job in 0..8 {
            j.append(&result(job)).unwrap();
        }
        drop(j);
        let whole = std::fs::read(&path).unwrap();
        // offset of the frame of job 2 (frames are of equal size)
        let first = MAGIC.len() + frame(&encode(&header())).len();
        let size = frame(&encode(&result(0))).len();
        for (what, at) in [("payload", first + 2 * size + 12), ("length", first + 2 * size + 1)] {
            let mut bad = whole.clone();
            bad[at] ^= 0x10;
            std::fs::write(&path, &bad).unwrap();
            let contents = read_contents(&path).unwrap();
            assert_eq!(contents.damaged, vec![(first + 2 * size, size)], "{what}");
            let notices = contents.notices(&path);
            assert!(notices[0].contains(&format!("byte offset {}", first + 2 * size)), "{what}: {notices:?}");
            let c = Journal::continue_or_restart(&path, &header()).unwrap();
            let jobs: Vec<u32> = c.results.iter().map(|r| r.job).collect();
            assert_eq!(jobs, vec![0, 1, 3, 4, 5, 6, 7], "{what}");
            assert_eq!(c.notices.len(), 1, "{what}");
            let mut j = c.journal;
            j.append(&result(2)).unwrap();
            drop(j);
            // rewritten without the damage: no second warning
            let again = read_contents(&path).unwrap();
            assert!(again.damaged.is_empty() && !again.torn_tail, "{what}");
            assert_eq!(again.latest().len(), 8, "{what}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_retried_job_is_taken_from_its_last_entry() {
        let dir = scratch("retry");
        let path = dir.join("retry.journal");
        let mut j = Journal::create(&path, &header()).unwrap();
        let failed = JobResult { status: 1, message: "failed".into(), ..result(4) };
        j.append(&failed).unwrap();
        j.append(&result(5)).unwrap();
        j.append(&result(4)).unwrap();
        drop(j);
        let c = Journal::continue_or_restart(&path, &header()).unwrap();
        assert_eq!(c.results, vec![result(4), result(5)]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_journal_torn_while_being_created_starts_afresh() {
        let dir = scratch("new");
        let path = dir.join("new.journal");
        let mut whole = MAGIC.to_vec();
        whole.extend(frame(&encode(&header())));
        for cut in [0, 3, MAGIC.len(), MAGIC.len() + 5, whole.len() - 1] {
            std::fs::write(&path, &whole[..cut]).unwrap();
            let c = Journal::continue_or_restart(&path, &header()).unwrap();
            assert!(c.results.is_empty(), "cut at {cut}");
            let mut j = c.journal;
            j.append(&result(4)).unwrap();
            drop(j);
            let (h, all) = read(&path).unwrap();
            assert_eq!((h, all), (header(), vec![result(4)]), "cut at {cut}");
        }
        // not a journal at all: refused, not overwritten
        std::fs::write(&path, b"something else entirely").unwrap();
        let err = Journal::continue_or_restart(&path, &header()).unwrap_err().to_string();
        assert!(err.contains("not a quakejoint journal"), "{err}");
        // a damaged header with entries after it: refused, not restarted
        let mut bad = whole.clone();
        bad[MAGIC.len() + 9] ^= 1;
        bad.extend(frame(&encode(&result(1))));
        std::fs::write(&path, &bad).unwrap();
        let err = Journal::continue_or_restart(&path, &header()).unwrap_err().to_string();
        assert!(err.contains("header is damaged"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn entries_of_another_journal_format_leave_the_header_to_say_so() {
        let dir = scratch("format");
        let path = dir.join("old.journal");
        // an entry that does not decode as this version's (a header, say)
        let mut bytes = MAGIC.to_vec();
        bytes.extend(frame(&encode(&header())));
        bytes.extend(frame(&encode(&header())));
        std::fs::write(&path, &bytes).unwrap();
        let c = read_contents(&path).unwrap();
        assert!(c.results.is_empty());
        let current = Header { schema: crate::runner::JOURNAL_SCHEMA, ..header() };
        let d = c.header.differences(&current);
        assert!(d.iter().any(|s| s.contains("journal format")), "{d:?}");
        // in this version's format the same entry is refused
        let mut bytes = MAGIC.to_vec();
        bytes.extend(frame(&encode(&current)));
        bytes.extend(frame(&encode(&current)));
        std::fs::write(&path, &bytes).unwrap();
        let err = read_contents(&path).unwrap_err().to_string();
        assert!(err.contains("unreadable job record"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_changed_config_or_record_is_named() {
        let mut other = header();
        other.config_sha256 = "def".into();
        other.records[0].1 = "x".into();
        let d = header().differences(&other);
        assert!(d.iter().any(|s| s.contains("config differs")), "{d:?}");
        assert!(d.iter().any(|s| s.contains("record \"r\" differ")), "{d:?}");
        assert!(header().differences(&header()).is_empty());
    }
}
