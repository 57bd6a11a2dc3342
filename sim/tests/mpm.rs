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
    resumed_run_matches(SCENE);
}

/// The shock model's internal energy and the plastic strain go through the checkpoint.
#[test]
fn a_shock_and_johnson_cook_run_resumes_to_the_same_bytes() {
    resumed_run_matches(&SCENE.replace(
        "elasticity = \"neo-hookean\"",
        "elasticity = \"shock\"\nbulk_sound_speed = 20\n\
         plasticity = { type = \"johnson-cook\", yield_stress = 2e3, hardening = 1e4, exponent = 0.5 }",
    ));
}

/// The thermal Johnson–Cook term's temperatures go through the checkpoint and into the
/// particle cache's `temperature` column, heated above room temperature by the impact.
#[test]
fn a_thermal_johnson_cook_run_resumes_to_the_same_bytes_and_caches_temperature() {
    let text = SCENE.replace(
        "elasticity = \"neo-hookean\"",
        "plasticity = { type = \"johnson-cook\", yield_stress = 2e3, hardening = 1e4, exponent = 0.5, \
         melting_temperature = 400, room_temperature = 300, thermal_exponent = 1, specific_heat = 1 }",
    );
    resumed_run_matches(&text);
    let frame = last_frame(&text);
    let t = frame.extra("temperature").expect("a temperature column");
    let (lo, hi) = t
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    assert!(lo >= 300.0 && hi > 300.5, "temperatures in [{lo}, {hi}] K");
}

/// SPB-MPM: the energy histories, the peridynamic particles and their bonds go through
/// the checkpoint; the cache has each particle's region and damage.
#[test]
fn an_spb_mpm_run_resumes_to_the_same_bytes_and_caches_region_and_damage() {
    let text = SCENE.replace(
        "elasticity = \"neo-hookean\"",
        "elasticity = \"neo-hookean\"\nenergy_release_rate = 0.05",
    );
    resumed_run_matches(&text);
    let frame = last_frame(&text);
    let region = frame.extra("region").expect("a region column");
    let members = region.iter().filter(|&&r| r == 1.0).count();
    let damaged = frame.damage.iter().filter(|&&d| d > 0.0).count();
    assert!(
        members > 0 && members < region.len() && damaged > 0,
        "{members} of {} particles peridynamic, {damaged} damaged",
        region.len()
    );
    assert!(region.iter().all(|&r| r == 0.0 || r == 1.0));
}

/// SPB-MPM of a plastic material: the peridynamic particles' plastic parts F_P⁻¹ go
/// through the checkpoint too, and they flow (ε^p above 0 in the peridynamic region).
#[test]
fn a_plastic_spb_mpm_run_resumes_to_the_same_bytes() {
    let text = SCENE.replace(
        "elasticity = \"neo-hookean\"",
        "energy_release_rate = 0.05\n\
         plasticity = { type = \"johnson-cook\", yield_stress = 2e3, hardening = 1e4, exponent = 0.5 }",
    );
    resumed_run_matches(&text);
    let frame = last_frame(&text);
    let region = frame.extra("region").expect("a region column");
    let flowing = region
        .iter()
        .zip(&frame.plastic)
        .filter(|&(&r, &e)| r == 1.0 && e > 0.0)
        .count();
    assert!(flowing > 0, "no peridynamic particle flows");
}

/// The integral-based MPM (Lyu ch. 5): the bonds of every particle, their plastic
/// extensions and their breaks go through the checkpoint; the impact on the box
/// breaks bonds and makes them flow, and the cache shows both.
#[test]
fn an_integral_based_mpm_run_resumes_to_the_same_bytes() {
    let text = SCENE.replace(
        "elasticity = \"neo-hookean\"",
        "bonds = { yield_stress = 5e3, critical_stretch = 0.02 }",
    );
    resumed_run_matches(&text);
    let frame = last_frame(&text);
    let region = frame.extra("region").expect("a region column");
    let damaged = frame.damage.iter().filter(|&&d| d > 0.0).count();
    let flowing = frame.plastic.iter().filter(|&&e| e > 0.0).count();
    assert!(region.iter().all(|&r| r == 1.0), "every particle is bonded");
    assert!(
        damaged > 0 && flowing > 0,
        "{damaged} damaged, {flowing} flowing"
    );
}

