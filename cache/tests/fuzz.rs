//! Fuzzing of every reader of outside input in the cache crate: the scene parser,
//! the particle PLY, the manifest, the split tet mesh (VTU), a mesh collider's PLY
//! and the checkpoint container. Each target feeds random and mutated inputs to the reader and asks
//! only that it returns (an error or a value), never panics; a checkpoint changed
//! anywhere must also be refused.
//!
//! `cargo test` runs a bounded number of cases (256 a target, a few seconds);
//! `PROPTEST_CASES=100000 cargo test -p perifrac-cache --test fuzz --release` runs
//! longer (docs/fuzz.md). Inputs that once failed are kept in
//! `tests/fuzz-corpus/<target>/` and replayed by `the_corpus_still_passes`.

use std::path::{Path, PathBuf};

use perifrac_cache::checkpoint::{Checkpoint, Encoder};
use perifrac_cache::collider::ColliderMesh;
use perifrac_cache::manifest::Manifest;
use perifrac_cache::ply::ParticleFrame;
use perifrac_cache::scene::Scene;
use perifrac_cache::vtu::TetFrame;
use proptest::prelude::*;

/// A valid scene using most tables, the seed of the scene mutations.
const SCENE: &str = r#"[scene]
name = "fuzz"
duration = 0.01
fps = 1000
gravity = [0, -9.81, 0]

[materials.glass]
density = 2200.0
youngs_modulus = 6.0e10
poisson_ratio = 0.2
critical_stretch = 0.0005
yield_stretch = 0.01

[[body]]
material = "glass"
resolution = 0.01
shape = { type = "difference", base = { type = "box", center = [0, 0.1, 0], size = [0.2, 0.2, 0.02] }, minus = { type = "sphere", center = [0, 0.2, 0], radius = 0.03 } }

[[body.anchor]]
region = { type = "box", center = [0, 0, 0], size = [0.3, 0.02, 0.1] }
until = 0.005

[[body.crack]]
point = [0, 0.1, 0]
normal = [1, 0, 0]
region = { type = "cylinder", center = [0, 0.1, 0], radius = 0.05, height = 0.05, axis = "z" }

[[collider]]
type = "sphere"
center = [0, 0.1, -0.05]
radius = 0.02
velocity = [0, 0, 30]
mass = 0.1

[output]
checkpoint_every = 2
"#;

/// The reader of each target, taking the input's bytes; `Err` is fine, a panic not.
fn read(target: &str, bytes: &[u8]) -> Result<(), String> {
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let file = |name: &str| -> PathBuf {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).expect("temp file");
        path
    };
    match target {
        "scene" => Scene::load(&file("scene.toml"))
            .map(drop)
            .map_err(|e| e.to_string()),
        "particles" => ParticleFrame::from_bytes(bytes).map(drop),
        "manifest" => Manifest::read(&file("manifest.json"))
            .map(drop)
            .map_err(|e| e.to_string()),
        "vtu" => TetFrame::read(&file("0001.vtu"))
            .map(drop)
            .map_err(|e| e.to_string()),
        "checkpoint" => Checkpoint::decode(bytes, Path::new("state.bin"))
            .map(drop)
            .map_err(|e| e.to_string()),
        "collider" => ColliderMesh::from_bytes(bytes).map(drop),
        other => panic!("no fuzz target {other}"),
    }
}

