//! The life of a run: killed (SIGKILL, also in the middle of a write), stopped by
//! SIGTERM/SIGINT, out of disk space, rerun into a folder holding another cache, and
//! checked by `perifrac verify`. Every interrupted run is resumed and must give the
//! bytes of an uninterrupted one (the checkpoint file aside: it is resume state, and a
//! stopped run checkpoints where it stopped), `manifest.json` included but for its wall
//! times, with no temporary file left.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::perifrac;

/// A jelly cube dropped on the ground: 21 frames of 2,250 particles, long
/// enough (a second or two) to be stopped in the middle.
const SCENE: &str = r#"[scene]
name = "lifecycle"
duration = 0.05
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
resolution = 0.008
velocity = [0, -1, 0]

[[collider]]
type = "ground"

[output]
checkpoint_every = 4
preview = false
"#;

/// Frames of [`SCENE`]: 1 + duration × fps.
const FRAMES: usize = 21;

fn binary() -> Command {
    Command::new(env!("CARGO_BIN_EXE_perifrac"))
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// Writes [`SCENE`] with a static mesh collider beside the cube (the table of
/// assets/meshes/table.obj, 2 m away: it touches nothing), so that its
/// `colliders/mesh_1.ply` is among the bytes a resumed run must reproduce.
fn write_scene(dir: &Path) -> String {
    let path = dir.join("scene.toml");
    let table = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/meshes/table.obj");
    let collider = format!(
        "\n[[collider]]\ntype = \"mesh\"\npath = {:?}\ntranslation = [2.0, 0.0, 0.0]\n",
        table.to_string_lossy()
    );
    std::fs::write(&path, format!("{SCENE}{collider}")).expect("write scene");
    path.to_string_lossy().into_owned()
}

/// `perifrac run SCENE -o OUT` with `extra` flags, started in the background.
fn start(scene: &str, out: &Path, extra: &[&str]) -> Child {
    binary()
        .args(["run", scene, "-o", &out.to_string_lossy(), "--quiet"])
        .args(extra)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary starts")
}

fn signal(child: &Child, name: &str) {
    let status = Command::new("kill")
        .args([&format!("-{name}"), &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(status.success(), "kill -{name} failed");
}

/// Whether every thread of `child` has stopped (state T or t in /proc) or it has
/// ended. `kill -STOP` returns once the signal is sent; a thread running on the other
/// core can still finish a rename before it stops.
fn stopped(child: &Child) -> bool {
    let Ok(tasks) = std::fs::read_dir(format!("/proc/{}/task", child.id())) else {
        return true;
    };
    tasks.flatten().all(|task| {
        let stat = std::fs::read_to_string(task.path().join("stat")).unwrap_or_default();
        let state = stat
            .rsplit(')')
            .next()
            .and_then(|rest| rest.split_whitespace().next());
        matches!(state, None | Some("T" | "t" | "Z" | "X"))
    })
}

/// Waits (at most a minute) until `ready` holds, polling every millisecond.
fn wait_for(what: &str, mut ready: impl FnMut() -> bool) {
    let start = Instant::now();
    while !ready() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "timed out waiting for {what}"
        );
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// Every file under `root`, by relative path.
fn files(root: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        // A run may be creating (or a test removing) directories meanwhile.
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else {
                out.push(path.strip_prefix(root).unwrap_or(&path).to_path_buf());
            }
        }
    }
    out.sort();
    out
}

fn temporary_files(root: &Path) -> Vec<PathBuf> {
    files(root)
        .into_iter()
        .filter(|p| p.to_string_lossy().contains(".tmp-"))
        .collect()
}

fn manifest(root: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(root.join("manifest.json")).expect("manifest");
    serde_json::from_str(&text).expect("manifest is JSON")
}

/// The cache's bytes as compared between runs: every file but the checkpoint, and the
/// manifest without its wall times.
fn cache_bytes(root: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    files(root)
        .into_iter()
        .filter(|p| !p.starts_with("checkpoint"))
        .map(|p| {
            let bytes = if p == Path::new("manifest.json") {
                let mut m = manifest(root);
                m.as_object_mut().expect("object").remove("timings");
                serde_json::to_vec_pretty(&m).expect("json")
            } else {
                std::fs::read(root.join(&p)).expect("read")
            };
            (p, bytes)
        })
        .collect()
}

fn assert_same_cache(got: &Path, reference: &BTreeMap<PathBuf, Vec<u8>>, what: &str) {
    let got = cache_bytes(got);
    let names = |m: &BTreeMap<PathBuf, Vec<u8>>| m.keys().cloned().collect::<Vec<_>>();
    assert_eq!(names(&got), names(reference), "{what}: other files");
    for (name, bytes) in reference {
        assert!(got[name] == *bytes, "{what}: {} differs", name.display());
    }
}

/// The uninterrupted run of [`SCENE`].
fn reference(dir: &Path, scene: &str) -> BTreeMap<PathBuf, Vec<u8>> {
    let out = dir.join("reference");
    let r = perifrac(&["run", scene, "-o", &out.to_string_lossy()]);
    assert!(r.status.success(), "{}", text(&r));
    assert_eq!(manifest(&out)["status"], "complete");
    assert_eq!(
        manifest(&out)["frame_times"].as_array().map(Vec::len),
        Some(FRAMES)
    );
    cache_bytes(&out)
}

/// Resumes until the run completes (a run killed twice needs two resumes at most).
fn resume(scene: &str, out: &Path) {
    let r = perifrac(&["run", scene, "-o", &out.to_string_lossy(), "--resume"]);
    assert!(r.status.success(), "{}", text(&r));
    assert_eq!(manifest(out)["status"], "complete", "{}", text(&r));
}

#[test]
fn sigkill_anywhere_then_resume_gives_the_bytes_of_an_uninterrupted_run() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = write_scene(dir.path());
    let reference = reference(dir.path(), &scene);

    // Killed after frame 1, after frame 6 (between checkpoints), after frame 13.
    for frame in [1, 6, 13] {
        let out = dir.path().join(format!("killed-after-{frame}"));
        let mut child = start(&scene, &out, &[]);
        let next = out.join(format!("particles/{:04}.ply", frame + 1));
        wait_for(&format!("frame {}", frame + 1), || next.exists());
        child.kill().expect("SIGKILL");
        child.wait().expect("reaped");
        resume(&scene, &out);
        assert_same_cache(&out, &reference, &format!("killed near frame {frame}"));
        assert_eq!(temporary_files(&out), Vec::<PathBuf>::new());
    }

    // Killed in the middle of a write: stop the process (SIGSTOP) when a temporary
    // file shows, kill it if the file is still there, else let it go on and try again.
    let out = dir.path().join("killed-mid-write");
    let mut child = start(&scene, &out, &[]);
    let mut caught = None;
    while caught.is_none() && child.try_wait().expect("status").is_none() {
        if let Some(tmp) = temporary_files(&out).into_iter().next() {
            signal(&child, "STOP");
            wait_for("the run to stop", || stopped(&child));
            if out.join(&tmp).exists() {
                caught = Some(tmp);
            } else {
                signal(&child, "CONT");
            }
        }
    }
    let tmp = caught.expect("a write in flight was caught before the run ended");
    child.kill().expect("SIGKILL");
    child.wait().expect("reaped");
    assert!(
        out.join(&tmp).exists(),
        "the half-written file is left by the kill"
    );
    resume(&scene, &out);
    assert_same_cache(
        &out,
        &reference,
        &format!("killed writing {}", tmp.display()),
    );
    assert_eq!(
        temporary_files(&out),
        Vec::<PathBuf>::new(),
        "swept on resume"
    );
}