/// Viscous bonds keep two flows a bond (the springs' and the μ term's), and both go
/// through the checkpoint: the ball flows on the box and resumes to the same bytes.
#[test]
fn a_viscous_integral_based_mpm_run_resumes_to_the_same_bytes() {
    let text = SCENE.replace(
        "elasticity = \"neo-hookean\"",
        "bonds = { viscosity = 20, yield_stress = 500 }",
    );
    resumed_run_matches(&text);
    let frame = last_frame(&text);
    let flowing = frame.plastic.iter().filter(|&&e| e > 0.0).count();
    assert!(flowing > 0, "{flowing} flowing");
}

/// The last particle frame of a whole run of the scene `text`.
fn last_frame(text: &str) -> ParticleFrame {
    let scene = Scene::parse(text, Path::new("mpm.toml"), Path::new(".")).expect("scene");
    let out = tempfile::tempdir().expect("temp dir");
    run::run(&scene, out.path(), &RunOptions::default(), &mut |_| {}).expect("runs");
    let last = scene.frame_count();
    ParticleFrame::read(&out.path().join(format!("particles/{last:04}.ply"))).expect("last frame")
}

fn resumed_run_matches(text: &str) {
    let scene = Scene::parse(text, Path::new("mpm.toml"), Path::new(".")).expect("scene");
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
    for column in ["J", "constitutive"] {
        let values = last.extra(column).expect("an MPM column");
        assert_eq!(values.len(), last.position.len(), "{column}");
    }
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
    for (replacement, key, fix) in [
        (
            "elasticity = \"shock\"",
            "materials.m.mpm.bulk_sound_speed",
            "add bulk_sound_speed",
        ),
        (
            "plasticity = { type = \"johnson-cook\", yield_stress = 1e4, exponent = 2 }",
            "materials.m.mpm.plasticity.exponent",
            "[0, 1]",
        ),
        (
            "plasticity = { type = \"snow\", critical_compression = 1.5, critical_stretch = 0.01 }",
            "materials.m.mpm.plasticity.critical_compression",
            "(0, 1)",
        ),
        (
            "plasticity = { type = \"drucker-prager\", friction_angle = 120 }",
            "materials.m.mpm.plasticity.friction_angle",
            "(0, 90)",
        ),
        (
            "elasticity = \"neo-hookean\"\nbulk_sound_speed = 100",
            "materials.m.mpm.bulk_sound_speed",
            "remove it",
        ),
        (
            "plasticity = { type = \"johnson-cook\", yield_stress = 1e3, melting_temperature = 1356, \
             room_temperature = 293 }",
            "materials.m.mpm.plasticity.melting_temperature",
            "add thermal_exponent or remove melting_temperature, room_temperature",
        ),
        (
            "plasticity = { type = \"johnson-cook\", yield_stress = 1e3, taylor_quinney = 0.9 }",
            "materials.m.mpm.plasticity.taylor_quinney",
            "or remove taylor_quinney",
        ),
        (
            "plasticity = { type = \"johnson-cook\", yield_stress = 1e3, melting_temperature = 200, \
             room_temperature = 293, thermal_exponent = 1, specific_heat = 383 }",
            "materials.m.mpm.plasticity.melting_temperature",
            "above the room temperature",
        ),
        (
            "plasticity = { type = \"johnson-cook\", yield_stress = 1e3, melting_temperature = 1356, \
             room_temperature = 293, thermal_exponent = 1, specific_heat = 383, taylor_quinney = 1.5 }",
            "materials.m.mpm.plasticity.taylor_quinney",
            "[0, 1]",
        ),
        (
            "elasticity = \"neo-hookean\"\nbonds = {}",
            "materials.m.mpm.elasticity",
            "remove elasticity, or remove the bonds table",
        ),
        (
            "bonds = { critical_stretch = -0.1 }",
            "materials.m.mpm.bonds.critical_stretch",
            "positive finite",
        ),
        (
            "bonds = { viscosity = 0 }",
            "materials.m.mpm.bonds.viscosity",
            "positive finite",
        ),
        (
            "elasticity = \"neo-hookean\"\nenergy_release_rate = -1",
            "materials.m.mpm.energy_release_rate",
            "positive finite",
        ),
        (
            "elasticity = \"neo-hookean\"\nerosion_release_rate = 1",
            "materials.m.mpm.erosion_release_rate",
            "add energy_release_rate",
        ),
        (
            "elasticity = \"neo-hookean\"\nenergy_release_rate = 1\nerosion_release_rate = 0",
            "materials.m.mpm.erosion_release_rate",
            "positive finite",
        ),
    ] {
        let text = SCENE.replace("elasticity = \"neo-hookean\"", replacement);
        let e = Scene::parse(&text, Path::new("mpm.toml"), Path::new(".")).expect_err("refused");
        let message = e.to_string();
        assert!(
            message.contains(key) && message.contains(fix),
            "{replacement}: {message}"
        );
    }
    let stray = format!("{SCENE}[mpm]\nflip_ratio = 1.5\n");
    let e = Scene::parse(&stray, Path::new("mpm.toml"), Path::new(".")).expect_err("refused");
    assert!(e.to_string().contains("mpm.flip_ratio"), "{e}");
}

