//! The process's memory: its peak as the operating system reports it, and where a budget
//! comes from.

/// Peak resident set size in bytes (`VmHWM` of /proc/self/status), if the system reports it.
pub fn peak_resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// A memory budget and where it comes from, for messages.
#[derive(Debug, Clone)]
pub struct Budget {
    /// Bytes the work may take.
    pub bytes: u64,
    /// Where the figure comes from, e.g. "--max-memory" or "half the machine's memory".
    pub origin: String,
}

/// The budget `--max-memory` gives, or the default one where it gives none.
pub fn budget(max_memory: Option<u64>) -> Budget {
    match max_memory {
        Some(bytes) => Budget { bytes, origin: "--max-memory".into() },
        None => Budget {
            bytes: relief_io::default_memory_limit(),
            origin: "half the machine's memory; raise it with --max-memory".into(),
        },
    }
}
