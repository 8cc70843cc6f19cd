//! The default memory budget: half of what this process may use, the smaller of the machine's
//! physical memory (`/proc/meminfo`) and its cgroup's memory limit (containers), with words
//! saying which one applied.
//!
//! cgroup v2: the `0::/path` line of `/proc/self/cgroup` names the process's group under
//! `/sys/fs/cgroup`; every `memory.max` from that group up to the root counts ("max" means no
//! limit), and the smallest applies. cgroup v1: the `memory` controller's line names the group
//! under `/sys/fs/cgroup/memory`; its `memory.limit_in_bytes` and those of its ancestors, down to
//! the mount's own, count (values of 2^62 bytes and more, such as 9223372036854771712, mean no
//! limit). Files that are absent, unreadable or not numbers are ignored.

use std::path::{Path, PathBuf};

/// The budget where the machine's memory cannot be read: 4 GiB.
const FALLBACK_BYTES: u64 = 4 << 30;

/// cgroup v1 writes "no limit" as a huge number (`PAGE_COUNTER_MAX` pages); any limit of this
/// many bytes or more is taken for none.
const NO_LIMIT_FROM: u64 = 1 << 62;

/// How much memory a raster may take by default, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MemoryBudget {
    /// The budget in bytes.
    pub bytes: u64,
    /// Which limit the budget is half of, in words that fit inside an error message, e.g.
    /// "half the machine's memory (MemTotal 23.5 GiB)" or "half the cgroup memory limit
    /// (2.0 GiB, /sys/fs/cgroup/memory.max)".
    pub source: String,
}

/// Half of the memory this process may use: the smaller of the machine's physical memory and
/// its cgroup's memory limit; 4 GiB where neither can be read.
///
/// ```
/// let budget = relief_io::default_memory_budget();
/// assert!(budget.bytes > 0);
/// assert!(budget.source.starts_with("half the") || budget.source.starts_with("4 GiB"));
/// ```
pub fn default_memory_budget() -> MemoryBudget {
    MemoryBudget::under_root(Path::new("/"))
}

/// The bytes of [`default_memory_budget`]: half of the smaller of the machine's memory and the
/// cgroup memory limit, or 4 GiB if unknown.
pub fn default_memory_limit() -> u64 {
    default_memory_budget().bytes
}

/// A limit found in a file: its bytes and the file (shown as an absolute path).
#[derive(Debug, Clone, PartialEq, Eq)]
struct Limit {
    bytes: u64,
    file: PathBuf,
}

impl MemoryBudget {
    /// The budget as read from `root/proc` and `root/sys/fs/cgroup` (`root` is `/` but in
    /// tests, which build fake trees).
    pub(crate) fn under_root(root: &Path) -> Self {
        let physical = mem_total(root);
        let cgroup = cgroup_limit(root);
        match (physical, cgroup) {
            (Some(total), Some(limit)) if limit.bytes < total => cgroup_budget(limit),
            (None, Some(limit)) => cgroup_budget(limit),
            (Some(total), _) => MemoryBudget {
                bytes: total / 2,
                source: format!("half the machine's memory (MemTotal {})", human(total)),
            },
            (None, None) => MemoryBudget {
                bytes: FALLBACK_BYTES,
                source: "4 GiB, as the machine's memory could not be read from /proc/meminfo"
                    .to_owned(),
            },
        }
    }
}

fn cgroup_budget(limit: Limit) -> MemoryBudget {
    MemoryBudget {
        bytes: limit.bytes / 2,
        source: format!(
            "half the cgroup memory limit ({}, {})",
            human(limit.bytes),
            limit.file.display()
        ),
    }
}

/// `bytes` as GiB with one decimal, or whole MiB below 1 GiB.
fn human(bytes: u64) -> String {
    if bytes >= 1 << 30 {
        format!("{:.1} GiB", bytes as f64 / (1u64 << 30) as f64)
    } else {
        format!("{} MiB", bytes >> 20)
    }
}

/// `MemTotal` of `root/proc/meminfo`, in bytes.
fn mem_total(root: &Path) -> Option<u64> {
    let text = std::fs::read_to_string(root.join("proc/meminfo")).ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib = line.split_whitespace().nth(1)?.parse::<u64>().ok()?;
    kib.checked_mul(1024).filter(|&b| b > 0)
}

