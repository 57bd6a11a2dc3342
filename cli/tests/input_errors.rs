//! Errors and checks that used to pass silently or say the wrong thing (issue 34, item
//! 7), each with the input that showed it: a manifest that contradicts its frames,
//! missing input files (exit 1 where bad input is 2), `perifrac check` on MPM bodies,
//! `--frames N` and what it writes, the memory refusal under `ulimit -v`, a build
//! without MPI started as one of several ranks, a body that starts inside a collider.

use std::path::Path;
use std::process::Command;

mod common;
use common::{outcome, perifrac};

/// A small cube dropped on the ground (one collider), with the embedded surface (so
/// the cache has tet frames): 5 frames.
const SCENE: &str = r#"[scene]
name = "errors"
duration = 0.01
fps = 400

[materials.jelly]
density = 1000.0
youngs_modulus = 1.0e5
poisson_ratio = 0.3

[[body]]
name = "cube"
material = "jelly"
shape = { type = "box", center = [0, 0.03, 0], size = [0.05, 0.05, 0.05] }
resolution = 0.01
velocity = [0, -1, 0]

[[collider]]
type = "ground"

[output]
surface = "embedded"
checkpoint_every = 0
preview = false
"#;

/// The cache of [`SCENE`] in `dir/out`.
fn cache(dir: &Path) -> String {
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let out = dir.join("out");
    let run = perifrac(&["run", scene.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(run.status.success(), "{}", outcome(&run).1);
    out.to_string_lossy().into_owned()
}

/// Copies the cache `from` to `to`.
fn copy(from: &str, to: &Path) -> String {
    let status = Command::new("cp")
        .args(["-r", from, to.to_str().unwrap()])
        .status()
        .unwrap();
    assert!(status.success());
    to.to_string_lossy().into_owned()
}

/// Rewrites `out/manifest.json` through `edit`.
fn edit_manifest(out: &str, edit: impl Fn(&mut serde_json::Value)) {
    let path = Path::new(out).join("manifest.json");
    let mut manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    edit(&mut manifest);
    std::fs::write(&path, manifest.to_string()).unwrap();
}

/// `verify`, `render` and `surface` on a cache whose manifest says something its frames
/// do not: exit 2, naming the manifest (or frame) and the fix. They used to exit 0 and
/// print nothing (render drew the colliders of the wrong frames).
#[test]
fn a_manifest_that_contradicts_its_frames_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let good = cache(dir.path());
    type Edit = fn(&mut serde_json::Value);
    let edits: [(&str, Edit, &str); 3] = [
        (
            "centres",
            |m| {
                let rows = m["collider_centers"].as_array_mut().unwrap();
                rows.truncate(rows.len() - 2);
            },
            "collider_centers has 3 rows for its 5 frames",
        ),
        (
            "colliders",
            |m| {
                for row in m["collider_centers"].as_array_mut().unwrap() {
                    row.as_array_mut()
                        .unwrap()
                        .push(serde_json::json!([0.0, 1.0, 0.0]));
                }
            },
            "for the scene's 1 colliders",
        ),
        (
            "count",
            |m| {
                let n = m["particles"].as_u64().unwrap() + 7;
                m["particles"] = n.into();
                m["bodies"][0]["particles"] = n.into();
            },
            "where manifest.json says particles =",
        ),
    ];
    for (name, edit, expected) in edits {
        let out = copy(&good, &dir.path().join(name));
        edit_manifest(&out, edit);
        let mut commands = vec![vec!["verify", out.as_str()]];
        if cfg!(feature = "gl") {
            commands.push(vec!["render", &out, "--frame", "2", "--size", "32x24"]);
        }
        commands.push(vec!["surface", &out, "--method", "embedded"]);
        for args in commands {
            let result = perifrac(&args);
            let (code, stderr) = outcome(&result);
            let stdout_and_err = format!("{}{stderr}", String::from_utf8_lossy(&result.stdout));
            assert_eq!(code, Some(2), "{name}: {args:?}: {stderr}");
            assert!(
                stdout_and_err.contains(expected) && stdout_and_err.contains("--force"),
                "{name}: {args:?}: {stdout_and_err}"
            );
        }
    }
}

/// A missing scene, manifest, particle or tet file is bad input (exit 2) naming the
/// file and the fix; it used to exit 1 with the OS's words only.
#[test]
fn missing_input_files_exit_with_2() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("no-such-scene.toml");
    let (code, stderr) = outcome(&perifrac(&["run", missing.to_str().unwrap()]));
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains("no-such-scene.toml: no such file") && stderr.contains("scene file"),
        "{stderr}"
    );
    let good = cache(dir.path());
    let mut cases = vec![
        ("manifest", "manifest.json", "embedded"),
        ("tets", "tets/0002.vtu", "embedded"),
    ];
    if cfg!(feature = "openvdb") {
        cases.push(("particles", "particles/0002.ply", "vdb"));
    }
    for (name, file, method) in cases {
        let out = copy(&good, &dir.path().join(name));
        std::fs::remove_file(Path::new(&out).join(file)).unwrap();
        let (code, stderr) = outcome(&perifrac(&["surface", &out, "--method", method]));
        assert_eq!(code, Some(2), "{file}: {stderr}");
        assert!(
            stderr.contains(&format!("{file}: no such file")) && stderr.contains("--force"),
            "{file}: {stderr}"
        );
    }
}