/// A valid input of each target, the seed of its mutations.
fn seed(target: &str) -> Vec<u8> {
    match target {
        "scene" => SCENE.as_bytes().to_vec(),
        "particles" => ParticleFrame {
            frame: 3,
            time: 0.25,
            position: vec![[0.0, 1.0, 2.0], [3.0, 4.0, 5.0]],
            velocity: vec![[0.5; 3]; 2],
            damage: vec![0.0, 1.0],
            plastic: vec![0.0; 2],
            material: vec![0.0; 2],
            fragment: vec![0.0, 1.0],
            extra: vec![("quantity".into(), vec![1.5, 2.5])],
        }
        .to_bytes(),
        "manifest" => Manifest {
            scene: "fuzz".into(),
            frame_times: vec![0.0, 0.001],
            collider_centers: vec![vec![[0.0; 3]], vec![[0.0, 0.0, 0.03]]],
            status: perifrac_cache::manifest::Status::Complete,
            ..Manifest::default()
        }
        .to_json()
        .into_bytes(),
        "vtu" => TetFrame {
            points: vec![
                [0.0; 3],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [1.0; 3],
            ],
            tets: vec![[0, 1, 2, 3], [4, 1, 2, 3]],
            particle: vec![0, 1],
            damage: vec![0.0, 0.5],
            parent: vec![-1, -1, -1, -1, 0],
        }
        .to_bytes(),
        "checkpoint" => {
            let mut e = Encoder::new();
            e.put_f64x3_slice(&[[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
            e.put_u32_slice(&[1, 0]);
            e.put_f64(0.5);
            Checkpoint {
                scene_hash: 7,
                frame: 2,
                steps: 40,
                broken_bonds: 1,
                time: 0.002,
                payload: e.finish(),
            }
            .encode()
        }
        "collider" => ColliderMesh {
            positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
            pivot: [0.0, 0.15, 0.0],
        }
        .to_bytes(),
        other => panic!("no fuzz target {other}"),
    }
}

const TARGETS: [&str; 6] = [
    "scene",
    "particles",
    "manifest",
    "vtu",
    "checkpoint",
    "collider",
];

/// One edit of an input: overwrite, insert or delete bytes at a position (taken
/// modulo the length), or cut the input there.
#[derive(Debug, Clone)]
enum Edit {
    Flip(usize, u8),
    Set(usize, u8),
    Insert(usize, Vec<u8>),
    Delete(usize, usize),
    Truncate(usize),
    /// An ASCII number written over the input (counts and lengths in headers).
    Number(usize, u64),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<usize>(), 0u8..8).prop_map(|(at, bit)| Edit::Flip(at, bit)),
        (any::<usize>(), any::<u8>()).prop_map(|(at, b)| Edit::Set(at, b)),
        (any::<usize>(), prop::collection::vec(any::<u8>(), 1..16))
            .prop_map(|(at, b)| Edit::Insert(at, b)),
        (any::<usize>(), 1usize..64).prop_map(|(at, n)| Edit::Delete(at, n)),
        any::<usize>().prop_map(Edit::Truncate),
        (
            any::<usize>(),
            prop_oneof![
                Just(0u64),
                Just(u32::MAX as u64),
                Just(u64::MAX),
                any::<u64>()
            ]
        )
            .prop_map(|(at, n)| Edit::Number(at, n)),
    ]
}

fn apply(mut bytes: Vec<u8>, edits: &[Edit]) -> Vec<u8> {
    for e in edits {
        let at = |i: usize, len: usize| if len == 0 { 0 } else { i % len };
        let len = bytes.len();
        match e {
            Edit::Flip(i, bit) if len > 0 => bytes[at(*i, len)] ^= 1 << bit,
            Edit::Set(i, b) if len > 0 => bytes[at(*i, len)] = *b,
            Edit::Insert(i, b) => {
                let i = at(*i, len + 1);
                bytes.splice(i..i, b.iter().copied());
            }
            Edit::Delete(i, n) if len > 0 => {
                let i = at(*i, len);
                bytes.drain(i..(i + n).min(len));
            }
            Edit::Truncate(i) => bytes.truncate(at(*i, len + 1)),
            Edit::Number(i, n) if len > 0 => {
                let i = at(*i, len);
                let digits = n.to_string().into_bytes();
                let end = (i + digits.len()).min(len);
                bytes.splice(i..end, digits);
            }
            _ => {}
        }
    }
    bytes
}

/// The first bytes of an input, for messages.
fn shown(bytes: &[u8]) -> String {
    String::from_utf8_lossy(&bytes[..bytes.len().min(200)])
        .escape_debug()
        .to_string()
}

proptest! {
    #[test]
    fn mutated_inputs_never_panic(
        target in prop::sample::select(TARGETS.to_vec()),
        edits in prop::collection::vec(edit(), 1..6),
    ) {
        let bytes = apply(seed(target), &edits);
        let outcome = std::panic::catch_unwind(|| read(target, &bytes));
        prop_assert!(outcome.is_ok(), "{target} panicked on {edits:?}: {}", shown(&bytes));
    }

    #[test]
    fn random_inputs_never_panic(
        target in prop::sample::select(TARGETS.to_vec()),
        bytes in prop::collection::vec(any::<u8>(), 0..512),
    ) {
        let outcome = std::panic::catch_unwind(|| read(target, &bytes));
        prop_assert!(outcome.is_ok(), "{target} panicked on {}", shown(&bytes));
    }

    /// A checkpoint changed in any way is refused (its length and CRC-32 cover every
    /// byte), never read as another state.
    #[test]
    fn changed_checkpoints_are_refused(edits in prop::collection::vec(edit(), 1..4)) {
        let good = seed("checkpoint");
        let bytes = apply(good.clone(), &edits);
        prop_assume!(bytes != good);
        prop_assert!(read("checkpoint", &bytes).is_err(), "accepted after {edits:?}");
    }
}

/// Every input in `tests/fuzz-corpus/<target>/` (inputs that once panicked or were
/// accepted when they should not have been) is read without a panic; files named
/// `refuse-*` must also be refused.
#[test]
fn the_corpus_still_passes() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-corpus");
    let mut replayed = 0;
    for target in TARGETS {
        let Ok(entries) = std::fs::read_dir(root.join(target)) else {
            continue;
        };
        for entry in entries {
            let path = entry.expect("corpus entry").path();
            let bytes = std::fs::read(&path).expect("corpus file");
            let outcome = std::panic::catch_unwind(|| read(target, &bytes));
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            match outcome {
                Err(_) => panic!("{target}: {name} panics"),
                Ok(Ok(())) if name.starts_with("refuse-") => {
                    panic!("{target}: {name} was accepted")
                }
                Ok(_) => replayed += 1,
            }
        }
    }
    assert!(replayed > 0, "the corpus in {} is empty", root.display());
}
