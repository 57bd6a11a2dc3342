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
