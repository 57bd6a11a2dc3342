//! `perifrac check`'s memory estimate of an MPM scene against the peak resident
//! memory of `perifrac run` on it (docs/memory.md): a block that fills its grid
//! blocks and a thin wall that holds a few particles a block, each run with a
//! checkpoint at every frame (the state is encoded into the file as it goes, never
//! held whole a second time). Alone in its test binary: it measures its children.

use std::path::Path;

mod common;

/// An MPM scene of one body `shape`, 3 frames, a checkpoint at each, no previews.
fn scene(dir: &Path, resolution: f64, shape: &str) -> std::path::PathBuf {
    let path = dir.join("scene.toml");
    std::fs::write(
        &path,
        format!(
            "[scene]\nduration = 0.003\nfps = 1000.0\n\
             [materials.m]\ndensity = 1000.0\nyoungs_modulus = 1.0e5\npoisson_ratio = 0.3\n\
             [[body]]\nmodel = \"mpm\"\nmaterial = \"m\"\nresolution = {resolution}\n\
             velocity = [0.0, -1.0, 0.0]\nshape = {shape}\n\
             [output]\npreview = false\nusd = false\nsurface = \"none\"\ntets = false\n\
             checkpoint_every = 1\n"
        ),
    )
    .expect("writes the scene");
    path
}

/// `perifrac check`'s estimate of the peak (MiB).
fn estimate(scene: &Path) -> f64 {
    let out = common::perifrac_ok(&["check", scene.to_str().expect("utf-8")]);
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    text.lines()
        .find_map(|l| l.trim().strip_prefix("memory:"))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|mib| mib.parse().ok())
        .unwrap_or_else(|| panic!("no memory line in:\n{text}"))
}

/// The peak resident memory (MiB) of `perifrac run` on `scene` into `out`.
fn peak(scene: &Path, out: &Path) -> f64 {
    let (scene, out) = (scene.to_str().expect("utf-8"), out.to_str().expect("utf-8"));
    common::peak_mib(
        env!("CARGO_BIN_EXE_perifrac"),
        &["run", scene, "-o", out, "--quiet"],
    )
}

#[test]
fn the_estimate_of_an_mpm_run_is_within_8_percent_of_its_peak() {
    let dir = tempfile::tempdir().expect("temp dir");
    for (what, resolution, shape) in [
        (
            "a block, 262,144 particles",
            0.0125,
            r#"{ type = "box", center = [0.0, 0.5, 0.0], size = [0.4, 0.4, 0.4] }"#,
        ),
        (
            "a wall two cells thick",
            0.005,
            r#"{ type = "box", center = [0.0, 0.5, 0.0], size = [0.01, 0.6, 0.6] }"#,
        ),
    ] {
        let scene = scene(dir.path(), resolution, shape);
        let estimate = estimate(&scene);
        let peak = peak(&scene, &dir.path().join(format!("out-{resolution}")));
        println!("{what}: estimate {estimate:.1} MiB, peak {peak:.1} MiB");
        // Both within 2% here. Without the grid counted from the particles the
        // wall's estimate is 13% low; with the checkpoint held twice the block's
        // peak is 1.6 times it.
        assert!(
            (estimate / peak - 1.0).abs() < 0.08,
            "{what}: estimate {estimate:.1} MiB against a peak of {peak:.1} MiB"
        );
    }
}
