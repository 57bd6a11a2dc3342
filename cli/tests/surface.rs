//! End-to-end runs of `perifrac surface` and `perifrac run` with `surface = "vdb"`:
//! the files land where the architecture says, the .glb files pass the Khronos glTF
//! validator, the .vdb files are read by OpenVDB's own `vdb_print`, and bad frames
//! fail with exit code 2 and a message.
#![cfg(feature = "openvdb")]

use std::path::Path;
use std::process::Command;

use perifrac_cache::Layout;
use perifrac_cache::manifest::{BodyInfo, Manifest};
use perifrac_cache::ply::ParticleFrame;
use perifrac_cache::scene::Scene;
use perifrac_sim::geometry::discretize::discretize;

mod common;
use common::perifrac;

const SCENE: &str = r#"[scene]
name = "surface-test"
duration = 0.001
fps = 1000.0

[materials.m]
density = 1000.0
bulk_modulus = 1e6
shear_modulus = 1e6

[[body]]
material = "m"
shape = { type = "box", center = [0.0, 0.5, 0.0], size = [0.1, 0.1, 0.1] }
resolution = 0.02

[output]
surface = "vdb"
checkpoint_every = 0
"#;

/// `perifrac run SCENE -o OUT EXTRA…`, which must succeed.
fn run(scene: &Path, out: &Path, extra: &[&str]) {
    let mut args = vec!["run", scene.to_str().unwrap(), "-o", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    let output = perifrac(&args);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
}

/// A cache of two frames: the scene's box split in two fragments side by side,
/// plus three loose particles (debris).
fn write_cache(root: &Path) -> usize {
    let scene = Scene::parse(SCENE, Path::new("scene.toml"), Path::new(".")).expect("scene");
    let disc = discretize(&scene).expect("discretize");
    let layout = Layout::new(root);
    layout.create().unwrap();
    std::fs::write(layout.scene(), scene.to_toml()).unwrap();
    let mut frame = ParticleFrame::default();
    for (copy, dx) in [(0.0f32, 0.0f32), (1.0, 0.2)] {
        for p in &disc.position {
            frame
                .position
                .push([p[0] as f32 + dx, p[1] as f32, p[2] as f32]);
            frame.fragment.push(copy);
        }
    }
    for k in 0..3 {
        frame.position.push([1.0 + k as f32, 0.0, 0.0]);
        frame.fragment.push(2.0 + k as f32);
    }
    let n = frame.position.len();
    frame.velocity = vec![[0.5, 0.0, 0.0]; n];
    frame.damage = vec![0.0; n];
    frame.plastic = vec![0.0; n];
    frame.material = vec![0.0; n];
    for f in 1..=2 {
        frame.frame = f;
        frame.write(&layout.particles(f)).unwrap();
    }
    Manifest {
        scene: "surface-test".into(),
        frame_times: vec![0.0, 0.001],
        particles: n,
        bodies: vec![BodyInfo {
            name: "body0".into(),
            material: "m".into(),
            particles: n,
            mean_edge: disc.quality[0].mean_edge,
            ..BodyInfo::default()
        }],
        ..Manifest::default()
    }
    .write(&layout.manifest())
    .unwrap();
    n
}

/// The Khronos validator's report on `file` (tools/gltf-validator, installed by
/// scripts/setup.sh).
fn validate(file: &Path) -> serde_json::Value {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tools/gltf-validator/validate.mjs");
    let out = Command::new("node")
        .arg(script)
        .arg(file)
        .output()
        .expect("node runs (scripts/setup.sh installs it and the validator)");
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "no JSON report ({e}): {}",
            String::from_utf8_lossy(&out.stderr)
        )
    })
}

