use super::*;

use std::path::Path;
use std::process::Command;

/// A tetrahedron, counter-clockwise from outside, with face-averaged normals.
fn tetrahedron() -> (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<u32>) {
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let n = p
        .iter()
        .map(|q: &[f32; 3]| {
            let c = [q[0] - 0.25, q[1] - 0.25, q[2] - 0.25];
            let l = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
            [c[0] / l, c[1] / l, c[2] / l]
        })
        .collect();
    (p, n, vec![0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3])
}

/// Runs the Khronos validator (tools/gltf-validator, installed by scripts/setup.sh)
/// and returns its report.
fn validate(file: &Path) -> serde_json::Value {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tools/gltf-validator/validate.mjs");
    let out = Command::new("node")
        .arg(&script)
        .arg(file)
        .output()
        .expect("node runs (scripts/setup.sh installs it and the validator)");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        !stdout.trim().is_empty(),
        "the validator printed nothing: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_str(stdout.trim()).expect("a JSON report")
}

#[test]
fn layout_of_the_binary() {
    let (p, n, i) = tetrahedron();
    let glb = to_glb(&[plain("tet", &p, &n, &i)]).expect("valid mesh");
    assert_eq!(&glb[..4], b"glTF");
    assert_eq!(
        u32::from_le_bytes(glb[8..12].try_into().unwrap()) as usize,
        glb.len()
    );
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    assert_eq!(json_len % 4, 0);
    let doc: serde_json::Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
    assert_eq!(
        doc["accessors"][0]["min"],
        serde_json::json!([0.0, 0.0, 0.0])
    );
    assert_eq!(
        doc["accessors"][0]["max"],
        serde_json::json!([1.0, 1.0, 1.0])
    );
    assert_eq!(doc["bufferViews"][2]["target"], 34963);
    for view in doc["bufferViews"].as_array().unwrap() {
        assert_eq!(view["byteOffset"].as_u64().unwrap() % 4, 0);
    }
    let bin_len = u32::from_le_bytes(glb[20 + json_len..24 + json_len].try_into().unwrap());
    assert_eq!(doc["buffers"][0]["byteLength"], bin_len);
}

#[test]
fn bad_input_is_an_error() {
    let (p, n, mut i) = tetrahedron();
    i[0] = 9;
    let err = to_glb(&[plain("bad", &p, &n, &i)]).unwrap_err();
    assert!(err.to_string().contains("index 9"), "{err}");
    let err = to_glb(&[plain("short", &p, &n[..2], &i)]).unwrap_err();
    assert!(err.to_string().contains("normals"), "{err}");
    let (p, n, i) = tetrahedron();
    let short = SurfaceMesh {
        damage: vec![0.5; 3],
        ..plain("short damage", &p, &n, &i)
    };
    let err = to_glb(&[short]).unwrap_err();
    assert!(err.to_string().contains("3 damage values"), "{err}");
}

#[test]
fn the_khronos_validator_finds_no_errors() {
    let dir = tempfile::tempdir().unwrap();
    let (p, n, i) = tetrahedron();
    // Two meshes, so that the second's views start after the first's; the second
    // with damage, as the vdb method's meshes carry it.
    let damaged = SurfaceMesh {
        damage: vec![0.0, 0.5, 1.0, 0.25],
        ..plain("tet", &p, &n, &i)
    };
    let glb = to_glb(&[plain("one triangle", &p[..3], &n[..3], &i[..3]), damaged]).unwrap();
    let file = dir.path().join("tet.glb");
    std::fs::write(&file, glb).unwrap();
    let report = validate(&file);
    assert_eq!(report["numErrors"], 0, "{report:#}");
    let empty = dir.path().join("empty.glb");
    std::fs::write(&empty, to_glb(&[]).unwrap()).unwrap();
    let report = validate(&empty);
    assert_eq!(report["numErrors"], 0, "{report:#}");
}

/// A mesh of original-surface triangles only.
fn plain(name: &str, p: &[[f32; 3]], n: &[[f32; 3]], i: &[u32]) -> SurfaceMesh {
    SurfaceMesh {
        name: name.into(),
        positions: p.to_vec(),
        normals: n.to_vec(),
        surface_indices: i.to_vec(),
        ..SurfaceMesh::default()
    }
}

