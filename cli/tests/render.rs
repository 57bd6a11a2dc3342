//! End-to-end runs of the render stage: `perifrac run` ends with previews,
//! `perifrac render` makes turntables and reports empty frames and missing fields, and
//! without any GL library the simulation still completes.
#![cfg(feature = "gl")]

use std::path::Path;
use std::process::{Command, Output};

const SCENE: &str = r#"[scene]
name = "tiny-ball"
duration = 0.01
fps = 400

[materials.jelly]
density = 1000.0
youngs_modulus = 1.0e5
poisson_ratio = 0.3
critical_stretch = 0.05

[[body]]
name = "cube"
material = "jelly"
shape = { type = "box", center = [0, 0.03, 0], size = [0.05, 0.05, 0.05] }
resolution = 0.01
velocity = [0, -1, 0]

[[collider]]
type = "ground"

[[collider]]
type = "sphere"
center = [0, 0.03, -0.06]
radius = 0.02
velocity = [0, 0, 1]
mass = 0.1
"#;

fn perifrac(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_perifrac"));
    cmd.args(args).arg("--quiet");
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().expect("the binary runs")
}

fn run_scene(dir: &Path, env: &[(&str, &str)]) -> (Output, std::path::PathBuf) {
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, SCENE).expect("write scene");
    let out = dir.join("out");
    let result = perifrac(
        &[
            "run",
            &scene.to_string_lossy(),
            "-o",
            &out.to_string_lossy(),
        ],
        env,
    );
    (result, out)
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

#[test]
fn run_ends_with_previews_and_render_makes_turntables() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (result, out) = run_scene(dir.path(), &[]);
    assert!(result.status.success(), "{}", text(&result));
    for frame in 1..=5 {
        let png = image::open(out.join(format!("preview/{frame:04}.png"))).expect("preview");
        assert_eq!((png.width(), png.height()), (960, 540));
    }
    assert!(out.join("preview/contact_sheet.png").is_file());
    // The dynamic ball's per-frame centre is in the manifest.
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["collider_centers"].as_array().unwrap().len(), 5);

    let o = out.to_string_lossy();
    let r = perifrac(
        &[
            "render",
            &o,
            "--turntable",
            "3",
            "--frame",
            "2",
            "--size",
            "64x48",
        ],
        &[],
    );
    assert!(r.status.success(), "{}", text(&r));
    for i in 1..=3 {
        let png = image::open(out.join(format!("preview/turntable_{i:03}.png"))).unwrap();
        assert_eq!((png.width(), png.height()), (64, 48));
    }
    let again = std::fs::read(out.join("preview/frame_0002.png")).unwrap();
    let r = perifrac(&["render", &o, "--frame", "2", "--size", "64x48"], &[]);
    assert!(r.status.success(), "{}", text(&r));
    assert_eq!(
        again,
        std::fs::read(out.join("preview/frame_0002.png")).unwrap(),
        "the same frame twice must give identical bytes"
    );
    // The single frame went beside the sequence's preview, not over it.
    let sequence = image::open(out.join("preview/0002.png")).unwrap();
    assert_eq!((sequence.width(), sequence.height()), (960, 540));

    let r = perifrac(&["render", &o, "--color-by", "temperature"], &[]);
    assert_eq!(r.status.code(), Some(2), "{}", text(&r));
    assert!(
        text(&r).contains("0001.ply") && text(&r).contains("'temperature'"),
        "{}",
        text(&r)
    );
    let r = perifrac(&["render", &o, "--frame", "99"], &[]);
    assert_eq!(r.status.code(), Some(2), "{}", text(&r));

    // A frame whose particles are all gone renders the ground and says so.
    let empty = perifrac_cache::ply::ParticleFrame {
        frame: 3,
        ..Default::default()
    };
    empty.write(&out.join("particles/0003.ply")).unwrap();
    let r = perifrac(&["render", &o, "--frame", "3", "--size", "64x48"], &[]);
    assert!(r.status.success(), "{}", text(&r));
    assert!(
        text(&r).contains("frame 3 has nothing in view"),
        "{}",
        text(&r)
    );
    assert!(out.join("preview/frame_0003.png").is_file());
}

#[test]
fn without_gl_libraries_the_simulation_still_completes() {
    let missing = [
        ("PERIFRAC_EGL_LIB", "/nonexistent/libEGL.so.1"),
        ("PERIFRAC_OSMESA_LIB", "/nonexistent/libOSMesa.so.8"),
    ];
    let dir = tempfile::tempdir().expect("temp dir");
    let (result, out) = run_scene(dir.path(), &missing);
    assert!(result.status.success(), "{}", text(&result));
    let t = text(&result);
    assert!(
        t.contains("previews skipped") && t.contains("libEGL.so.1") && t.contains("libOSMesa.so.8"),
        "{t}"
    );
    assert!(out.join("particles/0005.ply").is_file());
    assert!(!out.join("preview/0001.png").exists());
    let r = perifrac(&["render", &out.to_string_lossy()], &missing);
    assert_eq!(r.status.code(), Some(1), "{}", text(&r));
    assert!(text(&r).contains("libEGL.so.1"), "{}", text(&r));
}
