//! The CPU time of this process, for benchmark programs that run on a shared machine.

/// CPU seconds all threads of this process have run (from /proc, in nanoseconds; 0 where
/// unavailable): on a loaded machine, work per CPU second times the thread count estimates
/// the rate the threads would reach with the cores to themselves.
pub fn cpu_seconds() -> f64 {
    let tasks = std::fs::read_dir("/proc/self/task").into_iter().flatten().flatten();
    let on_cpu_ns = |task: std::fs::DirEntry| -> Option<u64> {
        let stat = std::fs::read_to_string(task.path().join("schedstat")).ok()?;
        stat.split_whitespace().next()?.parse().ok()
    };
    tasks.filter_map(on_cpu_ns).sum::<u64>() as f64 * 1e-9
}