/// A body that starts inside a collider is refused, naming the collider and the
/// fix: a fuzzed glass wall with its ground at 1e308 m ran `perifrac check` for
/// minutes with every particle a contact pair, and at 5 m it passed silently.
#[test]
fn a_body_that_starts_inside_a_collider_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    for height in ["5.0", "1e308"] {
        let scene = dir.path().join(format!("ground-{height}.toml"));
        let text = SCENE.replace(
            "type = \"ground\"",
            &format!("type = \"ground\"\nheight = {height}"),
        );
        std::fs::write(&scene, text).unwrap();
        for command in ["check", "run"] {
            let (code, stderr) = outcome(&perifrac(&[command, scene.to_str().unwrap()]));
            assert_eq!(code, Some(2), "{command}, ground at {height} m: {stderr}");
            assert!(
                stderr.contains("collider 0: the ground at height")
                    && stderr.contains("starts")
                    && stderr.contains("move the collider"),
                "{command}, ground at {height} m: {stderr}"
            );
        }
    }
}

/// `perifrac check` on an MPM body printed "0 particles" and "0.0 MiB": the model
/// seeds its particles (2³ a cell), so they are counted after seeding; and one placed
/// beyond the grid's reach is refused.
#[test]
fn check_counts_mpm_particles() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("mpm.toml");
    std::fs::write(
        &scene,
        r#"[scene]
name = "mpm"
duration = 0.02
fps = 100.0

[materials.snow]
density = 400.0
youngs_modulus = 1.4e5
poisson_ratio = 0.2

[[body]]
name = "snow"
model = "mpm"
material = "snow"
resolution = 0.01
shape = { type = "box", center = [0.0, 0.1, 0.0], size = [0.04, 0.04, 0.04] }

[output]
tets = false
surface = "none"
"#,
    )
    .unwrap();
    let out = perifrac(&["check", scene.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", outcome(&out).1);
    // Placed 3.5e9 m out (a fuzzed scene), beyond the grid's keys: it blew up at step
    // 16 (exit 1); now it is refused as bad input.
    let far = dir.path().join("far.toml");
    let text = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(&far, text.replace("[0.0, 0.1, 0.0]", "[0.0, 0.1, 3.5e9]")).unwrap();
    let (code, stderr) = outcome(&perifrac(&["check", far.to_str().unwrap()]));
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains("body 'snow'") && stderr.contains("beyond the MPM grid's reach"),
        "{stderr}"
    );
    // 4 cells a side of 0.01 m, 2³ particles a cell.
    assert!(
        stdout.contains("body snow: 512 MPM particles") && stdout.contains("particles: 512"),
        "{stdout}"
    );
    let mib: f64 = stdout
        .lines()
        .find_map(|l| l.trim().strip_prefix("memory:"))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|x| x.parse().ok())
        .unwrap_or_else(|| panic!("no memory line: {stdout}"));
    assert!(mib > 0.05, "{stdout}");
}

