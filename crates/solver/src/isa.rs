//! Which instructions the hot kernels are compiled for, chosen at run time.
//!
//! The portable build targets the x86-64 baseline (SSE2, two-wide vectors).
//! A binary built for AVX2 (four-wide) stops with an illegal instruction on
//! a processor without it. So the parts where the time goes (the residual,
//! the block factorisation and solves, the local friction solve, the
//! simplified Newton iteration, the error estimate, the accepted step's
//! energy quadrature and projection, the peak forces) are compiled twice,
//! once for the baseline and once with AVX2 enabled, and `run` picks one
//! per call from what the processor reports. On the reference run the AVX2
//! version is about 7 % faster (`QUAKEJOINT_SIMD` below;
//! `docs/performance.md`, "Hot loops on slices").
//!
//! Only AVX2 is enabled, not FMA: Rust never contracts `a * b + c` into a
//! fused multiply-add by itself, and vectorised loops keep the order of
//! their sums, so both versions compute the same numbers bit for bit and a
//! sweep sharded over nodes with and without AVX2 still gives bit-identical
//! results (checked by `crates/cli/tests/simd_paths.rs` on the test build,
//! and on the release build by the reference run's `simulate --json`,
//! `docs/performance.md`).
//!
//! `QUAKEJOINT_SIMD=portable` in the environment forces the baseline
//! version (read once per process), for that comparison and for timing the
//! difference in one binary; unset, or any other value, lets the processor
//! decide.

use std::sync::OnceLock;

/// Whether the AVX2 versions of the kernels are used in this process.
pub fn avx2_in_use() -> bool {
    static USE: OnceLock<bool> = OnceLock::new();
    *USE.get_or_init(|| {
        let forced_portable = std::env::var("QUAKEJOINT_SIMD").is_ok_and(|v| v.trim() == "portable");
        !forced_portable && detected()
    })
}

#[cfg(target_arch = "x86_64")]
fn detected() -> bool {
    std::arch::is_x86_feature_detected!("avx2")
}

#[cfg(not(target_arch = "x86_64"))]
fn detected() -> bool {
    false
}

/// Runs `f`, compiled with AVX2 if the processor has it (see the module
/// documentation). `f` should be a closure that calls an
/// `#[inline(always)]` function, so that its whole body is compiled into
/// both versions.
#[inline(always)]
pub(crate) fn run<R>(f: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    if avx2_in_use() {
        // SAFETY: the processor reports AVX2 (`avx2_in_use`).
        return unsafe { with_avx2(f) };
    }
    f()
}

/// `f()` compiled with AVX2 enabled.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn with_avx2<R>(f: impl FnOnce() -> R) -> R {
    f()
}
