//! `perifrac export usd OUT`, and the USD export `perifrac run` runs last when the
//! scene's `[output] usd` asks for it: the whole cache as `OUT/cache.usd` and its
//! value clips `OUT/usd/` (`perifrac_usd::write_stage`).

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
    // The clips are cache files `perifrac verify` checks, as the surfaces are.
    layout.record_outputs(&[layout.usd_dir()])?;
    let (author, encode) = report.seconds;
    if !quiet {
        eprintln!(
            "wrote {} with its clips {} ({:.1} MB, {} frames: {} particles, {} meshes{}, {} \
             colliders) in {:.2} s (the frames' clips {:.2} s, the stage {:.2} s)",
            layout.usd().display(),
            layout.usd_dir().join("NNNN.usdc").display(),
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
