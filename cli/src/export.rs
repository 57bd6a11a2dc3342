//! `perifrac export usd OUT`, and the USD export `perifrac run` runs last when the
//! scene's `[output] usd` asks for it: the whole cache as `OUT/cache.usd`
//! (`perifrac_usd::write_stage`).

use std::path::Path;

use perifrac_cache::Layout;
use perifrac_usd::UsdError;

use crate::commands::Failure;

impl From<UsdError> for Failure {
    fn from(e: UsdError) -> Failure {
        Failure {
            code: if e.is_bad_input() { 2 } else { 1 },
            error: e.into(),
        }
    }
}

/// Writes `OUT/cache.usd` for the cache in `out`; returns the seconds it took.
pub fn usd(out: &Path, quiet: bool) -> Result<f64, Failure> {
    let layout = Layout::new(out);
    if !layout.scene().is_file() {
        return Err(Failure::input(anyhow::anyhow!(
            "{}: not found; is {} the output directory of a `perifrac run`?",
            layout.scene().display(),
            out.display()
        )));
    }
    let report = perifrac_usd::write_stage(&layout)?;
    let (author, encode) = report.seconds;
    if !quiet {
        eprintln!(
            "wrote {} ({:.1} MB, {} frames: {} particles, {} meshes{}, {} colliders) in {:.2} s \
             (reading and authoring {:.2} s, encoding and writing {:.2} s)",
            layout.usd().display(),
            report.bytes as f64 / 1e6,
            report.frames,
            report.particles,
            report.meshes,
            if report.volume { ", a volume" } else { "" },
            report.colliders,
            author + encode,
            author,
            encode
        );
    }
    Ok(author + encode)
}
