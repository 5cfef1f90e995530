//! Progress of a sweep on stderr: bars on a terminal, plain timestamped
//! lines elsewhere (a SLURM log, `nohup`), or nothing.
//!
//! The estimate of the time left weighs jobs by the cost model
//! ([`crate::plan::cost_seconds`]): the work done so far, divided by the
//! time it took, gives the rate at which the rest will go.

use std::time::{Duration, Instant};

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

/// How a sweep shows its progress.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Progress {
    /// Bars redrawn in place (for a terminal).
    Bars,
    /// A plain line at this interval, and at the start and end (for logs).
    Lines {
        /// Time between lines.
        every: Duration,
    },
    /// Nothing.
    Quiet,
}

/// `1h02m`, `3m05s`, `12s`.
pub fn format_duration(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    match s {
        0..60 => format!("{s}s"),
        60..3600 => format!("{}m{:02}s", s / 60, s % 60),
        _ => format!("{}h{:02}m", s / 3600, s % 3600 / 60),
    }
}

/// Counts and draws the progress of one sweep run.
pub(crate) struct Reporter {
    mode: Progress,
    label: String,
    multi: MultiProgress,
    overall: ProgressBar,
    start: Instant,
    last_line: Instant,
    scope: usize,
    done: usize,
    failed: usize,
    flagged: usize,
    threads: usize,
    cost_left: f64,
    cost_done: f64,
}

impl Reporter {
    /// `label` names the output; `scope` jobs of which `done` are finished
    /// already (`failed` of them failed); the jobs to run cost `cost_left`
    /// (model seconds).
    pub(crate) fn new(
        mode: Progress,
        label: String,
        (scope, done, failed, flagged): (usize, usize, usize, usize),
        cost_left: f64,
        threads: usize,
    ) -> Self {
        let multi = MultiProgress::with_draw_target(match mode {
            Progress::Bars => ProgressDrawTarget::stderr(),
            _ => ProgressDrawTarget::hidden(),
        });
        let overall = multi.add(ProgressBar::new(scope as u64));
        overall.set_style(
            ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} jobs, {elapsed} elapsed, {msg}")
                .expect("template")
                .progress_chars("=> "),
        );
        overall.set_prefix("sweep");
        overall.set_position(done as u64);
        let now = Instant::now();
        let r = Self {
            mode,
            label,
            multi,
            overall,
            start: now,
            last_line: now,
            scope,
            done,
            failed,
            flagged,
            threads,
            cost_left,
            cost_done: 0.0,
        };
        r.overall.set_message(r.eta());
        if mode == Progress::Bars {
            // the elapsed time and the spinners move between finished jobs
            r.overall.enable_steady_tick(Duration::from_millis(500));
        }
        if matches!(mode, Progress::Lines { .. }) {
            eprintln!("{}", r.line("started"));
        }
        r
    }

    /// A spinner line for worker `w` (hidden unless bars are drawn).
    pub(crate) fn worker(&self, w: usize) -> ProgressBar {
        let pb = self.multi.add(ProgressBar::new_spinner());
        pb.set_style(ProgressStyle::with_template("  worker {prefix}: {msg}").expect("template"));
        pb.set_prefix(w.to_string());
        pb.set_message("idle");
        pb
    }

    /// Prints a message above the bars, or as a line of its own.
    pub(crate) fn notice(&self, message: &str) {
        match self.mode {
            Progress::Bars => self.multi.suspend(|| eprintln!("warning: {message}")),
            _ => eprintln!("warning: {message}"),
        }
    }

    /// One job finished (`failed` if it did not end OK, `flagged` if it
    /// left the model's validity) that cost `cost`.
    pub(crate) fn job_done(&mut self, failed: bool, flagged: bool, cost: f64) {
        self.done += 1;
        self.failed += usize::from(failed);
        self.flagged += usize::from(flagged);
        self.cost_done += cost;
        self.overall.inc(1);
        self.overall.set_message(self.eta());
        self.tick();
    }

    /// Prints a line if the interval has passed (lines mode).
    pub(crate) fn tick(&mut self) {
        if let Progress::Lines { every } = self.mode {
            if self.last_line.elapsed() >= every {
                self.last_line = Instant::now();
                eprintln!("{}", self.line("running"));
            }
        }
    }

    /// Time until the next line is due (for the writer's wait).
    pub(crate) fn until_next_line(&self) -> Option<Duration> {
        match self.mode {
            Progress::Lines { every } => Some(every.saturating_sub(self.last_line.elapsed())),
            _ => None,
        }
    }

    /// Clears the bars and prints the last line (lines mode).
    pub(crate) fn finish(&self, state: &str) {
        self.overall.finish_and_clear();
        if matches!(self.mode, Progress::Lines { .. }) {
            eprintln!("{}", self.line(state));
        }
    }

    fn eta(&self) -> String {
        let left = (self.cost_left - self.cost_done).max(0.0);
        if self.done >= self.scope {
            return "done".into();
        }
        let elapsed = self.start.elapsed().as_secs_f64();
        if self.cost_done > 0.0 && elapsed > 0.0 {
            format!("ETA {}", format_duration(left * elapsed / self.cost_done))
        } else {
            format!("ETA ~{} (estimate)", format_duration(left / self.threads.max(1) as f64))
        }
    }

    fn line(&self, state: &str) -> String {
        let eta = if state == "running" || state == "started" { self.eta() } else { "stopped".into() };
        let eta = if self.done >= self.scope { "done".into() } else { eta };
        format!(
            "[{}] sweep {} {state}: {} of {} jobs done ({} failed, {} flagged), {} elapsed, {}",
            quakejoint_io::time::utc_now(),
            self.label,
            self.done,
            self.scope,
            self.failed,
            self.flagged,
            format_duration(self.start.elapsed().as_secs_f64()),
            eta
        )
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn durations_read_well() {
        assert_eq!(super::format_duration(0.4), "0s");
        assert_eq!(super::format_duration(59.0), "59s");
        assert_eq!(super::format_duration(185.0), "3m05s");
        assert_eq!(super::format_duration(3720.0), "1h02m");
    }
}
