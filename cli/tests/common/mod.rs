//! What the CLI's integration tests share: running the binary this package builds.
// Each test file is its own crate and uses only some of these.
#![allow(dead_code)]

use std::process::{Command, Output};

/// `perifrac ARGS --quiet`, whatever its exit code.
pub fn perifrac(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_perifrac"))
        .args(args)
        .arg("--quiet")
        .output()
        .expect("the binary runs")
}

/// `perifrac ARGS --quiet`, which must succeed (its stderr in the failure).
pub fn perifrac_ok(args: &[&str]) -> Output {
    let out = perifrac(args);
    assert!(
        out.status.success(),
        "perifrac {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The exit code and stderr of a run.
pub fn outcome(out: &Output) -> (Option<i32>, String) {
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The peak resident memory (MiB) of `program ARGS`, read with `wait4` for that child
/// alone; the maximum covers the children it waited for (the ranks of `mpirun`).
// The child is reaped by wait4, which gives its own rusage (std's wait does not).
#[allow(clippy::zombie_processes)]
pub fn peak_mib(program: &str, args: &[&str]) -> f64 {
    let child = Command::new(program)
        .args(args)
        .spawn()
        .expect("starts the run");
    let mut status = 0;
    // SAFETY: rusage is plain data that wait4 fills for the child it reaps.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let pid = child.id() as libc::pid_t;
    // SAFETY: waits for our own child, which std has not reaped (no wait on it).
    let reaped = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    assert_eq!(reaped, pid, "waits for the run");
    assert!(
        libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0,
        "{program} {args:?} failed: {status}"
    );
    usage.ru_maxrss as f64 / 1024.0
}
