//! The MPM model through `run::run`: a scene file's MPM bodies run frame by frame,
//! and a run interrupted and resumed from its checkpoint writes the same bytes.

use std::path::Path;

use perifrac_sim::cache::ply::ParticleFrame;
use perifrac_sim::run::{self, RunOptions};
use perifrac_sim::scene::Scene;

const SCENE: &str = "\
[scene]\nname = \"mpm-drop\"\nduration = 0.02\nfps = 250\nseed = 3\n\
[materials.m]\ndensity = 1000\nyoungs_modulus = 1e5\npoisson_ratio = 0.3\n\
[materials.m.mpm]\nelasticity = \"neo-hookean\"\n\
[[body]]\nmodel = \"mpm\"\nmaterial = \"m\"\nresolution = 0.02\nvelocity = [0.5, -1, 0]\n\
shape = { type = \"sphere\", center = [0, 0.07, 0], radius = 0.05 }\n\
[[collider]]\ntype = \"ground\"\n\
[[collider]]\ntype = \"box\"\ncenter = [0.1, 0.05, 0]\nsize = [0.04, 0.1, 0.2]\n\
[output]\ntets = false\nsurface = \"none\"\ncheckpoint_every = 2\npreview = false\n";

#[test]
fn an_mpm_run_resumed_from_its_checkpoint_writes_the_same_bytes() {
    let scene = Scene::parse(SCENE, Path::new("mpm.toml"), Path::new(".")).expect("scene");
    let frames = scene.frame_count() + 1;
    let full = tempfile::tempdir().expect("temp dir");
    let manifest =
        run::run(&scene, full.path(), &RunOptions::default(), &mut |_| {}).expect("runs");
    assert_eq!(manifest.status.to_string(), "complete");
    let part = tempfile::tempdir().expect("temp dir");
    let stop = RunOptions {
        frames: Some(2),
        ..RunOptions::default()
    };
    let stopped = run::run(&scene, part.path(), &stop, &mut |_| {}).expect("runs");
    assert!(
        stopped.status.to_string() == "interrupted",
        "{}",
        stopped.status
    );
    let resume = RunOptions {
        resume: true,
        ..RunOptions::default()
    };
    let resumed = run::run(&scene, part.path(), &resume, &mut |_| {}).expect("resumes");
    assert_eq!(resumed.status.to_string(), "complete");
    for f in 1..=frames {
        let name = format!("particles/{f:04}.ply");
        let a = std::fs::read(full.path().join(&name)).expect("frame");
        let b = std::fs::read(part.path().join(&name)).expect("frame");
        assert!(
            a == b,
            "{name}: a resumed run differs from an uninterrupted one"
        );
    }
    let last = ParticleFrame::read(&full.path().join(format!("particles/{frames:04}.ply")))
        .expect("last frame");
    assert!(
        last.position.iter().all(|p| p[1] > -0.01),
        "the ground holds the particles"
    );
}

#[test]
fn bad_mpm_scene_input_names_the_key() {
    let mixed = SCENE.replace(
        "[[collider]]\ntype = \"ground\"\n",
        "[[body]]\nmaterial = \"m\"\nresolution = 0.02\nshape = { type = \"sphere\", center = [0, 0.3, 0], radius = 0.05 }\n[[collider]]\ntype = \"ground\"\n",
    );
    let e = Scene::parse(&mixed, Path::new("mpm.toml"), Path::new(".")).expect_err("refused");
    assert!(e.to_string().contains("body.1.model"), "{e}");
    let unknown = SCENE.replace("elasticity = \"neo-hookean\"", "elasticity = \"rubber\"");
    let e = Scene::parse(&unknown, Path::new("mpm.toml"), Path::new(".")).expect_err("refused");
    assert!(e.to_string().contains("elasticity"), "{e}");
}

/// Throughput of MLS-MPM with fixed corotated elasticity at ≈10⁵ particles (a
/// benchmark, not a check: run by `scripts/mpm-bench.sh`).
#[test]
#[ignore = "benchmark: scripts/mpm-bench.sh"]
fn throughput_at_1e5_particles() {
    let text = "\
[scene]\nduration = 1\nfps = 100\ngravity = [0, -9.81, 0]\n\
[materials.m]\ndensity = 1000\nyoungs_modulus = 1e5\npoisson_ratio = 0.3\n\
[[body]]\nmodel = \"mpm\"\nmaterial = \"m\"\nresolution = 0.01\n\
shape = { type = \"box\", center = [0, 0.1, 0], size = [0.4, 0.2, 0.16] }\n\
[[collider]]\ntype = \"ground\"\n\
[output]\ntets = false\nsurface = \"none\"\npreview = false\n";
    let scene = Scene::parse(text, Path::new("bench.toml"), Path::new(".")).expect("scene");
    let mut p = run::prepare(&scene).expect("prepares");
    let n = p.world.particles().position.len();
    let steps = 20;
    p.world.reset_times();
    let start = std::time::Instant::now();
    for _ in 0..steps {
        p.world.step().expect("steps");
    }
    let wall = start.elapsed().as_secs_f64();
    println!(
        "{n} particles, {steps} steps, {} threads: {:.3e} particle-steps/s",
        rayon::current_num_threads(),
        (n * steps) as f64 / wall
    );
    for (stage, t) in p.world.stage_times() {
        println!(
            "  {stage}: {:.1} ms/step ({:.0}%)",
            1e3 * t / steps as f64,
            100.0 * t / wall
        );
    }
}
