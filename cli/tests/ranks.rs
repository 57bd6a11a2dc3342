//! `mpirun -np N perifrac run` (issue 35): a fracturing scene gives the bytes of one
//! process on 2 and 4 ranks (4 oversubscribed on this machine's 2 cores), a run
//! stopped on 2 ranks resumes on 2 or 3 to those bytes, and a fragment that spans the
//! ranks' particle ranges is one fragment; a tearing, diffusing membrane does the same
//! on 2 and 3 ranks. Loopback only (OpenMPI's shared memory).
#![cfg(feature = "mpi")]

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Output};

use perifrac_cache::ply::ParticleFrame;

mod common;

/// A glass wall hit by a ball, coarse (1,499 particles, 5 frames): bonds break and
/// crush (`critical_compression`), so every kind of per-bond state a step sends
/// between ranks changes; the split tet mesh is written.
const SCENE: &str = r#"[scene]
name = "ranks-test"
duration = 0.002
fps = 2500.0
gravity = [0.0, -9.81, 0.0]

[materials.glass]
density = 2200.0
bulk_modulus = 3.3e10
shear_modulus = 2.0e10
critical_stretch = 0.0005
critical_compression = 0.01

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
checkpoint_every = 2
preview = false
usd = false
surface = "none"
tets = true
"#;

/// The same wall, ductile: its bonds yield (Chen Eq. 13–16) before they break.
fn plastic_scene() -> String {
    SCENE.replace(
        "critical_stretch = 0.0005\ncritical_compression = 0.01",
        "critical_stretch = 0.002\nyield_stretch = 0.0004\nplastic_limit = 0.2",
    )
}

/// `perifrac ARGS --quiet`, on `ranks` ranks of `mpirun` (OpenMPI), one thread each.
fn on_ranks(ranks: usize, args: &[&str]) -> Output {
    let np = ranks.to_string();
    Command::new("mpirun")
        // This machine has 2 cores; the suite runs as root in CI.
        .args(["--oversubscribe", "--allow-run-as-root", "-np", &np])
        .arg(env!("CARGO_BIN_EXE_perifrac"))
        .args(args)
        .args(["--quiet", "--threads", "1"])
        .output()
        .expect("mpirun runs (scripts/setup.sh installs OpenMPI)")
}

/// `perifrac ARGS --quiet` in one process, without MPI.
fn one_process(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_perifrac"))
        .args(args)
        .arg("--quiet")
        .output()
        .unwrap()
}