/// A run stopped by `name` after frame 5 or later.
fn stop_with(name: &str, expected_in_message: &str) {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = write_scene(dir.path());
    let reference = reference(dir.path(), &scene);
    let out = dir.path().join("out");
    let child = start(&scene, &out, &[]);
    wait_for("frame 5", || out.join("particles/0005.ply").exists());
    signal(&child, name);
    let r = child.wait_with_output().expect("exits");
    let err = String::from_utf8_lossy(&r.stderr).into_owned();
    assert_eq!(r.status.code(), Some(3), "{err}");
    assert!(err.contains(expected_in_message), "{err}");
    let command = format!("perifrac run {scene} -o {} --resume", out.display());
    assert!(err.contains(&command), "the resume command in:\n{err}");
    let m = manifest(&out);
    assert_eq!(m["status"], "interrupted", "{m}");
    let message = m["message"].as_str().expect("a message");
    assert!(message.contains(expected_in_message), "{message}");
    // The checkpoint is at the last frame on disk.
    let frames = m["frame_times"].as_array().expect("frames").len();
    assert!((5..FRAMES).contains(&frames), "{frames} frames");
    let checkpoint = std::fs::read(out.join("checkpoint/state.bin")).expect("checkpoint");
    let frame = u64::from_le_bytes(checkpoint[20..28].try_into().expect("8 bytes"));
    assert_eq!(frame as usize, frames, "checkpoint frame");
    assert_eq!(temporary_files(&out), Vec::<PathBuf>::new());
    resume(&scene, &out);
    assert_same_cache(&out, &reference, name);
}

