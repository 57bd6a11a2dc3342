//! The memory a run may use: the lowest of what the machine has available
//! (`MemAvailable`), the process's address-space limit (`ulimit -v`, `RLIMIT_AS`) and
//! its cgroup's limit less what the cgroup already uses (v2 `memory.max`, v1
//! `memory.limit_in_bytes`, at every level up to the root). `run`, `demo` and `check`
//! refuse a scene whose estimate is above it (exit code 2).

use std::path::Path;

use perifrac_sim::memory::{MemoryEstimate, MemoryLimit};

use crate::commands::Failure;

/// The lowest memory ceiling that applies to this process, if any is known.
pub fn memory_limit() -> Option<MemoryLimit> {
    let cgroups = std::fs::read_to_string("/proc/self/cgroup").unwrap_or_default();
    [
        available_memory(),
        address_space_limit(),
        cgroup_limit(&cgroups, Path::new("/sys/fs/cgroup")),
    ]
    .into_iter()
    .flatten()
    .min_by_key(|limit| limit.bytes)
}

/// Refuses an estimate above [`memory_limit`].
pub fn check_memory(estimate: &MemoryEstimate) -> Result<(), Failure> {
    match memory_limit() {
        Some(limit) => Ok(estimate.refuse_above(&limit)?),
        None => Ok(()),
    }
}

/// Memory the system can still give (`MemAvailable` of /proc/meminfo).
fn available_memory() -> Option<MemoryLimit> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(MemoryLimit {
        bytes: kb * 1024,
        source: "are available (MemAvailable in /proc/meminfo)".into(),
    })
}

/// The soft `RLIMIT_AS` of this process (`ulimit -v`), unless unlimited.
fn address_space_limit() -> Option<MemoryLimit> {
    let mut limit = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: getrlimit writes one `rlimit` through a pointer to a live local.
    let ok = unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut limit) } == 0;
    (ok && limit.rlim_cur != libc::RLIM_INFINITY).then(|| MemoryLimit {
        bytes: limit.rlim_cur,
        source: "is all this process may use (its address-space limit, ulimit -v)".into(),
    })
}

/// Values at or above this are cgroup v1's "no limit" (a page-rounded `i64::MAX`).
const CGROUP_V1_UNLIMITED: u64 = 1 << 62;

/// The room left under the memory limits of the cgroup that `proc_self_cgroup` (the
/// text of /proc/self/cgroup) names, under the cgroup file systems mounted at `root`:
/// for each level from the process's cgroup up to the root that has a limit, the limit
/// less its usage; the smallest of them.
fn cgroup_limit(proc_self_cgroup: &str, root: &Path) -> Option<MemoryLimit> {
    let mut best: Option<MemoryLimit> = None;
    for line in proc_self_cgroup.lines() {
        let mut fields = line.splitn(3, ':');
        let (Some(id), Some(controllers), Some(path)) =
            (fields.next(), fields.next(), fields.next())
        else {
            continue;
        };
        // v2: "0::/path" under root (or root/unified on hybrid systems); v1: the
        // "memory" controller under root/memory.
        let (mounts, limit_file, usage_file): (&[&str], _, _) =
            if id == "0" && controllers.is_empty() {
                (&["", "unified"], "memory.max", "memory.current")
            } else if controllers.split(',').any(|c| c == "memory") {
                (
                    &["memory"],
                    "memory.limit_in_bytes",
                    "memory.usage_in_bytes",
                )
            } else {
                continue;
            };
        for mount in mounts {
            let mut dir = root.join(mount).join(path.trim_start_matches('/'));
            loop {
                let read = |file: &str| -> Option<u64> {
                    std::fs::read_to_string(dir.join(file))
                        .ok()?
                        .trim()
                        .parse()
                        .ok()
                };
                if let Some(limit) = read(limit_file).filter(|&b| b < CGROUP_V1_UNLIMITED) {
                    let room = limit.saturating_sub(read(usage_file).unwrap_or(0));
                    if best.as_ref().is_none_or(|b| room < b.bytes) {
                        best = Some(MemoryLimit {
                            bytes: room,
                            source: format!(
                                "are left under this process's cgroup limit ({} of {:.1} GiB)",
                                dir.join(limit_file).display(),
                                limit as f64 / (1u64 << 30) as f64
                            ),
                        });
                    }
                }
                if dir == root.join(mount) || !dir.pop() {
                    break;
                }
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(root: &Path, file: &str, text: &str) {
        let path = root.join(file);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }

    #[test]
    fn a_cgroup_v2_limit_is_found_at_its_level_or_a_parent() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path();
        write(root, "job/memory.max", "max\n");
        write(root, "job/memory.current", "100\n");
        assert_eq!(cgroup_limit("0::/job\n", root), None);
        write(root, "memory.max", "1000\n");
        write(root, "memory.current", "400\n");
        assert_eq!(cgroup_limit("0::/job\n", root).map(|l| l.bytes), Some(600));
        write(root, "job/memory.max", "300\n");
        let limit = cgroup_limit("0::/job\n", root).unwrap();
        assert_eq!(limit.bytes, 200);
        assert!(limit.source.contains("job/memory.max"), "{}", limit.source);
    }

    #[test]
    fn a_cgroup_v1_memory_limit_is_found_and_no_limit_is_none() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path();
        let cgroups = "9:name=systemd:/\n4:memory:/api/x\n1:cpu:/\n0::/\n";
        write(
            root,
            "memory/api/x/memory.limit_in_bytes",
            "9223372036854771712\n",
        );
        write(
            root,
            "memory/memory.limit_in_bytes",
            "9223372036854771712\n",
        );
        assert_eq!(cgroup_limit(cgroups, root), None);
        write(root, "memory/api/x/memory.limit_in_bytes", "2048\n");
        write(root, "memory/api/x/memory.usage_in_bytes", "48\n");
        assert_eq!(cgroup_limit(cgroups, root).map(|l| l.bytes), Some(2000));
    }
}