fn crack_tet(p: &[[f32; 3]], n: &[[f32; 3]], d: &[f32], i: &[u32]) -> SurfaceMesh {
    SurfaceMesh {
        name: "tet".into(),
        positions: p.to_vec(),
        normals: n.to_vec(),
        damage: d.to_vec(),
        surface_indices: i[..9].to_vec(),
        crack_indices: i[9..].to_vec(),
        ..SurfaceMesh::default()
    }
}

/// Reads accessor `index` of a .glb as f32 scalars.
fn floats(glb: &[u8], doc: &serde_json::Value, index: u64) -> Vec<f32> {
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let bin = &glb[20 + json_len + 8..];
    let acc = &doc["accessors"][index as usize];
    let view = &doc["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
    let start = view["byteOffset"].as_u64().unwrap() as usize;
    let components = if acc["type"] == "VEC3" { 3 } else { 1 };
    (0..components * acc["count"].as_u64().unwrap() as usize)
        .map(|k| f32::from_le_bytes(bin[start + 4 * k..start + 4 * k + 4].try_into().unwrap()))
        .collect()
}

#[test]
fn the_quantity_is_an_attribute_a_colour_and_animated_targets() {
    let dir = tempfile::tempdir().unwrap();
    let (p, n, i) = tetrahedron();
    let s = SurfaceMesh {
        quantity: vec![0.0, 1.0, 2.0, 3.0],
        quantity_range: [0.0, 4.0],
        ..crack_tet(&p, &n, &[0.0; 4], &i)
    };
    let glb = crack_glb(&s, &Glb::default()).unwrap();
    let doc = json_chunk(&glb);
    let attributes = &doc["meshes"][0]["primitives"][0]["attributes"];
    assert_eq!(
        floats(&glb, &doc, attributes["_QUANTITY"].as_u64().unwrap()),
        s.quantity
    );
    let colours = floats(&glb, &doc, attributes["COLOR_0"].as_u64().unwrap());
    // θ = 0 is the map's dark end, θ = 3 of [0, 4] three quarters up it: the
    // colours follow the documented map over the declared range, not the mesh's own.
    assert_eq!(colours[..3], quantity_color(0.0, [0.0, 4.0]));
    assert_eq!(colours[9..], quantity_color(3.0, [0.0, 4.0]));
    assert!(
        colours[9] > colours[0] && colours[10] > colours[1],
        "{colours:?}"
    );
    assert_eq!(
        doc["meshes"][0]["extras"]["quantity"]["range"],
        serde_json::json!([0.0, 4.0])
    );
    let file = dir.path().join("frame.glb");
    std::fs::write(&file, &glb).unwrap();
    let report = validate(&file);
    assert_eq!(report["numErrors"], 0, "{report:#}");

    // Three frames in which θ rises by 1 a frame: each target's deltas take the
    // base colour and θ to the frame's own.
    let frames: Vec<Vec<[f32; 3]>> = (0..3).map(|_| p.clone()).collect();
    let quantities: Vec<Vec<f32>> = (0..3)
        .map(|k| s.quantity.iter().map(|q| (q + k as f32).min(4.0)).collect())
        .collect();
    let glb = animated_glb(
        &s,
        &[0.0, 0.1, 0.2],
        &frames,
        &quantities,
        &[],
        &Glb::default(),
    )
    .unwrap();
    let doc = json_chunk(&glb);
    let target = &doc["meshes"][0]["primitives"][1]["targets"][2];
    let dq = floats(&glb, &doc, target["_QUANTITY"].as_u64().unwrap());
    assert_eq!(dq, [2.0, 2.0, 2.0, 1.0]);
    let dc = floats(&glb, &doc, target["COLOR_0"].as_u64().unwrap());
    let expected = quantity_color(4.0, [0.0, 4.0]);
    assert!((0..3).all(|k| (colours[9 + k] + dc[9 + k] - expected[k]).abs() < 1e-6));
    std::fs::write(&file, &glb).unwrap();
    let report = validate(&file);
    assert_eq!(report["numErrors"], 0, "{report:#}");
    assert_eq!(report["numWarnings"], 0, "{report:#}");

    // Damage asked for as COLOR_0 takes the colour; θ stays an attribute.
    let coloured = Glb {
        damage_colour: true,
        ..Glb::default()
    };
    let glb = animated_glb(&s, &[0.0, 0.1, 0.2], &frames, &quantities, &[], &coloured);
    let doc = json_chunk(&glb.unwrap());
    let target = &doc["meshes"][0]["primitives"][0]["targets"][2];
    assert!(target.get("COLOR_0").is_none() && target["_QUANTITY"].is_u64());
    let short = animated_glb(
        &s,
        &[0.0, 0.1, 0.2],
        &frames,
        &quantities[..2],
        &[],
        &coloured,
    );
    assert!(
        short
            .unwrap_err()
            .to_string()
            .contains("frame 3 has 0 quantity values")
    );
}

#[test]
fn animated_crack_surface_passes_the_validator() {
    let dir = tempfile::tempdir().unwrap();
    let (p, n, i) = tetrahedron();
    let d = [0.0, 0.5, 1.0, 0.25];
    let s = crack_tet(&p, &n, &d, &i);
    let frames: Vec<Vec<[f32; 3]>> = (0..3)
        .map(|k| p.iter().map(|q| [q[0] + k as f32, q[1], q[2]]).collect())
        .collect();
    let file = dir.path().join("animated.glb");
    std::fs::write(
        &file,
        animated_glb(&s, &[0.0, 1e-4, 2e-4], &frames, &[], &[], &Glb::default()).unwrap(),
    )
    .unwrap();
    let report = validate(&file);
    assert_eq!(report["numErrors"], 0, "{report:#}");
    // With a mesh collider turning and moving beside it.
    let table = table();
    let glb = animated_glb(
        &s,
        &[0.0, 1e-4, 2e-4],
        &frames,
        &[],
        &[table],
        &Glb::default(),
    );
    std::fs::write(&file, glb.unwrap()).unwrap();
    let report = validate(&file);
    assert_eq!(report["numErrors"], 0, "{report:#}");
    let file = dir.path().join("frame.glb");
    std::fs::write(&file, crack_glb(&s, &Glb::default()).unwrap()).unwrap();
    let report = validate(&file);
    assert_eq!(report["numErrors"], 0, "{report:#}");
    let options = Glb {
        damage_colour: true,
        ..Glb::default()
    };
    std::fs::write(&file, crack_glb(&s, &options).unwrap()).unwrap();
    let report = validate(&file);
    assert_eq!(report["numErrors"], 0, "{report:#}");
}

/// A tetrahedron collider that moves along x and turns about y over three frames.
fn table() -> MovingCollider {
    let (p, _, i) = tetrahedron();
    let h = std::f64::consts::FRAC_1_SQRT_2;
    MovingCollider {
        index: 1,
        name: "mesh_1".into(),
        mesh: perifrac_cache::collider::ColliderMesh {
            positions: p,
            triangles: i.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
            pivot: [0.0, 0.3, 0.0],
        },
        centers: vec![[0.0, 0.3, 0.0], [0.1, 0.3, 0.0], [0.2, 0.3, 0.0]],
        rotations: vec![
            [0.0, 0.0, 0.0, 1.0],
            [0.0, 0.38268343236508984, 0.0, 0.9238795325112867],
            [0.0, h, 0.0, h],
        ],
    }
}

#[test]
fn a_mesh_collider_is_a_node_keyed_at_each_frame() {
    let (p, n, i) = tetrahedron();
    let s = crack_tet(&p, &n, &[0.0; 4], &i);
    let frames: Vec<Vec<[f32; 3]>> = (0..3).map(|_| p.clone()).collect();
    let glb = animated_glb(
        &s,
        &[0.0, 1e-4, 2e-4],
        &frames,
        &[],
        &[table()],
        &Glb::default(),
    );
    let doc = json_chunk(&glb.unwrap());
    assert_eq!(doc["scenes"][0]["nodes"], serde_json::json!([0, 1]));
    let node = &doc["nodes"][1];
    assert_eq!(node["name"], "mesh_1");
    assert_eq!(node["translation"][1].as_f64().unwrap() as f32, 0.3);
    let primitive = &doc["meshes"][1]["primitives"][0];
    assert!(primitive["attributes"]["POSITION"].is_u64() && primitive["indices"].is_u64());
    let animation = &doc["animations"][0];
    let paths: Vec<&str> = animation["channels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["target"]["path"].as_str().unwrap())
        .collect();
    assert_eq!(paths, ["weights", "translation", "rotation"]);
    let samplers = animation["samplers"].as_array().unwrap();
    assert!(samplers.iter().all(|s| s["input"] == samplers[0]["input"]));
    assert_eq!(samplers[2]["interpolation"], "LINEAR");
    let mut short = table();
    short.mesh.triangles[0][1] = 7;
    let err = animated_glb(
        &s,
        &[0.0, 1e-4, 2e-4],
        &frames,
        &[],
        &[short],
        &Glb::default(),
    );
    assert!(err.unwrap_err().to_string().contains("index 7"));
}

/// The JSON chunk of a .glb.
fn json_chunk(glb: &[u8]) -> serde_json::Value {
    let len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    serde_json::from_slice(&glb[20..20 + len]).unwrap()
}

#[test]
fn animation_is_keyed_at_the_playback_time_base_with_named_targets() {
    let (p, n, i) = tetrahedron();
    let s = crack_tet(&p, &n, &[0.0, 0.5, 1.0, 0.25], &i);
    let frames: Vec<Vec<[f32; 3]>> = (0..3).map(|_| p.clone()).collect();
    let options = Glb {
        playback_fps: 25.0,
        damage_colour: false,
    };
    let glb = animated_glb(&s, &[0.0, 1e-4, 2e-4], &frames, &[], &[], &options).unwrap();
    let doc = json_chunk(&glb);
    let input = &doc["accessors"][doc["animations"][0]["samplers"][0]["input"]
        .as_u64()
        .unwrap() as usize];
    assert_eq!(input["min"][0].as_f64().unwrap() as f32, 1.0 / 25.0);
    assert_eq!(input["max"][0].as_f64().unwrap() as f32, 3.0 / 25.0);
    let extras = &doc["meshes"][0]["extras"];
    assert_eq!(
        extras["targetNames"],
        serde_json::json!(["frame_0001", "frame_0002", "frame_0003"])
    );
    assert_eq!(extras["simulation_times"][2].as_f64().unwrap() as f32, 2e-4);
    assert_eq!(doc["animations"][0]["extras"]["playback_fps"], 25.0);
    let attributes = &doc["meshes"][0]["primitives"][0]["attributes"];
    assert!(attributes.get("COLOR_0").is_none() && attributes["_DAMAGE"].is_u64());
    let coloured = Glb {
        damage_colour: true,
        ..options
    };
    let doc = json_chunk(&crack_glb(&s, &coloured).unwrap());
    assert!(doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"].is_u64());
}

#[test]
fn bad_animations_are_errors() {
    let (p, n, i) = tetrahedron();
    let d = [0.0; 4];
    let s = crack_tet(&p, &n, &d, &i);
    let frames = vec![p.clone(), p[..3].to_vec()];
    let err = animated_glb(&s, &[0.0, 0.1], &frames, &[], &[], &Glb::default()).unwrap_err();
    assert!(err.to_string().contains("frame 2 has 3 positions"), "{err}");
    let err = animated_glb(
        &s,
        &[0.1, 0.1],
        &[p.clone(), p.clone()],
        &[],
        &[],
        &Glb::default(),
    )
    .unwrap_err();
    assert!(err.to_string().contains("increasing"), "{err}");
    let err = crack_glb(
        &SurfaceMesh {
            damage: d[..2].to_vec(),
            ..s
        },
        &Glb::default(),
    )
    .unwrap_err();
    assert!(err.to_string().contains("damage values"), "{err}");
}