/// A stop asked for while a frame's steps run checkpoints between two steps, and the
/// resume takes the rest of that frame's steps: the bytes of an uninterrupted run,
/// split tet mesh included (its crack-face set is the last frame's, not the bonds').
#[test]
fn a_stop_during_a_frame_checkpoints_between_steps_and_resumes_to_the_same_bytes() {
    let dir = tempfile::tempdir().expect("temp dir");
    // Five frames of many steps each (a frame takes most of the run's time), and a
    // cube that cracks on the ground with its split tet mesh written, so that a signal
    // lands among the steps after bonds broke.
    let path = dir.path().join("scene.toml");
    let long_frames = SCENE
        .replace("fps = 400", "fps = 80")
        .replace("velocity = [0, -1, 0]", "velocity = [0, -6, 0]")
        .replace("preview = false", "preview = false\nsurface = \"embedded\"");
    std::fs::write(&path, long_frames).expect("write scene");
    let scene = path.to_string_lossy().into_owned();
    let reference_out = dir.path().join("reference");
    let r = perifrac(&["run", &scene, "-o", &reference_out.to_string_lossy()]);
    assert!(r.status.success(), "{}", text(&r));
    let m = manifest(&reference_out);
    assert!(m["broken_bonds"].as_u64() > Some(0), "the cube cracks: {m}");
    let steps_per_frame = m["steps"].as_u64().expect("steps") / 4;
    let reference = cache_bytes(&reference_out);

    let mut landed = false;
    for attempt in 0..3 {
        let out = dir.path().join(format!("stopped-{attempt}"));
        let child = start(&scene, &out, &[]);
        wait_for("frame 2", || out.join("particles/0002.ply").exists());
        std::thread::sleep(Duration::from_millis(100));
        signal(&child, "TERM");
        let r = child.wait_with_output().expect("exits");
        let err = String::from_utf8_lossy(&r.stderr).into_owned();
        assert_eq!(r.status.code(), Some(3), "{err}");
        let m = manifest(&out);
        assert_eq!(m["status"], "interrupted", "{m}");
        let frames = m["frame_times"].as_array().expect("frames").len() as u64;
        let checkpoint = std::fs::read(out.join("checkpoint/state.bin")).expect("checkpoint");
        let word = |at: usize| u64::from_le_bytes(checkpoint[at..at + 8].try_into().expect("8"));
        let (frame, steps) = (word(20), word(28));
        assert_eq!(frame, frames, "the checkpoint's frame is the last on disk");
        let message = m["message"].as_str().expect("a message");
        if message.contains("stopped during frame") {
            let into = steps - (frame - 1) * steps_per_frame;
            assert!(
                (1..steps_per_frame).contains(&into),
                "{into} steps into a frame of {steps_per_frame}: {message}"
            );
            assert!(
                message.contains(&format!("after {into} of its")),
                "{message}"
            );
            landed = true;
        }
        resume(&scene, &out);
        assert_same_cache(&out, &reference, &format!("stopped: {message}"));
        assert_eq!(temporary_files(&out), Vec::<PathBuf>::new());
        if landed {
            break;
        }
    }
    assert!(
        landed,
        "no stop landed among a frame's steps in three tries"
    );
}

