//! `perifrac verify OUT`: the cache checked against its manifest
//! ([`perifrac_cache::verify`]), and the same checks as warnings before `render` and
//! `surface` read a cache.

use std::path::Path;

use perifrac_cache::Layout;
use perifrac_cache::manifest::Status;
use perifrac_cache::verify::{Problem, Report, verify};

use crate::commands::{EXIT_FAILED, EXIT_INPUT, Failure};
use crate::signals::EXIT_INTERRUPTED;

/// `perifrac verify OUT`: exit 0 when clean and complete, [`EXIT_INPUT`] (2) when a
/// file is damaged or missing, [`EXIT_FAILED`] (1) when the run failed,
/// [`EXIT_INTERRUPTED`] (3) when it is unfinished (running or interrupted).
pub fn command(out: &Path) -> Result<(), Failure> {
    if !out.is_dir() {
        return Err(Failure::input(anyhow::anyhow!(
            "{}: no such directory (give the output folder of a `perifrac run`)",
            out.display()
        )));
    }
    let report = verify(&Layout::new(out));
    for problem in &report.problems {
        println!("damaged: {problem}");
    }
    let frames = report.manifest.as_ref().map_or(0, |m| m.frames());
    let summary = format!(
        "{}: {} frames, {} files checked against their size and checksum",
        out.display(),
        frames,
        report.checked
    );
    if !report.is_clean() {
        return Err(Failure {
            error: anyhow::anyhow!(
                "{summary}: {} problem{} (listed above); rerun with --force, or with --resume \
                 if only frames after the last checkpoint are hit",
                report.problems.len(),
                if report.problems.len() == 1 { "" } else { "s" }
            ),
            code: EXIT_INPUT,
        });
    }
    let message = report
        .manifest
        .as_ref()
        .map(|m| m.message.clone())
        .unwrap_or_default();
    match report.status() {
        Some(Status::Complete) => {
            println!("{summary}: clean, complete");
            Ok(())
        }
        Some(Status::Failed) => Err(Failure {
            error: anyhow::anyhow!("{summary}: intact, but the run failed: {message}"),
            code: EXIT_FAILED,
        }),
        Some(status) => Err(Failure {
            error: anyhow::anyhow!(
                "{summary}: intact but unfinished ({status}{}); `perifrac run … --resume` \
                 continues it",
                if message.is_empty() {
                    String::new()
                } else {
                    format!(": {message}")
                }
            ),
            code: EXIT_INTERRUPTED,
        }),
        None => Ok(()),
    }
}

/// Prints what `perifrac verify` would flag in the cache at `out`, as warnings, before
/// a stage reads it, and returns the report; a manifest that contradicts itself or the
/// frames ([`Report::is_inconsistent`]) is refused instead (exit code 2): the stage
/// would draw colliders or particles where they were not.
pub fn warn(out: &Path) -> Result<Report, Failure> {
    let report = verify(&Layout::new(out));
    if report.is_inconsistent() {
        let problems: Vec<String> = report
            .problems
            .iter()
            .filter(|p| matches!(p, Problem::Inconsistent { .. }))
            .map(|p| p.to_string())
            .collect();
        return Err(Failure::input(anyhow::anyhow!("{}", problems.join("\n"))));
    }
    for problem in &report.problems {
        eprintln!("warning: {problem}");
    }
    if !report.is_clean() {
        eprintln!(
            "warning: the cache in {} is damaged (perifrac verify lists what); going on with \
             what reads",
            out.display()
        );
    }
    Ok(report)
}
