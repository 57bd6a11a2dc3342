//! Fuzzing of the mesh loaders (OBJ, ASCII and binary PLY, glTF and GLB): random
//! edits of small valid files must give a mesh or an error, never a panic, an
//! abort or an allocation beyond the file's own size.
//!
//! `cargo test` runs 256 cases; `PROPTEST_CASES=20000 cargo test -p perifrac-sim
//! --test fuzz_meshes --release` runs longer (docs/fuzz.md). Inputs that once failed
//! are in `tests/fuzz-corpus/meshes/` and replayed by `the_corpus_still_passes`.

use std::path::Path;

use perifrac_sim::geometry::mesh::{Placement, TriMesh};
use proptest::prelude::*;

/// A unit cube: 8 corners, 12 outward triangles.
const CORNERS: [[f32; 3]; 8] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [1.0, 1.0, 1.0],
    [0.0, 1.0, 1.0],
];
const TRIANGLES: [[u32; 3]; 12] = [
    [0, 2, 1],
    [0, 3, 2],
    [4, 5, 6],
    [4, 6, 7],
    [0, 1, 5],
    [0, 5, 4],
    [2, 3, 7],
    [2, 7, 6],
    [1, 2, 6],
    [1, 6, 5],
    [0, 4, 7],
    [0, 7, 3],
];

fn obj() -> Vec<u8> {
    let mut s = String::new();
    for c in CORNERS {
        s += &format!("v {} {} {}\n", c[0], c[1], c[2]);
    }
    for t in TRIANGLES {
        s += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    s.into_bytes()
}

fn ply_ascii() -> Vec<u8> {
    let mut s = "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n\
                 property float z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n"
        .to_string();
    for c in CORNERS {
        s += &format!("{} {} {}\n", c[0], c[1], c[2]);
    }
    for t in TRIANGLES {
        s += &format!("3 {} {} {}\n", t[0], t[1], t[2]);
    }
    s.into_bytes()
}

fn ply_binary() -> Vec<u8> {
    let mut b = b"ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\n\
                  property float y\nproperty float z\nelement face 12\n\
                  property list uchar int vertex_indices\nend_header\n"
        .to_vec();
    CORNERS
        .iter()
        .flatten()
        .for_each(|x| b.extend(x.to_le_bytes()));
    for t in TRIANGLES {
        b.push(3);
        t.iter().for_each(|i| b.extend(i.to_le_bytes()));
    }
    b
}

/// The cube's buffer: positions (96 bytes), then u32 indices (144 bytes).
fn buffer() -> Vec<u8> {
    let mut b = Vec::new();
    CORNERS
        .iter()
        .flatten()
        .for_each(|x| b.extend(x.to_le_bytes()));
    TRIANGLES
        .iter()
        .flatten()
        .for_each(|i| b.extend(i.to_le_bytes()));
    b
}

/// glTF JSON for the cube with `uri` as the buffer (none for GLB's binary chunk).
fn gltf_json(uri: Option<String>) -> String {
    let uri = uri.map_or(String::new(), |u| format!(r#""uri": "{u}", "#));
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
"nodes": [{{"mesh": 0, "children": [1]}}, {{"translation": [0, 0, 0]}}],
"meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}],
"buffers": [{{{uri}"byteLength": 240}}],
"bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 96}}, {{"buffer": 0, "byteOffset": 96, "byteLength": 144}}],
"accessors": [{{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1]}},
{{"bufferView": 1, "componentType": 5125, "count": 36, "type": "SCALAR"}}]}}"#
    )
}

fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |n, (i, &b)| n | (b as u32) << (16 - 8 * i));
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

fn gltf() -> Vec<u8> {
    gltf_json(Some(format!(
        "data:application/octet-stream;base64,{}",
        base64(&buffer())
    )))
    .into_bytes()
}

fn glb() -> Vec<u8> {
    let mut json = gltf_json(None).into_bytes();
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    let bin = buffer();
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut b = b"glTF".to_vec();
    b.extend(2u32.to_le_bytes());
    b.extend((total as u32).to_le_bytes());
    b.extend((json.len() as u32).to_le_bytes());
    b.extend(b"JSON");
    b.extend(json);
    b.extend((bin.len() as u32).to_le_bytes());
    b.extend(b"BIN\0");
    b.extend(bin);
    b
}