#[test]
fn sigterm_stops_cleanly_with_a_checkpoint_and_resumes_to_the_same_bytes() {
    stop_with("TERM", "SIGTERM");
}

#[test]
fn sigint_stops_cleanly_and_a_second_one_quits_at_once() {
    stop_with("INT", "SIGINT");

    // A second signal before the run has stopped quits at once. Two SIGINTs sent at
    // once may merge into one (a signal pending twice is delivered once), so the
    // second is a SIGTERM; both are sent while the process is stopped, so both are
    // waiting when it goes on. A run stops after one step, so on a loaded machine it
    // can finish its clean stop (exit 3) before the signal thread reads the second
    // signal: that attempt is retried, and the quit must be seen in three tries.
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = write_scene(dir.path());
    let mut quit = false;
    for attempt in 0..3 {
        let out = dir.path().join(format!("out-{attempt}"));
        let child = start(&scene, &out, &[]);
        wait_for("frame 2", || out.join("particles/0002.ply").exists());
        signal(&child, "STOP");
        wait_for("the run to stop", || stopped(&child));
        signal(&child, "INT");
        signal(&child, "TERM");
        signal(&child, "CONT");
        let r = child.wait_with_output().expect("exits");
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(temporary_files(&out), Vec::<PathBuf>::new());
        if r.status.code() == Some(3) {
            assert_eq!(manifest(&out)["status"], "interrupted", "{err}");
            continue;
        }
        assert!(
            matches!(r.status.code(), Some(130 | 143)),
            "exit {:?}: {err}",
            r.status.code()
        );
        assert!(err.contains("quitting at once"), "{err}");
        quit = true;
        break;
    }
    assert!(quit, "the second signal never quit at once in three tries");
}

/// A tmpfs mounted for the test (root only), unmounted on drop.
struct Tmpfs(PathBuf);

impl Tmpfs {
    fn mount(dir: &Path, bytes: u64) -> Option<Tmpfs> {
        std::fs::create_dir_all(dir).ok()?;
        let ok = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={bytes}"), "tmpfs"])
            .arg(dir)
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
        ok.then(|| Tmpfs(dir.to_path_buf()))
    }

    fn resize(&self, bytes: u64) {
        let ok = Command::new("mount")
            .args(["-o", &format!("remount,size={bytes}")])
            .arg(&self.0)
            .status()
            .is_ok_and(|s| s.success());
        assert!(ok, "remount");
    }
}

impl Drop for Tmpfs {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(&self.0).status();
    }
}