fn ok(out: Output, what: &str) {
    assert!(
        out.status.success(),
        "{what}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The cache's frames, split tet meshes or sheets, and checkpoint (relative path →
/// bytes); a folder the scene does not write (`tets` of a membrane, `sheet` of a
/// solid) is left out, and [`assert_same`] compares which were written.
fn cache(root: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut all = BTreeMap::new();
    for dir in ["particles", "tets", "sheet", "checkpoint"] {
        let Ok(entries) = std::fs::read_dir(root.join(dir)) else {
            continue;
        };
        let mut names: Vec<_> = entries.flatten().map(|e| e.path()).collect();
        names.sort();
        for path in names {
            let name = path.strip_prefix(root).unwrap().display().to_string();
            all.insert(name, std::fs::read(&path).unwrap());
        }
    }
    assert!(all.len() > 5, "{}: {:?}", root.display(), all.keys());
    all
}

/// The manifest's steps, broken bonds and frame times, which every rank count agrees
/// on (its timings do not).
fn manifest_facts(root: &Path) -> (u64, u64, Vec<f64>) {
    let text = std::fs::read_to_string(root.join("manifest.json")).unwrap();
    let m: serde_json::Value = serde_json::from_str(&text).unwrap();
    (
        m["steps"].as_u64().unwrap(),
        m["broken_bonds"].as_u64().unwrap(),
        m["frame_times"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| t.as_f64().unwrap())
            .collect(),
    )
}

fn assert_same(one: &Path, other: &Path, what: &str) {
    let (a, b) = (cache(one), cache(other));
    assert_eq!(
        a.keys().collect::<Vec<_>>(),
        b.keys().collect::<Vec<_>>(),
        "{what}"
    );
    for (name, bytes) in &a {
        assert!(bytes == &b[name], "{what}: {name} differs");
    }
    assert_eq!(manifest_facts(one), manifest_facts(other), "{what}");
}

fn write_scene(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// `dir/name` as an argument.
fn out(dir: &Path, name: &str) -> String {
    dir.join(name).to_str().unwrap().to_string()
}

/// Runs `scene` in one process into `dir/one`.
fn run_whole(dir: &Path, scene: &str) {
    ok(
        one_process(&["run", scene, "-o", &out(dir, "one")]),
        "one process",
    );
}

/// Runs `scene` on `ranks` ranks into `dir/ranksN`: the bytes of `dir/one`.
fn same_on_ranks(dir: &Path, scene: &str, ranks: usize) {
    let name = format!("ranks{ranks}");
    ok(
        on_ranks(ranks, &["run", scene, "-o", &out(dir, &name)]),
        &format!("{ranks} ranks"),
    );
    assert_same(
        &dir.join("one"),
        &dir.join(&name),
        &format!("{scene} on {ranks} ranks"),
    );
}

/// Stops `scene` on 2 ranks after `frames` frames and resumes it on `ranks` ranks,
/// into `dir/resumed-on-N`: the bytes of `dir/one`.
fn same_after_resume(dir: &Path, scene: &str, frames: usize, ranks: usize) {
    let name = format!("resumed-on-{ranks}");
    let frames = frames.to_string();
    ok(
        on_ranks(
            2,
            &["run", scene, "-o", &out(dir, &name), "--frames", &frames],
        ),
        &format!("2 ranks, {frames} frames"),
    );
    ok(
        on_ranks(ranks, &["run", scene, "-o", &out(dir, &name), "--resume"]),
        &format!("resumed on {ranks} ranks"),
    );
    assert_same(
        &dir.join("one"),
        &dir.join(&name),
        &format!("{scene} stopped on 2 ranks, resumed on {ranks}"),
    );
}

#[test]
fn two_and_four_ranks_give_the_bytes_of_one_process() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "wall.toml", SCENE);
    run_whole(dir.path(), &scene);
    for ranks in [2, 4] {
        same_on_ranks(dir.path(), &scene, ranks);
    }
    let (_, broken, _) = manifest_facts(&dir.path().join("one"));
    assert!(broken > 10_000, "the wall breaks: {broken} bonds");
    // Rank 0 owns the first half of the particles (by bonds), rank 1 the second: a
    // fragment with particles in both is still one fragment, numbered as one process
    // numbers it (the bytes above), and the wall is in pieces.
    let last = ParticleFrame::read(&dir.path().join("ranks2/particles/0006.ply")).unwrap();
    let n = last.fragment.len();
    let spans = (0..n / 3).any(|i| (2 * n / 3..n).any(|j| last.fragment[i] == last.fragment[j]));
    assert!(spans, "a fragment spans both ranks' particles");
    let fragments: std::collections::BTreeSet<u32> =
        last.fragment.iter().map(|&f| f as u32).collect();
    assert!(fragments.len() > 1, "the wall breaks into pieces");
}

#[test]
fn a_run_stopped_on_two_ranks_resumes_on_two_or_three_to_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "wall.toml", &plastic_scene());
    run_whole(dir.path(), &scene);
    let last = ParticleFrame::read(&dir.path().join("one/particles/0006.ply")).unwrap();
    assert!(
        last.plastic.iter().any(|&p| p > 0.0),
        "the bonds yield, so plastic extensions go between the ranks"
    );
    for ranks in [2, 3] {
        same_after_resume(dir.path(), &scene, 3, ranks);
    }
}

/// A state-based membrane torn from a slit by its top edge's halves, with wet
/// patches whose moisture diffuses and swells it (Han Eq. 25–28; 460 particles, 5
/// frames): every value its shared pass sends (ϑ, forces, damage, diffusion rates,
/// broken bits) reaches the frames. Run whole, on 2 and 3 ranks, and stopped on 2
/// ranks after 2 frames then resumed on 3.
const MEMBRANE: &str = r#"[scene]
name = "ranks-membrane"
duration = 0.2
fps = 25.0
gravity = [0.0, -9.81, 0.0]

