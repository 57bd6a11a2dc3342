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

/// `perifrac run SCENE -o OUT --quiet`, which must succeed.
fn run(scene: &Path, out: &Path) {
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
}

/// `perifrac check SCENE`: its exit code and standard error.
fn check(scene: &Path) -> (Option<i32>, String) {
    let run = Command::new(env!("CARGO_BIN_EXE_perifrac"))
        .args(["check", scene.to_str().unwrap()])
        .output()
        .unwrap();
    (
        run.status.code(),
        String::from_utf8_lossy(&run.stderr).into_owned(),
    )
}

#[test]
fn a_torn_film_becomes_one_closed_sheet_surface_a_fragment() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("sheet.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let out = dir.path().join("out");
    run(&scene, &out);
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

/// An OBJ hemisphere cap of radius `r` about the origin, pole up (+y), `rings` rings
/// of `segments` vertices, wound outward: an open mesh with a circular rim.
fn hemisphere_obj(r: f64, rings: usize, segments: usize) -> String {
    let mut obj = format!("v 0 {r} 0\n");
    for i in 1..=rings {
        let polar = std::f64::consts::FRAC_PI_2 * i as f64 / rings as f64;
        for j in 0..segments {
            let azimuth = std::f64::consts::TAU * j as f64 / segments as f64;
            let (x, z) = (polar.sin() * azimuth.cos(), polar.sin() * azimuth.sin());
            obj += &format!("v {} {} {}\n", r * x, r * polar.cos(), r * z);
        }
    }
    let at = |i: usize, j: usize| 2 + (i - 1) * segments + j % segments;
    for j in 0..segments {
        obj += &format!("f 1 {} {}\n", at(1, j + 1), at(1, j));
    }
    for i in 1..rings {
        for j in 0..segments {
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
            obj += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
        }
    }
    obj
}

/// A hemisphere cap of film (a mesh sheet), its rim pulled down, heated at its pole
/// by a θ source: θ spreads and the cap swells.
fn cap_scene(mesh: &str) -> String {
    format!(
        r#"[scene]
name = "cap"
duration = 2.0
fps = 1.0
gravity = [0.0, 0.0, 0.0]

[materials.film]
density = 5000.0
youngs_modulus = 2e4
poisson_ratio = 0.3

[materials.film.membrane]
diffusion_conductivity = 0.05
expansion = 0.05

[[body]]
material = "film"
model = "membrane"
resolution = 0.03
shape = {{ type = "mesh", path = "{mesh}" }}

[body.membrane]
thickness = 0.001

[[body.membrane.source]]
region = {{ type = "sphere", center = [0.0, 0.15, 0.0], radius = 0.05 }}
rate = 1.0

[[body.anchor]]
region = {{ type = "box", center = [0.0, 0.0, 0.0], size = [1.0, 0.02, 1.0] }}
velocity = [0.0, -0.02, 0.0]

[output]
surface = "sheet"
preview = false
checkpoint_every = 0
usd = false
"#
    )
}

/// The JSON chunk and binary chunk of a .glb.
fn glb_chunks(path: &Path) -> (serde_json::Value, Vec<u8>) {
    let bytes = std::fs::read(path).unwrap();
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let doc = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    (doc, bytes[20 + json_len + 8..].to_vec())
}

/// Accessor `index` of a .glb read as f32 values.
fn glb_floats(doc: &serde_json::Value, bin: &[u8], index: &serde_json::Value) -> Vec<f32> {
    let acc = &doc["accessors"][index.as_u64().unwrap() as usize];
    let view = &doc["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
    let start = view["byteOffset"].as_u64().unwrap_or(0) as usize;
    let width = if acc["type"] == "VEC3" { 3 } else { 1 };
    (0..width * acc["count"].as_u64().unwrap() as usize)
        .map(|k| f32::from_le_bytes(bin[start + 4 * k..start + 4 * k + 4].try_into().unwrap()))
        .collect()
}

/// The `quantity` column of a particle PLY.
fn particle_quantity(path: &Path) -> Vec<f32> {
    let (header, data) = ply(path);
    let n = count(&header, "vertex");
    let props: Vec<&str> = header
        .iter()
        .filter_map(|l| l.strip_prefix("property float "))
        .collect();
    let k = props.iter().position(|&p| p == "quantity").unwrap();
    (0..n)
        .map(|i| {
            let o = 4 * (i * props.len() + k);
            f32::from_le_bytes(data[o..o + 4].try_into().unwrap())
        })
        .collect()
}

#[test]
fn a_heated_mesh_cap_carries_theta_in_its_sheet_glb_files() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("cap.obj"), hemisphere_obj(0.15, 6, 24)).unwrap();
    let scene = dir.path().join("cap.toml");
    std::fs::write(&scene, cap_scene("cap.obj")).unwrap();
    let out = dir.path().join("out");
    run(&scene, &out);
    let frames = 3;
    // The mesh sheet's triangles go through the sheet method like a lattice's.
    let (n, first) = sheet_triangles(&out.join("sheet/0001.ply"));
    assert!(
        first.len() > n,
        "{} triangles over {n} particles",
        first.len()
    );
    // θ over the run, from the particles: the range every colour refers to.
    let theta: Vec<Vec<f32>> = (1..=frames)
        .map(|f| particle_quantity(&out.join(format!("particles/{f:04}.ply"))))
        .collect();
    let lo = theta
        .iter()
        .flatten()
        .copied()
        .fold(f32::INFINITY, f32::min);
    let hi = theta
        .iter()
        .flatten()
        .copied()
        .fold(f32::NEG_INFINITY, f32::max);
    assert!(
        lo == 0.0 && hi > 0.5,
        "θ in [{lo}, {hi}]: the source heated the pole"
    );
    for f in 1..=frames {
        let path = out.join(format!("surface/{f:04}.glb"));
        let report = validate(&path);
        assert_eq!(report["numErrors"], 0, "{path:?}: {report}");
        let (doc, bin) = glb_chunks(&path);
        let mesh = &doc["meshes"][0];
        let range = &mesh["extras"]["quantity"]["range"];
        let range = [0, 1].map(|k| range[k].as_f64().unwrap() as f32);
        assert_eq!(range, [lo, hi]);
        let attributes = &mesh["primitives"][0]["attributes"];
        // Top and bottom copies of every particle carry its θ.
        let q = glb_floats(&doc, &bin, &attributes["_QUANTITY"]);
        assert_eq!(q, [theta[f - 1].clone(), theta[f - 1].clone()].concat());
        // The hottest particle is the map's yellow end, an unheated one its dark end,
        // in every frame: the range is the run's, not the frame's.
        let colours = glb_floats(&doc, &bin, &attributes["COLOR_0"]);
        for (i, &t) in q.iter().enumerate() {
            let c = &colours[3 * i..3 * i + 3];
            let brightness = c[0] + c[1] + c[2];
            if t == hi {
                assert!(c[0] > 0.8 && c[2] < 0.1, "θ = {t}: colour {c:?}");
            }
            if t == 0.0 {
                assert!(brightness < 0.2, "θ = 0: colour {c:?}");
            }
        }
    }
    // animated.glb: each frame's target takes θ and its colour to the frame's own.
    let path = out.join("surface/animated.glb");
    let report = validate(&path);
    assert_eq!(report["numErrors"], 0, "{report}");
    let (doc, bin) = glb_chunks(&path);
    let primitive = &doc["meshes"][0]["primitives"][0];
    let base = glb_floats(&doc, &bin, &primitive["attributes"]["_QUANTITY"]);
    assert_eq!(base, [theta[0].clone(), theta[0].clone()].concat());
    for f in 0..frames {
        let delta = glb_floats(&doc, &bin, &primitive["targets"][f]["_QUANTITY"]);
        let last: Vec<f32> = base.iter().zip(&delta).map(|(b, d)| b + d).collect();
        let expected = [theta[f].clone(), theta[f].clone()].concat();
        assert!(
            last.iter()
                .zip(&expected)
                .all(|(a, b)| (a - b).abs() < 1e-6),
            "frame {}",
            f + 1
        );
        assert!(primitive["targets"][f]["COLOR_0"].is_u64());
    }
}