/// Throughput of MLS-MPM with fixed corotated elasticity: a 0.4 × 0.2 × 0.16 m block
/// on a slip ground at the resolution `MPM_BENCH_RESOLUTION` (default 0.01 m: ≈10⁵
/// particles; 0.0046 m: ≈10⁶) for `MPM_BENCH_STEPS` steps (default 20). Optional:
/// `MPM_BENCH_MPM`, lines of the material's `[materials.m.mpm]` table (a plastic flow,
/// another elasticity), and `MPM_BENCH_VELOCITY`, the block's initial downward speed
/// (m/s, default 0; a block thrown at the ground flows at once). It prints the share of
/// particles whose plastic strain grows in one more step. A benchmark, not a check: run
/// by `scripts/mpm-bench.sh` and `scripts/taichi-compare.sh`.
#[test]
#[ignore = "benchmark: scripts/mpm-bench.sh"]
fn throughput() {
    let setting = |name: &str, default: f64| {
        std::env::var(name)
            .ok()
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or(default)
    };
    let resolution = setting("MPM_BENCH_RESOLUTION", 0.01);
    let steps = setting("MPM_BENCH_STEPS", 20.0) as usize;
    let speed = setting("MPM_BENCH_VELOCITY", 0.0);
    let mpm = std::env::var("MPM_BENCH_MPM").unwrap_or_default();
    let text = format!(
        "[scene]\nduration = 1\nfps = 100\ngravity = [0, -9.81, 0]\n\
         [materials.m]\ndensity = 1000\nyoungs_modulus = 1e5\npoisson_ratio = 0.3\n\
         [materials.m.mpm]\n{mpm}\n\
         [[body]]\nmodel = \"mpm\"\nmaterial = \"m\"\nresolution = {resolution}\n\
         velocity = [0, {}, 0]\n\
         shape = {{ type = \"box\", center = [0, 0.1, 0], size = [0.4, 0.2, 0.16] }}\n\
         [[collider]]\ntype = \"ground\"\nfriction = 0\n\
         [output]\ntets = false\nsurface = \"none\"\npreview = false\n",
        -speed
    );
    let scene = Scene::parse(&text, Path::new("bench.toml"), Path::new(".")).expect("scene");
    let mut p = run::prepare(&scene).expect("prepares");
    let n = p.world.particles().position.len();
    // Warm-up: the grid's buffers reach their size.
    for _ in 0..3 {
        p.world.step().expect("steps");
    }
    p.world.reset_times();
    let start = std::time::Instant::now();
    for _ in 0..steps {
        p.world.step().expect("steps");
    }
    let wall = start.elapsed().as_secs_f64();
    let times = p.world.stage_times();
    // One more step, untimed, to see how many particles flow.
    let before = p.world.particles().plastic;
    p.world.step().expect("steps");
    let after = p.world.particles().plastic;
    let flowing = before.iter().zip(&after).filter(|(b, a)| a > b).count();
    println!(
        "{n} particles, {steps} steps, {} threads: {:.4e} particle-steps/s \
         ({:.1}% of the particles flow in the next step)",
        rayon::current_num_threads(),
        (n * steps) as f64 / wall,
        100.0 * flowing as f64 / n as f64
    );
    for (stage, t) in times {
        println!(
            "  {stage}: {:.1} ms/step ({:.0}%)",
            1e3 * t / steps as f64,
            100.0 * t / wall
        );
    }
}

