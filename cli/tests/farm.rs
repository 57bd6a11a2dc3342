//! A shot's per-frame stages split across a farm (issue 35, item 3): `perifrac surface
//! --frames` and `perifrac render --frames` ranges run side by side on one cache, then
//! `render --join` and `export usd`, leave the bytes one machine running each stage
//! over every frame leaves, manifest included.
#![cfg(all(feature = "openvdb", feature = "gl"))]

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Child, Command, Stdio};

mod common;
use common::{outcome, perifrac, perifrac_ok};

/// A glass wall hit by a ball, coarse: 1,499 particles, 6 frames, the split tet
/// meshes written for the embedded method.
const SCENE: &str = r#"[scene]
name = "farm-test"
duration = 0.002
fps = 2500.0
gravity = [0.0, -9.81, 0.0]

[materials.glass]
density = 2200.0
bulk_modulus = 3.3e10
shear_modulus = 2.0e10
critical_stretch = 0.0005

[[body]]
name = "wall"
material = "glass"
shape = { type = "box", center = [0.0, 0.2, 0.0], size = [0.3, 0.3, 0.05] }
resolution = 0.04

[[collider]]
type = "ground"

[[collider]]
type = "sphere"
center = [0.0, 0.2, -0.08]
radius = 0.05
velocity = [0.0, 0.0, 50.0]
mass = 4.11

[output]
checkpoint_every = 0
preview = false
usd = false
tets = true
"#;

/// Starts `perifrac ARGS --quiet` without waiting.
fn start(args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_perifrac"))
        .args(args)
        .arg("--quiet")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs")
}

/// Runs the commands side by side; each must succeed.
fn side_by_side(commands: &[&[&str]]) {
    let children: Vec<Child> = commands.iter().map(|args| start(args)).collect();
    for (child, args) in children.into_iter().zip(commands) {
        let out = child.wait_with_output().expect("waits");
        assert!(
            out.status.success(),
            "perifrac {args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// Every file under `root` (relative path → bytes), the manifest's lock aside.
fn files(root: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut all = BTreeMap::new();
    let mut dirs = vec![root.to_path_buf()];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                dirs.push(path);
            } else if entry.file_name() != ".manifest.lock" {
                let name = path
                    .strip_prefix(root)
                    .unwrap()
                    .to_string_lossy()
                    .into_owned();
                all.insert(name, std::fs::read(&path).unwrap());
            }
        }
    }
    all
}

/// Copies the cache `from` to `to`.
fn copy(from: &Path, to: &Path) {
    for (name, bytes) in files(from) {
        let path = to.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, bytes).unwrap();
    }
}

/// The files that differ (or are on one side only) between two trees.
fn differences(a: &BTreeMap<String, Vec<u8>>, b: &BTreeMap<String, Vec<u8>>) -> Vec<String> {
    a.keys()
        .chain(b.keys())
        .filter(|k| a.get(*k) != b.get(*k))
        .cloned()
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect()
}

#[test]
fn frame_ranges_side_by_side_give_the_bytes_of_one_pass_over_every_frame() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("farm.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let (one, farm) = (dir.path().join("one"), dir.path().join("farm"));
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let (one_s, farm_s) = (s(&one), s(&farm));
    perifrac_ok(&["run", &s(&scene), "-o", &one_s]);
    copy(&one, &farm);
    let (embedded_one, embedded_farm) = (dir.path().join("e1"), dir.path().join("e2"));
    copy(&one, &embedded_one);
    copy(&one, &embedded_farm);

    // One machine: each stage over every frame.
    perifrac_ok(&["surface", &one_s]);
    perifrac_ok(&["render", &one_s, "--movie"]);
    perifrac_ok(&["export", "usd", &one_s]);

    // A farm: two ranges of each stage at once, one worker each, then the joins.
    side_by_side(&[
        &["surface", &farm_s, "--frames", "1..4", "--threads", "1"],
        &["surface", &farm_s, "--frames", "5..6", "--threads", "1"],
    ]);
    side_by_side(&[
        &["render", &farm_s, "--frames", "1..2", "--threads", "1"],
        &["render", &farm_s, "--frames", "3..6", "--threads", "1"],
    ]);
    perifrac_ok(&["render", &farm_s, "--join", "--movie"]);
    perifrac_ok(&["export", "usd", &farm_s]);

    let (a, b) = (files(&one), files(&farm));
    assert_eq!(differences(&a, &b), Vec::<String>::new());
    for name in [
        "vdb/0006.vdb",
        "surface/0006.glb",
        "preview/0006.png",
        "preview/contact_sheet.png",
        "preview/movie.png",
        "cache.usd",
    ] {
        assert!(b.contains_key(name), "{name} missing from the farm's cache");
    }
    let verify = perifrac(&["verify", &farm_s]);
    assert_eq!(outcome(&verify).0, Some(0), "{}", outcome(&verify).1);

    // The embedded method's ranges write their frames; animated.glb, which needs every
    // frame, only a pass over all of them.
    let (e1, e2) = (s(&embedded_one), s(&embedded_farm));
    perifrac_ok(&["surface", &e1, "--method", "embedded"]);
    side_by_side(&[
        &["surface", &e2, "--method", "embedded", "--frames", "1..3"],
        &["surface", &e2, "--method", "embedded", "--frames", "4..6"],
    ]);
    let (a, b) = (files(&embedded_one), files(&embedded_farm));
    for k in 1..=6 {
        let name = format!("surface/{k:04}.glb");
        assert!(
            b.contains_key(&name) && a.get(&name) == b.get(&name),
            "{name}"
        );
    }
    assert!(a.contains_key("surface/animated.glb") && !b.contains_key("surface/animated.glb"));
}

#[test]
fn ranges_outside_the_cache_and_joins_with_frames_missing_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("farm.toml");
    // Two frames, no tet meshes.
    let short = SCENE
        .replace("duration = 0.002", "duration = 0.0004")
        .replace("tets = true", "tets = false");
    std::fs::write(&scene, short).unwrap();
    let out = dir.path().join("out");
    let out_s = out.to_str().unwrap();
    perifrac_ok(&["run", scene.to_str().unwrap(), "-o", out_s]);
    for (args, says) in [
        (
            vec!["surface", out_s, "--frames", "3..9"],
            "the cache has frames 1..2",
        ),
        (
            vec!["render", out_s, "--frames", "3"],
            "the cache has frames 1..2",
        ),
        (
            vec!["render", out_s, "--frames", "2..1"],
            "before the first",
        ),
        (
            vec!["surface", out_s, "--frames", "0..1"],
            "numbered from 1",
        ),
        (
            vec!["render", out_s, "--join"],
            "2 of the 2 frames not rendered yet (1..2)",
        ),
    ] {
        let (code, stderr) = outcome(&perifrac(&args));
        assert_eq!(code, Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
    }
    // A farm's last chunk may run past the end: its frames there are left out.
    let stderr =
        String::from_utf8_lossy(&perifrac_ok(&["surface", out_s, "--frames", "2..10"]).stderr)
            .into_owned();
    assert!(
        stderr.contains("ends at frame 2: working on 2..2"),
        "{stderr}"
    );
    assert!(out.join("vdb/0002.vdb").is_file() && !out.join("vdb/0001.vdb").exists());
    // A failed stage leaves the other method's surfaces: no tet meshes here.
    perifrac_ok(&["surface", out_s]);
    let (code, stderr) = outcome(&perifrac(&["surface", out_s, "--method", "embedded"]));
    assert_eq!(code, Some(2), "{stderr}");
    assert!(out.join("vdb/0002.vdb").is_file(), "{stderr}");
}