/// The format (file extension) and a valid file of it.
fn seeds() -> Vec<(&'static str, Vec<u8>)> {
    vec![
        ("obj", obj()),
        ("ply", ply_ascii()),
        ("ply", ply_binary()),
        ("gltf", gltf()),
        ("glb", glb()),
    ]
}

/// Loads `bytes` as a mesh file with extension `ext`; `Err` is fine, a panic not.
fn load(ext: &str, bytes: &[u8]) -> Result<TriMesh, String> {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join(format!("mesh.{ext}"));
    std::fs::write(&path, bytes).expect("write");
    TriMesh::load(&path, &Placement::default()).map_err(|e| e.to_string())
}

#[test]
fn the_seeds_load() {
    for (ext, bytes) in seeds() {
        let mesh = load(ext, &bytes).unwrap_or_else(|e| panic!("{ext}: {e}"));
        assert_eq!(mesh.triangles.len(), 12, "{ext}");
    }
}

#[derive(Debug, Clone)]
enum Edit {
    Set(usize, u8),
    Insert(usize, Vec<u8>),
    Delete(usize, usize),
    Truncate(usize),
    Number(usize, u64),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(at, b)| Edit::Set(at, b)),
        (any::<usize>(), prop::collection::vec(any::<u8>(), 1..8))
            .prop_map(|(at, b)| Edit::Insert(at, b)),
        (any::<usize>(), 1usize..32).prop_map(|(at, n)| Edit::Delete(at, n)),
        any::<usize>().prop_map(Edit::Truncate),
        (
            any::<usize>(),
            prop_oneof![Just(0u64), Just(u32::MAX as u64), any::<u64>()]
        )
            .prop_map(|(at, n)| Edit::Number(at, n)),
    ]
}

fn apply(mut b: Vec<u8>, edits: &[Edit]) -> Vec<u8> {
    for e in edits {
        let len = b.len();
        let at = |i: usize, n: usize| if n == 0 { 0 } else { i % n };
        match e {
            Edit::Set(i, v) if len > 0 => b[at(*i, len)] = *v,
            Edit::Insert(i, v) => {
                let i = at(*i, len + 1);
                b.splice(i..i, v.iter().copied());
            }
            Edit::Delete(i, n) if len > 0 => {
                let i = at(*i, len);
                b.drain(i..(i + n).min(len));
            }
            Edit::Truncate(i) => b.truncate(at(*i, len + 1)),
            Edit::Number(i, n) if len > 0 => {
                let i = at(*i, len);
                let digits = n.to_string().into_bytes();
                let end = (i + digits.len()).min(len);
                b.splice(i..end, digits);
            }
            _ => {}
        }
    }
    b
}

proptest! {
    #[test]
    fn mutated_meshes_never_panic(
        seed in 0usize..5,
        edits in prop::collection::vec(edit(), 1..5),
    ) {
        let (ext, good) = seeds().swap_remove(seed);
        let bytes = apply(good, &edits);
        let outcome = std::panic::catch_unwind(|| load(ext, &bytes).map(drop));
        prop_assert!(outcome.is_ok(), "{ext} panicked after {edits:?}");
    }
}

/// Files in `tests/fuzz-corpus/meshes/` load without a panic; `refuse-*` ones are
/// refused (among them the glTF whose node is its own child, which grew to 5 GB).
#[test]
fn the_corpus_still_passes() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-corpus/meshes");
    let mut replayed = 0;
    for entry in std::fs::read_dir(&root).expect("corpus") {
        let path = entry.expect("entry").path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let ext = path.extension().unwrap().to_string_lossy().to_string();
        let bytes = std::fs::read(&path).expect("corpus file");
        match std::panic::catch_unwind(|| load(&ext, &bytes).map(drop)) {
            Err(_) => panic!("{name} panics"),
            Ok(Ok(())) if name.starts_with("refuse-") => panic!("{name} was accepted"),
            Ok(_) => replayed += 1,
        }
    }
    assert!(
        replayed >= 3,
        "the corpus in {} is too small",
        root.display()
    );
}

/// A node that is its own child is refused at once, naming the node, before it adds
/// the mesh a second time.
#[test]
fn a_gltf_node_that_is_its_own_child_is_refused() {
    let looped = String::from_utf8(gltf())
        .unwrap()
        .replace(r#""children": [1]"#, r#""children": [0]"#);
    let e = load("gltf", looped.as_bytes()).expect_err("a cycle");
    assert!(e.contains("node 0 is reached twice"), "{e}");
}
