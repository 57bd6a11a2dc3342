//! End-to-end runs of the `sheet` surface method: a membrane film with a slit torn in
//! two by `perifrac run` with `surface = "sheet"`. The sheets are read back by an
//! independent PLY parser written here, every .glb passes the Khronos glTF validator,
//! and the last surface has one closed piece for every fragment that has triangles.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;

const SCENE: &str = r#"[scene]
name = "sheet-test"
duration = 4.0
fps = 1.0
gravity = [0.0, 0.0, 0.0]

[materials.film]
density = 5000.0
youngs_modulus = 2e4
poisson_ratio = 0.3

[materials.film.membrane]
fracture_energy = 11.3

[[body]]
material = "film"
model = "membrane"
resolution = 0.02
shape = { type = "slab", center = [0.0, 0.0, 0.0], size = [0.6, 0.001, 0.4] }

[[body.anchor]]
region = { type = "box", center = [-0.3, 0.0, 0.0], size = [0.05, 1.0, 1.0] }
velocity = [-0.05, 0.0, 0.0]

[[body.anchor]]
region = { type = "box", center = [0.3, 0.0, 0.0], size = [0.05, 1.0, 1.0] }
velocity = [0.05, 0.01, 0.0]

[[body.crack]]
point = [0.001, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]
region = { type = "box", center = [0.0, 0.0, 0.2], size = [0.1, 0.1, 0.2] }

[output]
surface = "sheet"
preview = false
checkpoint_every = 0
"#;

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

/// (header lines, data) of a binary PLY.
fn ply(path: &Path) -> (Vec<String>, Vec<u8>) {
    let bytes = std::fs::read(path).unwrap();
    let end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let header = String::from_utf8(bytes[..end].to_vec()).unwrap();
    (
        header.lines().map(str::to_string).collect(),
        bytes[end..].to_vec(),
    )
}

fn count(header: &[String], element: &str) -> usize {
    let prefix = format!("element {element} ");
    header
        .iter()
        .find_map(|l| l.strip_prefix(&prefix))
        .unwrap()
        .parse()
        .unwrap()
}

/// The triangles of a sheet file: after the vertices' float properties, a count byte
/// and three u32 indices a face.
fn sheet_triangles(path: &Path) -> (usize, Vec<[u32; 3]>) {
    let (header, data) = ply(path);
    let vertices = count(&header, "vertex");
    let floats = header
        .iter()
        .take_while(|l| !l.starts_with("element face"))
        .filter(|l| l.starts_with("property float"))
        .count();
    let faces = count(&header, "face");
    let start = vertices * 4 * floats;
    assert_eq!(data.len(), start + 13 * faces, "the sheet's size");
    let u32_at = |o: usize| u32::from_le_bytes(data[o..o + 4].try_into().unwrap());
    let triangles = (0..faces)
        .map(|f| {
            let o = start + 13 * f;
            assert_eq!(data[o], 3);
            [u32_at(o + 1), u32_at(o + 5), u32_at(o + 9)]
        })
        .collect();
    (vertices, triangles)
}

/// The `fragment` column of a particle PLY.
fn fragments(path: &Path) -> Vec<u32> {
    let (header, data) = ply(path);
    let n = count(&header, "vertex");
    let props: Vec<&str> = header
        .iter()
        .filter_map(|l| l.strip_prefix("property float "))
        .collect();
    let k = props.iter().position(|&p| p == "fragment").unwrap();
    (0..n)
        .map(|i| {
            let o = 4 * (i * props.len() + k);
            f32::from_le_bytes(data[o..o + 4].try_into().unwrap()) as u32
        })
        .collect()
}

/// Connected pieces of a triangle soup over `n` vertices (shared vertices join).
fn pieces(n: usize, triangles: &[[u32; 3]]) -> usize {
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(p: &mut [usize], mut v: usize) -> usize {
        while p[v] != v {
            p[v] = p[p[v]];
            v = p[v];
        }
        v
    }
    let mut used = BTreeSet::new();
    for t in triangles {
        for e in [(t[0], t[1]), (t[1], t[2])] {
            let (a, b) = (
                root(&mut parent, e.0 as usize),
                root(&mut parent, e.1 as usize),
            );
            parent[a] = b;
        }
        used.extend(t.iter().map(|&v| v as usize));
    }
    used.iter()
        .map(|&v| root(&mut parent, v))
        .collect::<BTreeSet<_>>()
        .len()
}

/// The triangles of every primitive of a .glb's first mesh (u32 indices).
fn glb_triangles(path: &Path) -> (usize, Vec<[u32; 3]>) {
    let bytes = std::fs::read(path).unwrap();
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let doc: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let bin = &bytes[20 + json_len + 8..];
    let mut triangles = Vec::new();
    let mut vertices = 0;
    for prim in doc["meshes"][0]["primitives"].as_array().unwrap() {
        let position = &doc["accessors"][prim["attributes"]["POSITION"].as_u64().unwrap() as usize];
        vertices = position["count"].as_u64().unwrap() as usize;
        let acc = &doc["accessors"][prim["indices"].as_u64().unwrap() as usize];
        assert_eq!(acc["componentType"], 5125, "u32 indices");
        let view = &doc["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
        let start = view["byteOffset"].as_u64().unwrap_or(0) as usize
            + acc["byteOffset"].as_u64().unwrap_or(0) as usize;
        let idx: Vec<u32> = (0..acc["count"].as_u64().unwrap() as usize)
            .map(|i| u32::from_le_bytes(bin[start + 4 * i..start + 4 * i + 4].try_into().unwrap()))
            .collect();
        triangles.extend(idx.chunks(3).map(|t| [t[0], t[1], t[2]]));
    }
    (vertices, triangles)
}

#[test]
fn a_torn_film_becomes_one_closed_sheet_surface_a_fragment() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("sheet.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let out = dir.path().join("out");
    let run = Command::new(env!("CARGO_BIN_EXE_perifrac"))
        .args([
            "run",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let frames = 5;
    for f in 1..=frames {
        let glb = out.join(format!("surface/{f:04}.glb"));
        let report = validate(&glb);
        assert_eq!(report["numErrors"], 0, "{glb:?}: {report}");
    }
    let animated = validate(&out.join("surface/animated.glb"));
    assert_eq!(animated["numErrors"], 0, "{animated}");

    let (n, first) = sheet_triangles(&out.join("sheet/0001.ply"));
    let (_, last) = sheet_triangles(&out.join(format!("sheet/{frames:04}.ply")));
    assert!(
        last.len() < first.len(),
        "triangles dropped where the film tore"
    );
    let fragment = fragments(&out.join(format!("particles/{frames:04}.ply")));
    assert_eq!(fragment.len(), n, "one sheet vertex a particle");
    let with_triangles: BTreeSet<u32> = last
        .iter()
        .flat_map(|t| t.iter().map(|&v| fragment[v as usize]))
        .collect();
    assert!(with_triangles.len() >= 2, "the film tore in two");
    let (vertices, shell) = glb_triangles(&out.join(format!("surface/{frames:04}.glb")));
    assert_eq!(vertices, 2 * n, "a top and a bottom vertex a particle");
    assert_eq!(
        pieces(vertices, &shell),
        with_triangles.len(),
        "one closed piece a fragment"
    );
}