/// The smallest memory limit of the process's cgroups, v2 and v1, if any is set.
fn cgroup_limit(root: &Path) -> Option<Limit> {
    let text = std::fs::read_to_string(root.join("proc/self/cgroup")).ok()?;
    let mut found = Vec::new();
    for line in text.lines() {
        // hierarchy-ID:controller-list:cgroup-path; the path may itself hold colons.
        let mut fields = line.splitn(3, ':');
        let (Some(id), Some(controllers), Some(path)) =
            (fields.next(), fields.next(), fields.next())
        else {
            continue;
        };
        if id == "0" && controllers.is_empty() {
            found.extend(smallest_up(root, "sys/fs/cgroup", path, "memory.max"));
        } else if controllers.split(',').any(|c| c == "memory") {
            found.extend(smallest_up(root, "sys/fs/cgroup/memory", path, "memory.limit_in_bytes"));
        }
    }
    found.into_iter().min_by_key(|l| l.bytes)
}

/// The smallest limit in the files `file` of the group `group` under `root/mount` and of each of
/// its ancestors up to the mount itself.
fn smallest_up(root: &Path, mount: &str, group: &str, file: &str) -> Option<Limit> {
    let mut relative = PathBuf::from(mount);
    let mut dirs = vec![relative.clone()];
    for part in group.split('/').filter(|p| !p.is_empty() && *p != "." && *p != "..") {
        relative.push(part);
        dirs.push(relative.clone());
    }
    dirs.into_iter()
        .filter_map(|dir| {
            let bytes = read_limit(&root.join(&dir).join(file))?;
            Some(Limit { bytes, file: Path::new("/").join(dir).join(file) })
        })
        .min_by_key(|l| l.bytes)
}

