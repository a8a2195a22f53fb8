//! This process's peak resident memory, for tests that bound what a piece of code keeps while it
//! reads something endless or huge (Linux: `/proc/self`). Such a test is best alone in its file:
//! another test in the same process would be measured with it.

/// This process's peak resident memory since [`reset_peak`], kB (`VmHWM`).
///
/// # Panics
/// Where `/proc/self/status` is missing or has no `VmHWM` line (not Linux).
#[must_use]
pub fn peak_kb() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").expect("/proc/self/status");
    let line = status.lines().find(|l| l.starts_with("VmHWM:")).expect("a VmHWM line");
    line.split_whitespace().nth(1).and_then(|kb| kb.parse().ok()).expect("kB")
}

/// Starts this process's peak resident memory again from what it holds now (Linux ≥ 4.0), and
/// answers that.
///
/// # Panics
/// Where `/proc/self/clear_refs` does not take `5` (not Linux, or older than 4.0).
#[must_use]
pub fn reset_peak() -> u64 {
    std::fs::write("/proc/self/clear_refs", "5").expect("/proc/self/clear_refs takes 5");
    peak_kb()
}