#[test]
fn bad_sheet_meshes_are_refused_naming_the_file_and_the_fix() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        // Three faces on the edge 1–2.
        (
            "fin.obj",
            "v 0 0 0\nv 1 0 0\nv 0 0 1\nv 0 1 0\nv 0 -1 0\nf 1 2 3\nf 1 3 4\nf 1 5 3\n",
            "not a surface",
        ),
        // A face of zero area (three points on a line).
        (
            "flat.obj",
            "v 0 0 0\nv 1 0 0\nv 0 0 1\nv 2 0 0\nf 1 2 3\nf 1 2 4\n",
            "degenerate",
        ),
        ("empty.obj", "v 0 0 0\nv 1 0 0\n", "no triangles"),
        ("garbage.ply", "this is no PLY", "cannot read"),
    ];
    for (file, text, what) in cases {
        std::fs::write(dir.path().join(file), text).unwrap();
        let scene = dir.path().join("bad.toml");
        std::fs::write(&scene, cap_scene(file)).unwrap();
        let (code, stderr) = check(&scene);
        assert_eq!(code, Some(2), "{file}: {stderr}");
        assert!(
            stderr.contains(file) && stderr.contains(what),
            "{file}: {stderr}"
        );
    }
    // A mesh membrane without its thickness names the key.
    std::fs::write(dir.path().join("cap.obj"), hemisphere_obj(0.15, 3, 8)).unwrap();
    let scene = dir.path().join("bad.toml");
    std::fs::write(
        &scene,
        cap_scene("cap.obj").replace("thickness = 0.001", ""),
    )
    .unwrap();
    let (code, stderr) = check(&scene);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("membrane.thickness"), "{stderr}");
}

/// `perifrac check` on a membrane scene reports the sheet's particles, not an empty tet
/// mesh ("0 particles, mean edge 0.0000 m, dihedral angles 0.0°–0.0°", as it did).
#[test]
fn check_reports_a_membrane_bodys_particles() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("sheet.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let run = Command::new(env!("CARGO_BIN_EXE_perifrac"))
        .args(["check", scene.to_str().unwrap()])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success(), "{stdout}");
    let total = stdout
        .lines()
        .find_map(|l| l.trim().strip_prefix("particles:"))
        .map(|n| n.trim().to_string())
        .expect("a particle count");
    assert_ne!(total, "0", "{stdout}");
    assert!(
        stdout.contains(&format!(": {total} membrane particles (a sheet)")),
        "{stdout}"
    );
    assert!(!stdout.contains("dihedral"), "{stdout}");
}
