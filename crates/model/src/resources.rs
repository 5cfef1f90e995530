//! What a process costs the machine, for reports and cluster job requests.

/// Peak resident memory of this process so far [MB], from Linux's `VmHWM`
/// (`None` where `/proc` is not available).
pub fn peak_memory_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
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
}
