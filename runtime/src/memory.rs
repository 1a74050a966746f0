//! Process memory figures for `--timings` and the asset benchmark: the resident set and its
//! peak, read from Linux's /proc (elsewhere they are unknown, and said so).

/// Peak resident memory of this process so far (VmHWM), in bytes.
pub fn peak_resident() -> Option<u64> {
    status_field("VmHWM:")
}

/// Resident memory now (VmRSS), in bytes.
pub fn resident() -> Option<u64> {
    status_field("VmRSS:")
}

/// Start a new peak from the current resident set (Linux: `5` to /proc/self/clear_refs).
pub fn reset_peak() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

fn status_field(name: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(name))?;
    let kib: u64 = line[name.len()..].trim().trim_end_matches("kB").trim().parse().ok()?;
    Some(kib * 1024)
}

/// Bytes as MiB with one decimal, or "unknown".
pub fn mib(bytes: Option<u64>) -> String {
    bytes
        .map(|b| format!("{:.1} MiB", b as f64 / (1 << 20) as f64))
        .unwrap_or_else(|| "unknown".into())
}

#[cfg(test)]
mod tests {
    #[cfg(target_os = "linux")]
    #[test]
    fn peak_is_at_least_the_current_resident_set() {
        let (now, peak) = (super::resident().unwrap(), super::peak_resident().unwrap());
        assert!(now > 0 && peak >= now, "{now} {peak}");
    }
}
