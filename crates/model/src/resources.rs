//! What a process costs the machine, for reports and cluster job requests.

/// Peak resident memory of this process so far \[MB\], from Linux's `VmHWM`
/// (`None` where `/proc` is not available).
pub fn peak_memory_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// CPU time the calling thread has used so far \[s\], from Linux's
/// `/proc/thread-self/schedstat` (nanoseconds on the CPU; `None` where it is
/// not available). A sweep's job runs on one worker thread, so the
/// difference across a run is that run's CPU time, whatever else the
/// process does meanwhile. The kernel updates it at context switches and
/// scheduler ticks (a few milliseconds), which bounds its resolution.
pub fn thread_cpu_time_s() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let fields: Vec<f64> = stat.split_whitespace().map(|f| f.parse().ok()).collect::<Option<_>>()?;
    // kernels without scheduler statistics report zeros in every field (a
    // thread just started may have 0 ns on the CPU, but not 0 time slices)
    (fields.len() >= 3 && fields[..3].iter().any(|&f| f > 0.0)).then(|| fields[0] * 1e-9)
}

/// Measures the calling thread's CPU time from its creation
/// ([`thread_cpu_time_s`]; NaN where it is not available).
#[derive(Debug, Clone, Copy)]
pub struct CpuClock(Option<f64>);

impl CpuClock {
    /// Starts the clock.
    pub fn start() -> Self {
        Self(thread_cpu_time_s())
    }

    /// CPU seconds used by this thread since [`CpuClock::start`] (NaN if
    /// unknown).
    pub fn elapsed_s(&self) -> f64 {
        match (self.0, thread_cpu_time_s()) {
            (Some(a), Some(b)) => b - a,
            _ => f64::NAN,
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn peak_memory_is_positive_on_linux() {
        if cfg!(target_os = "linux") {
            let mb = super::peak_memory_mb().expect("VmHWM");
            assert!(mb > 0.1 && mb < 1.0e6, "{mb}");
        }
    }

    #[test]
    fn thread_cpu_time_counts_work_not_sleep() {
        if !cfg!(target_os = "linux") {
            return;
        }
        let clock = super::CpuClock::start();
        std::thread::sleep(std::time::Duration::from_millis(200));
        let slept = clock.elapsed_s();
        let mut x = 0.0f64;
        let wall = std::time::Instant::now();
        for _ in 0..200_000_000u64 {
            x = std::hint::black_box(x + 1.0);
        }
        let (worked, elapsed) = (clock.elapsed_s() - slept, wall.elapsed().as_secs_f64());
        assert!(slept < 0.05, "sleeping used {slept} s of CPU");
        // CPU time can only lag the wall clock (another process may hold the core)
        assert!(worked > 0.02 && worked <= elapsed + 0.01, "{worked} s of CPU in {elapsed} s")
    }
}
