//! The writer thread of a running sweep: it journals each result as it
//! arrives (fsync per job), keeps the arrays, checkpoints the HDF5 file
//! and reports progress.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, RecvTimeoutError};

use crate::error::SweepError;
use crate::journal::Journal;
use crate::progress::Reporter;
use crate::results::{status, JobResult};
use crate::sweep_h5::{write_sweep, SweepFile};

/// The writer thread's state: it journals each result, keeps the arrays,
/// checkpoints the HDF5 file and reports progress; a write error stops the
/// workers (the journal keeps what was finished).
pub(super) struct Writer {
    pub(super) journal: Journal,
    pub(super) file: SweepFile,
    pub(super) output: PathBuf,
    pub(super) checkpoint: Duration,
    /// The output on disk is behind the arrays.
    pub(super) dirty: bool,
    pub(super) reporter: Reporter,
    /// Cost-model estimate of every job [s].
    pub(super) costs: Vec<f64>,
}

impl Writer {
    pub(super) fn run(mut self, rx: Receiver<JobResult>, stop: &AtomicBool) -> Result<SweepFile, SweepError> {
        let result = self.receive(&rx, stop);
        if result.is_err() {
            stop.store(true, Ordering::Relaxed);
            // let the workers finish their current send
            while rx.recv().is_ok() {}
        }
        let state = match &result {
            Err(_) => "stopped by an error",
            Ok(()) if stop.load(Ordering::Relaxed) => "interrupted",
            Ok(()) => "finished",
        };
        self.reporter.finish(state);
        result.map(|()| self.file)
    }

    fn receive(&mut self, rx: &Receiver<JobResult>, stop: &AtomicBool) -> Result<(), SweepError> {
        let mut last = Instant::now();
        loop {
            let wait = self.reporter.until_next_line().unwrap_or(Duration::from_secs(3600));
            match rx.recv_timeout(wait) {
                Ok(result) => {
                    self.journal.append(&result)?;
                    let failed = result.status != status::OK;
                    let flagged = quakejoint_model::validity::Flags(result.validity).is_flagged();
                    let cost = self.costs.get(result.job as usize).copied().unwrap_or(0.0);
                    self.file.results.insert(result);
                    self.dirty = true;
                    self.reporter.job_done(failed, flagged, cost);
                    if last.elapsed() >= self.checkpoint && !stop.load(Ordering::Relaxed) {
                        write_sweep(&self.output, &self.file)?;
                        last = Instant::now();
                        self.dirty = false;
                    }
                }
                Err(RecvTimeoutError::Timeout) => self.reporter.tick(),
                Err(RecvTimeoutError::Disconnected) => break,
            }
        }
        if self.dirty || !self.output.exists() {
            write_sweep(&self.output, &self.file)?;
        }
        Ok(())
    }
}