#[test]
fn a_full_disk_stops_cleanly_names_the_file_and_resumes_once_space_is_freed() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = write_scene(dir.path());
    let reference = reference(dir.path(), &scene);
    let total: u64 = reference.values().map(|b| b.len() as u64).sum();
    // Room for about half the cache (tmpfs counts whole pages).
    let mount = dir.path().join("small-disk");
    let Some(disk) = Tmpfs::mount(&mount, total / 2) else {
        eprintln!("skipped: cannot mount a tmpfs here (needs root)");
        return;
    };
    let out = mount.join("out");
    let r = perifrac(&["run", &scene, "-o", &out.to_string_lossy()]);
    let err = text(&r);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(err.contains("could not write"), "{err}");
    assert!(err.contains("No space left on device"), "{err}");
    assert_eq!(
        err.matches("os error").count(),
        1,
        "the OS's words once: {err}"
    );
    assert!(err.contains(" free and this file needs "), "{err}");
    assert!(
        !err.contains(".tmp-"),
        "the final file is named, not the temporary: {err}"
    );
    assert!(err.contains("--resume"), "{err}");
    assert_eq!(temporary_files(&out), Vec::<PathBuf>::new());
    let m = manifest(&out);
    assert_eq!(m["status"], "failed", "{m}");
    assert!(
        m["message"]
            .as_str()
            .is_some_and(|s| s.contains("No space left")),
        "{m}"
    );

    disk.resize(4 * total + (1 << 20));
    resume(&scene, &out);
    assert_same_cache(&out, &reference, "after a full disk");
    assert_eq!(temporary_files(&out), Vec::<PathBuf>::new());
}

#[test]
fn a_folder_holding_a_cache_is_resumed_or_replaced_never_mixed() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = write_scene(dir.path());
    let out = dir.path().join("out");
    let o = out.to_string_lossy().into_owned();
    let r = perifrac(&["run", &scene, "-o", &o, "--frames", "8"]);
    assert!(r.status.success(), "{}", text(&r));
    assert_eq!(manifest(&out)["status"], "interrupted");

    // A shorter rerun is refused, naming the folder and the ways out.
    let r = perifrac(&["run", &scene, "-o", &o, "--frames", "3"]);
    assert_eq!(r.status.code(), Some(2), "{}", text(&r));
    for needle in [o.as_str(), "--resume", "--force", "9 frames"] {
        assert!(text(&r).contains(needle), "'{needle}' in {}", text(&r));
    }
    // So is a resume that would stop before the frames on disk.
    let r = perifrac(&["run", &scene, "-o", &o, "--frames", "3", "--resume"]);
    assert_eq!(r.status.code(), Some(2), "{}", text(&r));
    assert!(text(&r).contains("already holds 9 frames"), "{}", text(&r));

    // --force replaces it: only the new frames remain.
    let r = perifrac(&["run", &scene, "-o", &o, "--frames", "3", "--force"]);
    assert!(r.status.success(), "{}", text(&r));
    let frames: Vec<PathBuf> = files(&out.join("particles"));
    assert_eq!(frames.len(), 4, "{frames:?}");
    assert_eq!(
        manifest(&out)["frame_times"].as_array().map(Vec::len),
        Some(4)
    );

    // Resumed to the end, then "already complete" without running again.
    resume(&scene, &out);
    let before = std::fs::metadata(out.join("manifest.json")).and_then(|m| m.modified());
    let r = perifrac(&["run", &scene, "-o", &o, "--resume"]);
    assert!(r.status.success(), "{}", text(&r));
    assert!(text(&r).contains("already complete"), "{}", text(&r));
    let after = std::fs::metadata(out.join("manifest.json")).and_then(|m| m.modified());
    assert_eq!(before.ok(), after.ok(), "nothing rewritten");

    // A manifest that does not read is not resumed.
    std::fs::write(out.join("manifest.json"), "{ \"scene\": ").expect("write");
    let r = perifrac(&["run", &scene, "-o", &o, "--resume"]);
    assert_eq!(r.status.code(), Some(2), "{}", text(&r));
    assert!(
        text(&r).contains("manifest.json") && text(&r).contains("--force"),
        "{}",
        text(&r)
    );
}

#[test]
fn a_scene_name_that_is_not_a_folder_name_is_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    for name in ["../escape", "/tmp/absolute", "", "..", "a/b"] {
        let text_of_scene = SCENE.replace("name = \"lifecycle\"", &format!("name = {name:?}"));
        let scene = dir.path().join("named.toml");
        std::fs::write(&scene, text_of_scene).expect("write");
        let r = binary()
            .args(["run", &scene.to_string_lossy(), "--quiet"])
            .current_dir(dir.path())
            .output()
            .expect("runs");
        assert_eq!(r.status.code(), Some(2), "{name:?}: {}", text(&r));
        assert!(text(&r).contains("name"), "{}", text(&r));
        assert!(!dir.path().join("out").exists() && !dir.path().join("escape").exists());
    }
}