/// `--frames N` simulates N frames after the initial one: N + 1 files, and the
/// manifest's message says so. It used to say "stopped after frame 3 as asked
/// (--frames 2)", reading as if frame 3 were one too many.
#[test]
fn frames_n_writes_n_frames_after_the_initial_one_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    std::fs::write(
        &scene,
        SCENE.replace("surface = \"embedded\"", "surface = \"none\""),
    )
    .unwrap();
    let out = dir.path().join("out");
    let run = perifrac(&[
        "run",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--frames",
        "2",
    ]);
    let (code, stderr) = outcome(&run);
    assert_eq!(code, Some(0), "{stderr}");
    let mut files: Vec<String> = std::fs::read_dir(out.join("particles"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert_eq!(files, ["0001.ply", "0002.ply", "0003.ply"]);
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    let message = manifest["message"].as_str().unwrap();
    assert!(
        message.contains("--frames 2: 2 frames after the initial one, files 0001 to 0003"),
        "{message}"
    );
    let help = Command::new(env!("CARGO_BIN_EXE_perifrac"))
        .args(["run", "--help"])
        .output()
        .unwrap();
    let help = String::from_utf8_lossy(&help.stdout);
    assert!(help.contains("N + 1 frame files"), "{help}");
}

/// The memory refusal honours the process's own limit (`ulimit -v`), not only the
/// machine's available memory: a scene estimated at 1.6 GiB under a 1 GiB limit is
/// refused before meshing (exit 2) naming the limit; it used to start and run out.
#[test]
fn the_memory_refusal_honours_ulimit_v() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("big.toml");
    std::fs::write(
        &scene,
        r#"[scene]
name = "big"
duration = 0.001
fps = 1000.0

[materials.m]
density = 1000.0
youngs_modulus = 1e6
poisson_ratio = 0.3

[[body]]
material = "m"
shape = { type = "box", center = [0, 0, 0], size = [1.0, 1.0, 0.1] }
resolution = 0.015
"#,
    )
    .unwrap();
    let out_dir = dir.path().join("out");
    let scene = scene.to_str().unwrap();
    let runs = [
        ("check", vec!["check", scene]),
        ("run", vec!["run", scene, "-o", out_dir.to_str().unwrap()]),
    ];
    for (command, args) in runs {
        let out = Command::new("sh")
            .arg("-c")
            .arg("ulimit -v 1048576 && exec \"$@\"")
            .arg("sh")
            .arg(env!("CARGO_BIN_EXE_perifrac"))
            .args(args)
            .arg("--quiet")
            .output()
            .unwrap();
        let (code, stderr) = outcome(&out);
        assert_eq!(code, Some(2), "{command}: {stderr}");
        assert!(
            stderr.contains("1.0 GiB") && stderr.contains("ulimit -v"),
            "{command}: {stderr}"
        );
    }
}

/// Started by `mpirun -np 2` (OpenMPI's variable says so), a build without the `mpi`
/// feature would run the scene twice into one cache: it refuses (exit 2) and says how
/// to build it, before it writes anything.
#[cfg(not(feature = "mpi"))]
#[test]
fn a_build_without_mpi_refuses_to_run_as_one_of_several_ranks() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let out = dir.path().join("out");
    let run = Command::new(env!("CARGO_BIN_EXE_perifrac"))
        .args(["run", scene.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .env("OMPI_COMM_WORLD_SIZE", "2")
        .output()
        .unwrap();
    let (code, stderr) = outcome(&run);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("--features mpi"), "{stderr}");
    assert!(!out.exists(), "nothing written");
    // One rank is a plain run.
    let run = Command::new(env!("CARGO_BIN_EXE_perifrac"))
        .args(["run", scene.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .args(["--frames", "1", "--quiet"])
        .env("OMPI_COMM_WORLD_SIZE", "1")
        .output()
        .unwrap();
    assert_eq!(outcome(&run).0, Some(0), "{}", outcome(&run).1);
}
