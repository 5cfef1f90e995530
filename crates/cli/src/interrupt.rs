//! What a long command does besides its work: stop cleanly on SIGINT and
//! SIGTERM (sweeps), and show a progress bar on a terminal (`simulate`).

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use anyhow::{Context, Result};

/// Exit code of a sweep stopped by a signal: 128 + the signal's number.
pub fn interrupted_code(signals: &Signals) -> u8 {
    if signals.term.load(Ordering::Relaxed) {
        143
    } else {
        130
    }
}

/// SIGINT and SIGTERM (what Ctrl-C, `scancel` and a SLURM time limit send)
/// ask the sweep to stop; a second signal ends the process at once (the
/// journal is crash-safe either way).
pub struct Signals {
    /// Set by either signal: the sweep stops.
    pub stop: Arc<AtomicBool>,
    /// Set by SIGTERM.
    term: Arc<AtomicBool>,
}

impl Signals {
    /// Installs the handlers.
    pub fn install() -> Result<Self> {
        use signal_hook::consts::{SIGINT, SIGTERM};
        let stop = Arc::new(AtomicBool::new(false));
        let term = Arc::new(AtomicBool::new(false));
        for sig in [SIGINT, SIGTERM] {
            // the second signal: exit at once with 128 + the signal
            signal_hook::flag::register_conditional_shutdown(sig, 128 + sig, stop.clone())
                .context("installing the signal handlers")?;
            signal_hook::flag::register(sig, stop.clone()).context("installing the signal handlers")?;
        }
        signal_hook::flag::register(SIGTERM, term.clone()).context("installing the signal handlers")?;
        Ok(Self { stop, term })
    }
}

/// A progress bar of a single run on a terminal, drawn once the run has
/// taken more than a second (shorter runs print nothing extra), or
/// `QUAKEJOINT_BAR_AFTER` seconds (the tests set 0, so that the bar shows
/// however fast the machine).
pub struct TerminalProgress {
    /// The bar (hidden until the run has taken a second).
    pub bar: indicatif::ProgressBar,
    start: std::time::Instant,
    after: f64,
}

impl TerminalProgress {
    /// `None` when stderr is not a terminal.
    pub fn new(duration: f64) -> Option<Arc<Self>> {
        if !std::io::stderr().is_terminal() {
            return None;
        }
        let bar = indicatif::ProgressBar::with_draw_target(
            Some((duration * 1000.0).max(1.0) as u64),
            indicatif::ProgressDrawTarget::hidden(),
        );
        bar.set_style(
            indicatif::ProgressStyle::with_template("simulate [{bar:30}] t = {msg} s, {elapsed} elapsed, ETA {eta}")
                .expect("template")
                .progress_chars("=> "),
        );
        let after = std::env::var("QUAKEJOINT_BAR_AFTER").ok().and_then(|s| s.trim().parse().ok()).unwrap_or(1.0);
        Some(Arc::new(Self { bar, start: std::time::Instant::now(), after }))
    }

    /// The run's progress callback, which draws the bar.
    pub fn callback(self: &Arc<Self>) -> quakejoint_model::run::ProgressFn {
        let me = Arc::clone(self);
        Arc::new(move |t| {
            if me.bar.is_hidden() && me.start.elapsed().as_secs_f64() >= me.after {
                me.bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
            }
            me.bar.set_message(format!("{t:.1}"));
            me.bar.set_position((t * 1000.0) as u64);
        })
    }
}
