//! The cache of `pinned/scene.toml` is pinned byte for byte: the particle PLY and
//! split-tet VTU frames in `pinned/cache/` were written before the restructure into one
//! integrator and one cache crate, and every later run must reproduce them. Work that
//! changes the physics on purpose regenerates them (`PINNED_UPDATE=1 cargo test -p
//! perifrac-sim --test pinned`) and says why in its commit.

use std::path::{Path, PathBuf};

use perifrac_sim::run::{self, RunOptions};
use perifrac_sim::scene::Scene;

fn pinned_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/pinned")
}

/// The largest relative difference between the f32 payloads of two binary PLY files
/// (the header must be equal), for the failure message.
fn ply_difference(a: &[u8], b: &[u8]) -> Option<f64> {
    let body = |x: &[u8]| {
        let end = x.windows(11).position(|w| w == b"end_header\n")? + 11;
        Some((x[..end].to_vec(), x[end..].to_vec()))
    };
    let ((ha, ba), (hb, bb)) = (body(a)?, body(b)?);
    if ha != hb || ba.len() != bb.len() {
        return None;
    }
    let floats = |x: &[u8]| -> Vec<f32> {
        x.chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect()
    };
    let (fa, fb) = (floats(&ba), floats(&bb));
    let scale = fa.iter().fold(0.0f64, |m, &v| m.max((v as f64).abs())).max(1e-30);
    Some(
        fa.iter()
            .zip(&fb)
            .map(|(&x, &y)| (x as f64 - y as f64).abs() / scale)
            .fold(0.0, f64::max),
    )
}

#[test]
fn the_pinned_scene_gives_the_pinned_bytes() {
    let dir = pinned_dir();
    let scene = Scene::load(&dir.join("scene.toml")).expect("pinned scene");
    let out = tempfile::tempdir().expect("temp dir");
    run::run(&scene, out.path(), &RunOptions::default(), &mut |_| {}).expect("runs");
    let frames = scene.frame_count() + 1;
    let reference = dir.join("cache");
    let update = std::env::var_os("PINNED_UPDATE").is_some();
    let mut compared = 0;
    for f in 1..=frames {
        for name in [format!("particles/{f:04}.ply"), format!("tets/{f:04}.vtu")] {
            let ours = std::fs::read(out.path().join(&name)).expect("frame written");
            let pinned = reference.join(&name);
            if update {
                std::fs::create_dir_all(pinned.parent().expect("parent")).expect("dir");
                std::fs::write(&pinned, &ours).expect("pinned frame written");
                continue;
            }
            let theirs = std::fs::read(&pinned).expect("pinned frame (PINNED_UPDATE=1 makes it)");
            if ours != theirs {
                let detail = match ply_difference(&ours, &theirs) {
                    Some(d) => format!("largest relative difference {d:.3e}"),
                    None => "layout differs".into(),
                };
                panic!("{name} differs from the pinned cache: {detail}");
            }
            compared += 1;
        }
    }
    assert!(update || compared == 2 * frames);
    let manifest: serde_json::Value = serde_json::from_slice(
        &std::fs::read(out.path().join("manifest.json")).expect("manifest"),
    )
    .expect("manifest is JSON");
    assert!(
        manifest["broken_bonds"].as_u64().unwrap_or(0) > 0,
        "the pinned scene must fracture"
    );
}
