//! The process's memory: its peak as the operating system reports it, and where a budget
//! comes from.

/// Peak resident set size in bytes (`VmHWM` of /proc/self/status), if the system reports it.
pub fn peak_resident_bytes() -> Option<u64> {
    status_bytes("VmHWM:")
}

/// Resident set size now, in bytes (`VmRSS` of /proc/self/status), if the system reports it.
pub fn resident_bytes() -> Option<u64> {
    status_bytes("VmRSS:")
}

/// The figure of the /proc/self/status line starting with `key`, in bytes (it is in KiB).
fn status_bytes(key: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(key))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// A memory budget and where it comes from, for messages.
#[derive(Debug, Clone)]
pub struct Budget {
    /// Bytes the work may take.
    pub bytes: u64,
    /// Where the figure comes from: "--max-memory", or the limit the default is half of.
    pub origin: String,
}

/// The budget `--max-memory` gives, or the default one where it gives none.
pub fn budget(max_memory: Option<u64>) -> Budget {
    match max_memory {
        Some(bytes) => Budget { bytes, origin: "--max-memory".into() },
        None => {
            let default = relief_io::default_memory_budget();
            Budget {
                bytes: default.bytes,
                origin: format!("{}; raise it with --max-memory", default.source),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_budget_says_which_limit_applied() {
        let default = budget(None);
        assert_eq!(default.bytes, relief_io::default_memory_budget().bytes);
        assert!(default.origin.contains(&relief_io::default_memory_budget().source));
        assert!(default.origin.ends_with("raise it with --max-memory"), "{}", default.origin);
        assert_eq!(budget(Some(5)).origin, "--max-memory");
    }
}
