//! This process's CPU time and resident memory, read from `/proc/self` (Linux), for the
//! interleaved examples that measure each side in its own process: CPU time beside wall time on a
//! shared machine, and the growth of the peak resident set over one piece of work.

use std::time::Duration;

/// This process's user + system CPU time (`/proc/self/stat` fields 14 and 15, in clock ticks of
/// 1/100 s; `None` off Linux).
///
/// ```
/// let t = rappel_benches::proc_stats::cpu_time();
/// assert!(cfg!(not(target_os = "linux")) || t.is_some());
/// ```
pub fn cpu_time() -> Option<Duration> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The command name (field 2) is parenthesised and may hold spaces: count after its `)`.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: u64 = fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
    Some(Duration::from_millis(ticks * 10))
}

/// A field of `/proc/self/status` in kB (`VmRSS`, `VmHWM`; `None` off Linux).
///
/// ```
/// let rss = rappel_benches::proc_stats::status_kb("VmRSS");
/// assert!(cfg!(not(target_os = "linux")) || rss.is_some_and(|kb| kb > 0));
/// ```
pub fn status_kb(field: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(field))?;
    line[field.len()..]
        .trim_start_matches(':')
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// Resets the peak resident set to the current one and returns the current one, kB (`None` when
/// the kernel does not allow it).
pub fn reset_peak() -> Option<u64> {
    std::fs::write("/proc/self/clear_refs", "5").ok()?;
    status_kb("VmRSS")
}

/// Growth of the peak resident set since `before` (from [`reset_peak`]), MB.
///
/// ```
/// use rappel_benches::proc_stats::{peak_growth_mb, reset_peak};
/// let before = reset_peak();
/// let v = vec![1u8; 64 << 20];
/// std::hint::black_box(&v);
/// if let Some(mb) = peak_growth_mb(before) {
///     assert!(mb >= 60.0, "{mb}");
/// }
/// ```
pub fn peak_growth_mb(before: Option<u64>) -> Option<f64> {
    let (before, peak) = (before?, status_kb("VmHWM")?);
    Some(peak.saturating_sub(before) as f64 / 1024.0)
}