/// Runs the scene file `MPM_SCENE` (surfaces and previews off, for `MPM_SCENE_FRAMES`
/// frames if set) and prints its wall time, step count and what the last frame
/// holds. A benchmark, not a check: run by `scripts/mpm-scenes.sh`.
#[test]
#[ignore = "scene run: scripts/mpm-scenes.sh"]
fn scene_run() {
    let Ok(path) = std::env::var("MPM_SCENE") else {
        return;
    };
    let path = Path::new(&path);
    let mut scene = Scene::load(path).expect("scene");
    scene.output.surface = perifrac_sim::scene::SurfaceMethod::None;
    scene.output.preview = false;
    let frames = std::env::var("MPM_SCENE_FRAMES")
        .ok()
        .and_then(|f| f.parse().ok());
    let out = tempfile::tempdir().expect("temp dir");
    let start = std::time::Instant::now();
    let options = RunOptions {
        frames,
        ..RunOptions::default()
    };
    let mut steps = 0;
    let manifest = run::run(&scene, out.path(), &options, &mut |p| steps = p.steps).expect("runs");
    let wall = start.elapsed().as_secs_f64();
    let last = std::fs::read_dir(out.path().join("particles"))
        .expect("particles")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .max()
        .expect("a frame");
    let frame = ParticleFrame::read(&last).expect("last frame");
    let n = frame.position.len();
    let max_plastic = frame.plastic.iter().copied().fold(0.0f32, f32::max);
    let mean_plastic = frame.plastic.iter().map(|&e| e as f64).sum::<f64>() / n as f64;
    let j = frame.extra("J").expect("J");
    let (j_min, j_max) = j
        .iter()
        .fold((f32::INFINITY, 0.0f32), |(a, b), &x| (a.min(x), b.max(x)));
    println!(
        "{}: {} ({n} particles, {steps} steps, {wall:.1} s, {:.3e} particle-steps/s); last frame: ε^p mean {mean_plastic:.4} max {max_plastic:.4}, J in [{j_min:.3}, {j_max:.3}]",
        path.display(),
        manifest.status,
        (n as f64 * steps as f64) / wall
    );
    if let Some(region) = frame.extra("region") {
        let mut pieces: Vec<u32> = frame.fragment.iter().map(|&f| f as u32).collect();
        pieces.sort_unstable();
        pieces.dedup();
        println!(
            "  SPB-MPM: {} peridynamic particles, {} pieces, mean damage {:.3}",
            region.iter().filter(|&&r| r == 1.0).count(),
            pieces.len(),
            frame.damage.iter().map(|&d| f64::from(d)).sum::<f64>() / n as f64
        );
    }
    for b in 0..scene.bodies.len() {
        let members: Vec<usize> = (0..n)
            .filter(|&i| frame.material[i] as usize == b)
            .collect();
        let mean = |a: usize| {
            members
                .iter()
                .map(|&i| frame.velocity[i][a] as f64)
                .sum::<f64>()
                / members.len() as f64
        };
        println!(
            "  body {} ({}): {} particles, mean velocity [{:.2}, {:.2}, {:.2}] m/s",
            b,
            scene.bodies[b].name,
            members.len(),
            mean(0),
            mean(1),
            mean(2)
        );
    }
}