#[test]
fn surface_writes_valid_glb_vdb_and_debris_files() {
    let dir = tempfile::tempdir().unwrap();
    write_cache(dir.path());
    let out = perifrac(&["surface", dir.path().to_str().unwrap(), "--method", "vdb"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for f in ["0001", "0002"] {
        let glb = dir.path().join(format!("surface/{f}.glb"));
        let report = validate(&glb);
        assert_eq!(report["numErrors"], 0, "{report:#}");
        let bytes = std::fs::read(&glb).unwrap();
        let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        let doc: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
        let names: Vec<&str> = doc["meshes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m["name"].as_str().unwrap())
            .collect();
        assert_eq!(names, ["fragment 0", "fragment 1"]);

        let vdb = dir.path().join(format!("vdb/{f}.vdb"));
        let print = Command::new("vdb_print")
            .arg(&vdb)
            .arg("-l")
            .output()
            .expect("vdb_print runs (libopenvdb-tools, installed by scripts/setup.sh)");
        let text = String::from_utf8_lossy(&print.stdout);
        assert!(print.status.success(), "{text}");
        assert!(text.contains("Name: surface"), "{text}");
        assert!(text.contains("class: level set"), "{text}");
        assert_eq!(text.matches("voxel size:").count(), 2, "{text}");
        assert!(text.contains("Name: v"), "{text}");

        let debris = std::fs::read(dir.path().join(format!("surface/{f}_debris.ply"))).unwrap();
        assert!(String::from_utf8_lossy(&debris).contains("element vertex 3\n"));
    }
}

#[test]
fn a_frame_with_nan_fails_with_a_message() {
    let dir = tempfile::tempdir().unwrap();
    write_cache(dir.path());
    let layout = Layout::new(dir.path());
    let mut frame = ParticleFrame::read(&layout.particles(2)).unwrap();
    frame.position[7][2] = f32::NAN;
    frame.write(&layout.particles(2)).unwrap();
    let out = perifrac(&["surface", dir.path().to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("frame 2") && stderr.contains("particle 7 has a non-finite position"),
        "{stderr}"
    );
}

#[test]
fn run_surfaces_when_the_scene_asks() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let out_dir = dir.path().join("out");
    run(&scene, &out_dir, &["--frames", "1"]);
    let manifest = Manifest::read(&out_dir.join("manifest.json")).unwrap();
    for f in 1..=manifest.frame_times.len() {
        for file in [format!("vdb/{f:04}.vdb"), format!("surface/{f:04}.glb")] {
            assert!(out_dir.join(&file).is_file(), "{file} missing");
        }
    }
}

/// An MPM body has no tet mesh: its particle spacing (grid spacing over the particles
/// per cell axis) goes into the manifest, and the vdb method meshes it at that spacing
/// (before, `mean_edge` was 0 for it and the surface stage refused every MPM run).
#[test]
fn an_mpm_run_is_surfaced_at_its_particle_spacing() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("mpm.toml");
    std::fs::write(
        &scene,
        r#"[scene]
name = "mpm-block"
duration = 0.002
fps = 1000.0

[materials.gel]
density = 1000.0
youngs_modulus = 1e5
poisson_ratio = 0.3

[[body]]
material = "gel"
model = "mpm"
resolution = 0.01
shape = { type = "box", center = [0.0, 0.1, 0.0], size = [0.1, 0.1, 0.1] }

[output]
surface = "vdb"
preview = false
checkpoint_every = 0
"#,
    )
    .unwrap();
    let out_dir = dir.path().join("out");
    run(&scene, &out_dir, &[]);
    let manifest = Manifest::read(&out_dir.join("manifest.json")).unwrap();
    assert_eq!(manifest.bodies[0].mean_edge, 0.0);
    assert!((manifest.bodies[0].particle_spacing - 0.005).abs() < 1e-15);
    let glb = out_dir.join("surface/0003.glb");
    let report = validate(&glb);
    assert_eq!(report["numErrors"], 0, "{report:#}");
    // The mesh spans the 0.1 m block to within two particle spacings.
    let bytes = std::fs::read(&glb).unwrap();
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let doc: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let position = &doc["accessors"][0];
    for axis in 0..3 {
        let extent =
            position["max"][axis].as_f64().unwrap() - position["min"][axis].as_f64().unwrap();
        assert!(
            (extent - 0.1).abs() < 0.01,
            "axis {axis}: extent {extent} m"
        );
    }
}