#[test]
fn verify_names_a_deleted_frame_and_a_flipped_byte() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = write_scene(dir.path());
    let out = dir.path().join("out");
    let o = out.to_string_lossy().into_owned();
    let r = perifrac(&["run", &scene, "-o", &o, "--frames", "4"]);
    assert!(r.status.success(), "{}", text(&r));
    let r = perifrac(&["verify", &o]);
    assert_eq!(r.status.code(), Some(3), "unfinished: {}", text(&r));
    resume(&scene, &out);
    let r = perifrac(&["verify", &o]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r));
    assert!(text(&r).contains("clean, complete"), "{}", text(&r));

    let frame4 = std::fs::read(out.join("particles/0004.ply")).expect("read");
    std::fs::remove_file(out.join("particles/0004.ply")).expect("remove");
    let path = out.join("particles/0007.ply");
    let mut bytes = std::fs::read(&path).expect("read");
    let middle = bytes.len() / 2;
    bytes[middle] ^= 0x01;
    std::fs::write(&path, &bytes).expect("write");
    let r = perifrac(&["verify", &o]);
    assert_eq!(r.status.code(), Some(2), "{}", text(&r));
    let t = text(&r);
    assert!(t.contains("particles/0004.ply: missing"), "{t}");
    assert!(t.contains("particles/0007.ply: checksum"), "{t}");

    // A truncated frame: the same exit code from `surface` and `render`, each warning
    // first about what verify flags.
    std::fs::write(out.join("particles/0004.ply"), frame4).expect("write");
    bytes.truncate(bytes.len() - 100);
    std::fs::write(&path, &bytes).expect("write");
    let surface = perifrac(&["surface", &o, "--method", "vdb"]);
    let render = perifrac(&["render", &o, "--size", "32x24"]);
    for (what, r) in [("surface", &surface), ("render", &render)] {
        assert_eq!(r.status.code(), Some(2), "{what}: {}", text(r));
        assert!(text(r).contains("warning: "), "{what}: {}", text(r));
        assert!(text(r).contains("0007.ply"), "{what}: {}", text(r));
    }
}

/// `verify` also covers `scene.toml` and what the stages after the run leave (here the
/// previews `render` writes), as the manifest recorded them.
#[test]
fn verify_names_a_changed_scene_and_a_damaged_preview() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = write_scene(dir.path());
    let out = dir.path().join("out");
    let o = out.to_string_lossy().into_owned();
    let r = perifrac(&["run", &scene, "-o", &o]);
    assert!(r.status.success(), "{}", text(&r));
    let r = perifrac(&["render", &o, "--size", "32x24"]);
    assert!(r.status.success(), "{}", text(&r));
    assert!(
        manifest(&out)["files"]
            .as_object()
            .is_some_and(|f| f.contains_key("preview/0003.png") && f.contains_key("scene.toml")),
        "{}",
        manifest(&out)["files"]
    );
    let r = perifrac(&["verify", &o]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r));

    let preview = out.join("preview/0003.png");
    let mut bytes = std::fs::read(&preview).expect("read");
    let middle = bytes.len() / 2;
    bytes[middle] ^= 0x01;
    std::fs::write(&preview, &bytes).expect("write");
    let mut toml = std::fs::read_to_string(out.join("scene.toml")).expect("read");
    toml.push('\n');
    std::fs::write(out.join("scene.toml"), toml).expect("write");
    let r = perifrac(&["verify", &o]);
    assert_eq!(r.status.code(), Some(2), "{}", text(&r));
    let t = text(&r);
    assert!(t.contains("preview/0003.png"), "{t}");
    assert!(t.contains("scene.toml"), "{t}");
}