[materials.towel]
density = 100.0
youngs_modulus = 2.0e4
poisson_ratio = 0.3

[materials.towel.membrane]
fracture_energy = 2.4
diffusion_capacity = 1.0
diffusion_conductivity = 0.05
expansion = 0.3

[[body]]
name = "towel"
material = "towel"
model = "membrane"
shape = { type = "slab", center = [0.0, 0.1, 0.0], size = [0.2, 0.2, 0.0002] }
resolution = 0.01

[body.membrane]
membrane_model = "state"

[[body.anchor]]
region = { type = "box", center = [-0.05, 0.2, 0.0], size = [0.1, 0.04, 0.1] }
velocity = [-0.5, 0.0, -0.2]

[[body.anchor]]
region = { type = "box", center = [0.05, 0.2, 0.0], size = [0.1, 0.04, 0.1] }
velocity = [0.5, 0.0, 0.2]

[[body.crack]]
point = [0.001, 0.19, 0.0]
normal = [1.0, 0.0, 0.0]
region = { type = "box", center = [0.0, 0.19, 0.0], size = [0.02, 0.02, 0.1] }

[[body.membrane.source]]
scatter = { count = 5, radius = 0.03 }
value = 0.5

[output]
surface = "sheet"
preview = false
usd = false
checkpoint_every = 2
"#;

#[test]
fn a_membrane_on_two_and_three_ranks_and_resumed_gives_the_bytes_of_one_process() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "towel.toml", MEMBRANE);
    run_whole(dir.path(), &scene);
    let (_, broken, _) = manifest_facts(&dir.path().join("one"));
    assert!(broken > 500, "the towel tears: {broken} bonds");
    let last = ParticleFrame::read(&dir.path().join("one/particles/0006.ply")).unwrap();
    let (_, wet) = last
        .extra
        .iter()
        .find(|(name, _)| name == "quantity")
        .expect("a quantity column");
    let damp = wet.iter().filter(|&&q| q > 0.01 && q < 0.49).count();
    assert!(damp > 20, "moisture diffuses: {damp} particles partly wet");
    for ranks in [2, 3] {
        same_on_ranks(dir.path(), &scene, ranks);
    }
    same_after_resume(dir.path(), &scene, 2, 3);
}

/// A rank keeps the constants of its own bonds alone (sim/src/pd/coefficients.rs):
/// on 2 ranks each peaks at 0.77 of one process (116 against 150 MiB, a soft wall of
/// 2.75×10⁶ bonds, 36 bytes a bond at the peak of one process' set-up, OpenMPI's own
/// ~15 MiB a rank included). Every rank holding the whole model, as before, peaked
/// above one process.
#[test]
fn a_rank_holds_its_share_of_the_bonds() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(
        dir.path(),
        "wall.toml",
        "[scene]\nduration = 0.0001\nfps = 10000\ngravity = [0, 0, 0]\n\
         [materials.soft]\ndensity = 1000.0\nbulk_modulus = 1.0e7\nshear_modulus = 6.0e6\n\
         [[body]]\nmaterial = \"soft\"\nresolution = 0.035\n\
         shape = { type = \"box\", center = [0, 0.5, 0], size = [1.0, 1.0, 0.1] }\n\
         [output]\ncheckpoint_every = 0\npreview = false\nusd = false\nsurface = \"none\"\n",
    );
    let bin = env!("CARGO_BIN_EXE_perifrac");
    let (one_out, two_out) = (out(dir.path(), "one"), out(dir.path(), "two"));
    let run = |out| {
        [
            "run",
            &scene,
            "-o",
            out,
            "--frames",
            "1",
            "--quiet",
            "--threads",
            "1",
        ]
    };
    let one = common::peak_mib(bin, &run(&one_out));
    let mpirun = ["--oversubscribe", "--allow-run-as-root", "-np", "2", bin];
    let two = common::peak_mib("mpirun", &[&mpirun[..], &run(&two_out)].concat());
    println!("peak: one process {one:.1} MiB, a rank of 2 {two:.1} MiB");
    assert!(
        two < 0.85 * one,
        "a rank of 2 peaked at {two:.1} MiB, one process at {one:.1} MiB"
    );
}