/// The limit in a `memory.max` or `memory.limit_in_bytes` file; `None` for "max", a huge value,
/// zero, or a file that cannot be read or parsed.
fn read_limit(path: &Path) -> Option<u64> {
    let text = std::fs::read_to_string(path).ok()?;
    let bytes = text.trim().parse::<u64>().ok()?;
    (bytes > 0 && bytes < NO_LIMIT_FROM).then_some(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_dir::TestDir;

    const GIB: u64 = 1 << 30;

    /// Writes `text` to `rel` under `root`, creating its folders.
    fn put(root: &Path, rel: &str, text: &str) {
        let path = root.join(rel);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }

    /// A fake root whose machine has `gib` GiB of memory.
    fn machine(name: &str, gib: u64) -> TestDir {
        let dir = TestDir::new(&format!("budget-{name}"));
        let kib = gib * GIB / 1024;
        put(dir.path(), "proc/meminfo", &format!("MemTotal:       {kib} kB\nMemFree: 12 kB\n"));
        dir
    }

    #[test]
    fn without_a_cgroup_the_budget_is_half_the_machine() {
        let dir = machine("none", 24);
        let budget = MemoryBudget::under_root(dir.path());
        assert_eq!(budget.bytes, 12 * GIB);
        assert_eq!(budget.source, "half the machine's memory (MemTotal 24.0 GiB)");
    }

    #[test]
    fn a_cgroup_v2_limit_below_the_machine_applies() {
        let dir = machine("v2", 24);
        put(dir.path(), "proc/self/cgroup", "0::/\n");
        put(dir.path(), "sys/fs/cgroup/memory.max", &format!("{}\n", 2 * GIB));
        let budget = MemoryBudget::under_root(dir.path());
        assert_eq!(budget.bytes, GIB);
        assert_eq!(
            budget.source,
            "half the cgroup memory limit (2.0 GiB, /sys/fs/cgroup/memory.max)"
        );
    }

    #[test]
    fn a_cgroup_v2_max_is_no_limit() {
        let dir = machine("v2-max", 8);
        put(dir.path(), "proc/self/cgroup", "0::/user.slice\n");
        put(dir.path(), "sys/fs/cgroup/user.slice/memory.max", "max\n");
        let budget = MemoryBudget::under_root(dir.path());
        assert_eq!(budget.bytes, 4 * GIB);
        assert!(budget.source.starts_with("half the machine's memory"), "{}", budget.source);
    }

    #[test]
    fn nested_cgroup_v2_paths_take_the_smallest_limit_up_to_the_root() {
        let dir = machine("v2-nested", 64);
        put(dir.path(), "proc/self/cgroup", "0::/system.slice/docker-abc.scope/app\n");
        let base = "sys/fs/cgroup/system.slice";
        put(dir.path(), &format!("{base}/docker-abc.scope/app/memory.max"), "max\n");
        put(dir.path(), &format!("{base}/docker-abc.scope/memory.max"), &format!("{}", 3 * GIB));
        put(dir.path(), &format!("{base}/memory.max"), &format!("{}", 16 * GIB));
        let budget = MemoryBudget::under_root(dir.path());
        assert_eq!(budget.bytes, 3 * GIB / 2);
        assert_eq!(
            budget.source,
            "half the cgroup memory limit (3.0 GiB, \
             /sys/fs/cgroup/system.slice/docker-abc.scope/memory.max)"
        );
        // A group the mount does not show (another namespace) still finds the limits above it.
        put(dir.path(), "proc/self/cgroup", "0::/elsewhere/deep\n");
        put(dir.path(), "sys/fs/cgroup/memory.max", &format!("{}", 512 << 20));
        let budget = MemoryBudget::under_root(dir.path());
        assert_eq!(budget.bytes, 256 << 20);
        assert!(
            budget.source.contains("(512 MiB, /sys/fs/cgroup/memory.max)"),
            "{}",
            budget.source
        );
    }

    #[test]
    fn a_cgroup_v1_limit_applies_and_its_huge_no_limit_value_does_not() {
        let dir = machine("v1", 16);
        put(dir.path(), "proc/self/cgroup", "12:cpu,cpuacct:/docker/x\n4:memory:/docker/x\n");
        put(dir.path(), "sys/fs/cgroup/memory/docker/x/memory.limit_in_bytes", "1073741824\n");
        put(dir.path(), "sys/fs/cgroup/memory/memory.limit_in_bytes", "9223372036854771712\n");
        let budget = MemoryBudget::under_root(dir.path());
        assert_eq!(budget.bytes, GIB / 2);
        assert_eq!(
            budget.source,
            "half the cgroup memory limit (1.0 GiB, \
             /sys/fs/cgroup/memory/docker/x/memory.limit_in_bytes)"
        );
        // The group's own folder is not mounted: the mount's file is the fallback.
        std::fs::remove_dir_all(dir.path().join("sys/fs/cgroup/memory/docker")).unwrap();
        put(dir.path(), "sys/fs/cgroup/memory/memory.limit_in_bytes", "2147483648\n");
        let budget = MemoryBudget::under_root(dir.path());
        assert_eq!(budget.bytes, GIB);
        assert!(budget.source.contains("/sys/fs/cgroup/memory/memory.limit_in_bytes"));
        // No limit at all: the machine's memory.
        put(dir.path(), "sys/fs/cgroup/memory/memory.limit_in_bytes", "9223372036854771712\n");
        assert_eq!(MemoryBudget::under_root(dir.path()).bytes, 8 * GIB);
    }

    #[test]
    fn a_cgroup_limit_above_the_machine_does_not_apply() {
        let dir = machine("above", 4);
        put(dir.path(), "proc/self/cgroup", "0::/\n");
        put(dir.path(), "sys/fs/cgroup/memory.max", &format!("{}", 64 * GIB));
        let budget = MemoryBudget::under_root(dir.path());
        assert_eq!(budget.bytes, 2 * GIB);
        assert!(budget.source.starts_with("half the machine's memory"), "{}", budget.source);
    }

    #[test]
    fn unreadable_or_garbled_files_are_ignored() {
        let dir = machine("unreadable", 8);
        put(dir.path(), "proc/self/cgroup", "garbage\n0::/a\n4:memory:/a\n");
        // A folder where the file should be cannot be read; nor can text that is no number.
        std::fs::create_dir_all(dir.path().join("sys/fs/cgroup/a/memory.max")).unwrap();
        put(dir.path(), "sys/fs/cgroup/memory.max", "lots\n");
        put(dir.path(), "sys/fs/cgroup/memory/a/memory.limit_in_bytes", "0\n");
        let budget = MemoryBudget::under_root(dir.path());
        assert_eq!(budget.bytes, 4 * GIB);
        assert!(budget.source.starts_with("half the machine's memory"), "{}", budget.source);
    }

    #[test]
    fn without_meminfo_the_cgroup_limit_or_4_gib_applies() {
        let dir = TestDir::new("budget-no-meminfo");
        let budget = MemoryBudget::under_root(dir.path());
        assert_eq!(budget.bytes, 4 * GIB);
        assert!(budget.source.contains("/proc/meminfo"), "{}", budget.source);
        put(dir.path(), "proc/self/cgroup", "0::/\n");
        put(dir.path(), "sys/fs/cgroup/memory.max", &format!("{}", 6 * GIB));
        assert_eq!(MemoryBudget::under_root(dir.path()).bytes, 3 * GIB);
    }

    #[test]
    fn the_default_limit_is_the_default_budget() {
        assert_eq!(default_memory_limit(), default_memory_budget().bytes);
        assert!(default_memory_limit() > 0);
    }
}
