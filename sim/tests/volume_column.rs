//! Every model writes each particle's volume (m³) as the `volume` column of
//! `particles/NNNN.ply`, so readers (previews, `cache.usd`'s `widths`) draw each
//! particle at its own size: the volumes are positive and add up to the body's.

use std::path::Path;

use perifrac_sim::cache::ply::{ParticleFrame, VOLUME};
use perifrac_sim::run::{self, RunOptions};
use perifrac_sim::scene::Scene;

/// A still body of `shape` run by `model` for one frame; returns frame 1's particles.
fn first_frame(model: &str, shape: &str) -> ParticleFrame {
    let text = format!(
        "[scene]\nname = \"volumes\"\nduration = 0.001\nfps = 1000\ngravity = [0, 0, 0]\n\
         [materials.m]\ndensity = 1000\nyoungs_modulus = 1e5\npoisson_ratio = 0.3\n\
         [[body]]\nmodel = \"{model}\"\nmaterial = \"m\"\nresolution = 0.02\nshape = {shape}\n\
         [output]\ntets = false\nsurface = \"none\"\ncheckpoint_every = 0\npreview = false\n"
    );
    let scene = Scene::parse(&text, Path::new("volumes.toml"), Path::new(".")).expect("scene");
    let dir = tempfile::tempdir().expect("temp dir");
    run::run(&scene, dir.path(), &RunOptions::default(), &mut |_| {}).expect("runs");
    ParticleFrame::read(&dir.path().join("particles/0001.ply")).expect("frame 1")
}

#[test]
fn every_model_writes_particle_volumes_that_add_up_to_its_body() {
    let block = "{ type = \"box\", center = [0, 0.1, 0], size = [0.1, 0.1, 0.1] }";
    let sheet = "{ type = \"slab\", center = [0, 0.1, 0], size = [0.2, 0.2, 0.002] }";
    for (model, shape, volume) in [
        ("peridynamics", block, 1e-3),
        ("fem-corotated", block, 1e-3),
        ("mpm", block, 1e-3),
        // A sheet's particle volume is its area times the thickness.
        ("membrane", sheet, 0.2 * 0.2 * 0.002),
    ] {
        let frame = first_frame(model, shape);
        let v = frame
            .volume()
            .unwrap_or_else(|| panic!("{model}: no '{VOLUME}' column"));
        assert!(v.iter().all(|&x| x.is_finite() && x > 0.0), "{model}");
        let sum: f64 = v.iter().map(|&x| x as f64).sum();
        assert!(
            (sum / volume - 1.0).abs() < 0.1,
            "{model}: the particles' volumes add up to {sum:e} m³, the body's is {volume:e}"
        );
        // The first extra column, right after the standard ones.
        assert_eq!(frame.extra[0].0, VOLUME, "{model}");
    }
}
