//! Mesh input: one error test per failure kind, readers, signed distance and
//! conformity of the tet mesh.

use std::path::{Path, PathBuf};

use perifrac_math::{add, normalize, scale};

use super::*;
use crate::geometry::sdf::{Cuboid, Sdf};
use crate::geometry::stuff;

/// A unit tetrahedron wound outward.
fn tetrahedron() -> TriMesh {
    TriMesh {
        vertices: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    }
}

/// An axis-aligned box with corners `lo`, `hi`, as 12 outward triangles.
fn box_mesh(lo: [f64; 3], hi: [f64; 3]) -> TriMesh {
    let vertices = (0..8)
        .map(|i| {
            [
                if i & 1 == 0 { lo[0] } else { hi[0] },
                if i & 2 == 0 { lo[1] } else { hi[1] },
                if i & 4 == 0 { lo[2] } else { hi[2] },
            ]
        })
        .collect();
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let triangles = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    TriMesh {
        vertices,
        triangles,
    }
}

/// A sphere of `radius`: an octahedron subdivided `levels` times, projected.
fn sphere_mesh(radius: f64, levels: usize) -> TriMesh {
    let mut m = TriMesh {
        vertices: vec![
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ],
        triangles: vec![
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ],
    };
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut triangles = Vec::new();
        for t in m.triangles.clone() {
            let [a, b, c] = [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])].map(|(i, j)| {
                *mid.entry((i.min(j), i.max(j))).or_insert_with(|| {
                    let p = scale(add(m.vertices[i as usize], m.vertices[j as usize]), 0.5);
                    m.vertices.push(p);
                    (m.vertices.len() - 1) as u32
                })
            });
            triangles.extend([[t[0], a, c], [a, t[1], b], [c, b, t[2]], [a, b, c]]);
        }
        m.triangles = triangles;
    }
    for v in &mut m.vertices {
        *v = scale(normalize(*v), radius);
    }
    m
}

fn obj_text(m: &TriMesh) -> String {
    let mut s = String::new();
    for v in &m.vertices {
        s += &format!("v {} {} {}\n", v[0], v[1], v[2]);
    }
    for t in &m.triangles {
        s += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    s
}

fn ply_ascii(m: &TriMesh) -> String {
    let mut s = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        m.vertices.len(),
        m.triangles.len()
    );
    for v in &m.vertices {
        s += &format!("{} {} {}\n", v[0], v[1], v[2]);
    }
    for t in &m.triangles {
        s += &format!("3 {} {} {}\n", t[0], t[1], t[2]);
    }
    s
}

/// Writes `text` to `name` in `dir` and loads it with the default placement.
fn load_text(dir: &Path, name: &str, text: &str) -> (PathBuf, Result<TriMesh, MeshFileError>) {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write");
    let result = TriMesh::load(&path, &Placement::default());
    (path, result)
}

/// Loads `text`, expects an error, checks that its message names the file and
/// contains every string of `needles`; returns the error.
fn expect_error(name: &str, text: &str, needles: &[&str]) -> MeshFileError {
    let dir = tempfile::tempdir().expect("tempdir");
    let (path, result) = load_text(dir.path(), name, text);
    let error = result.expect_err("the mesh should be rejected");
    let message = error.to_string();
    assert!(message.contains(&path.display().to_string()), "{message}");
    for n in needles {
        assert!(message.contains(n), "'{n}' missing from: {message}");
    }
    error
}

#[test]
fn unreadable_file() {
    let e = expect_error(
        "broken.ply",
        "ply\nformat ascii 1.0\nelement vertex x\n",
        &["cannot read"],
    );
    assert!(matches!(e, MeshFileError::Unreadable { .. }));
    let e = expect_error("broken.glb", "glTF\u{2}\0\0\0garbage", &["cannot read"]);
    assert!(matches!(e, MeshFileError::Unreadable { .. }));
    let missing = TriMesh::load(Path::new("/nonexistent/none.obj"), &Placement::default());
    assert!(matches!(missing, Err(MeshFileError::Unreadable { .. })));
}

#[test]
fn unsupported_extension() {
    let e = expect_error(
        "part.stl",
        "solid x\nendsolid x\n",
        &["'stl'", ".obj, .ply, .gltf or .glb"],
    );
    assert!(matches!(e, MeshFileError::UnsupportedExtension { .. }));
}

#[test]
fn empty_mesh() {
    let e = expect_error("points.obj", "v 0 0 0\nv 1 0 0\n", &["no triangles"]);
    assert!(matches!(e, MeshFileError::Empty { .. }));
    let mut m = tetrahedron();
    m.triangles.clear();
    let e = expect_error(
        "no-faces.ply",
        &ply_ascii(&m),
        &["no triangles", "4 vertices"],
    );
    assert!(matches!(e, MeshFileError::Empty { vertices: 4, .. }));
}

#[test]
fn index_out_of_range() {
    let mut m = tetrahedron();
    m.triangles[3] = [1, 2, 9];
    let e = expect_error(
        "bad-index.ply",
        &ply_ascii(&m),
        &["face 3", "vertex 9", "4 vertices"],
    );
    assert!(matches!(e, MeshFileError::IndexOutOfRange { .. }));
}

#[test]
fn non_finite_coordinates() {
    let text = obj_text(&tetrahedron()).replace("v 1 0 0", "v nan 0 0");
    let e = expect_error(
        "nan.obj",
        &text,
        &["1 vertices have non-finite", "[NaN, 0.0, 0.0]"],
    );
    assert!(matches!(e, MeshFileError::NonFinite { count: 1, .. }));
    // Finite in the file, infinite after scaling.
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("huge.obj");
    let mut big = tetrahedron();
    big.vertices.iter_mut().for_each(|v| *v = scale(*v, 2.0));
    std::fs::write(&path, obj_text(&big)).expect("write");
    let placement = Placement {
        scale: [1e308, 1e308, 1e308],
        ..Placement::default()
    };
    let e = TriMesh::load(&path, &placement).expect_err("overflow");
    assert!(
        matches!(e, MeshFileError::NonFinite { count: 3, .. }),
        "{e}"
    );
}

#[test]
fn degenerate_faces() {
    // A repeated vertex (after welding a duplicate of vertex 1) and a zero-area sliver.
    let mut m = tetrahedron();
    m.vertices.push([1.0, 0.0, 0.0]);
    m.vertices.push([0.5, 0.5, 0.0]);
    m.triangles.push([1, 4, 2]);
    m.triangles.push([1, 5, 2]);
    let e = expect_error(
        "degenerate.obj",
        &obj_text(&m),
        &[
            "2 of 6 faces are degenerate",
            "1 with a repeated vertex",
            "1 of zero area",
            "face 4",
        ],
    );
    assert!(matches!(e, MeshFileError::Degenerate { count: 2, .. }));
}

#[test]
fn not_closed() {
    let mut m = tetrahedron();
    m.triangles.pop();
    let e = expect_error(
        "open.obj",
        &obj_text(&m),
        &["not closed", "3 boundary edges", "0 non-manifold"],
    );
    assert!(matches!(e, MeshFileError::NotClosed { boundary: 3, .. }));
    // Two tetrahedra sharing one edge: four faces on it.
    let mut two = tetrahedron();
    two.vertices.extend([[1.0, 1.0, -1.0], [-1.0, -1.0, -1.0]]);
    // Second tetrahedron on edge 0–1 with apexes 4 and 5.
    two.triangles
        .extend([[0, 1, 4], [1, 5, 4], [0, 4, 5], [0, 5, 1]]);
    let e = expect_error("bowtie.obj", &obj_text(&two), &["1 non-manifold edges"]);
    assert!(matches!(
        e,
        MeshFileError::NotClosed {
            non_manifold: 1,
            ..
        }
    ));
}

#[test]
fn inconsistent_orientation() {
    let mut m = tetrahedron();
    m.triangles[2].swap(1, 2);
    let e = expect_error(
        "flipped.obj",
        &obj_text(&m),
        &["inconsistent orientation", "3 edges"],
    );
    assert!(matches!(
        e,
        MeshFileError::InconsistentOrientation { edges: 3, .. }
    ));
}

#[test]
fn self_intersecting() {
    let mut m = box_mesh([0.0; 3], [1.0; 3]);
    let other = box_mesh([0.5, 0.25, 0.25], [1.5, 0.75, 0.75]);
    let offset = m.vertices.len() as u32;
    m.vertices.extend(other.vertices);
    m.triangles
        .extend(other.triangles.iter().map(|t| t.map(|v| v + offset)));
    let e = expect_error(
        "overlap.obj",
        &obj_text(&m),
        &["intersects itself", "pairs of faces intersect"],
    );
    match e {
        MeshFileError::SelfIntersecting { pairs, .. } => assert!(pairs >= 4, "{pairs}"),
        other => panic!("{other}"),
    }
}

#[test]
fn formats_agree_and_inside_out_is_turned() {
    let dir = tempfile::tempdir().expect("tempdir");
    let m = box_mesh([0.0; 3], [1.0, 2.0, 3.0]);
    let (_, obj) = load_text(dir.path(), "box.obj", &obj_text(&m));
    let (_, ply) = load_text(dir.path(), "box.ply", &ply_ascii(&m));
    // The OBJ reader renumbers vertices in order of use; compare invariants.
    let (obj, ply) = (obj.expect("obj"), ply.expect("ply"));
    assert_eq!(obj.bounds(), ply.bounds());
    assert_eq!((obj.vertices.len(), obj.triangles.len()), (8, 12));
    assert_eq!((ply.vertices.len(), ply.triangles.len()), (8, 12));
    assert!((obj.enclosed_volume() - 6.0).abs() < 1e-12);
    assert!((ply.enclosed_volume() - 6.0).abs() < 1e-12);
    assert!((obj.area() - 22.0).abs() < 1e-12);
    let mut inverted = m.clone();
    inverted.flip();
    let (_, inv) = load_text(dir.path(), "inverted.obj", &obj_text(&inverted));
    assert!((inv.expect("inverted").enclosed_volume() - 6.0).abs() < 1e-12);
    // Quads are fanned into triangles and duplicate vertices welded.
    let quads = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                 f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\nv 0 0 0\n";
    let (_, q) = load_text(dir.path(), "quads.obj", quads);
    let q = q.expect("quads");
    assert_eq!((q.vertices.len(), q.triangles.len()), (8, 12));
    // Placement: scale 2 along x, rotate 90° about z, move up 1.
    let placement = Placement {
        scale: [2.0, 1.0, 1.0],
        rotation_deg: [0.0, 0.0, 90.0],
        translation: [0.0, 1.0, 0.0],
    };
    let p = placement.apply([1.0, 0.0, 0.0]);
    assert!(dist(p, [0.0, 3.0, 0.0]) < 1e-12, "{p:?}");
    let mirrored = TriMesh::load(
        &dir.path().join("box.obj"),
        &Placement {
            scale: [-1.0, 1.0, 1.0],
            ..Placement::default()
        },
    )
    .expect("mirrored");
    assert!((mirrored.enclosed_volume() - 6.0).abs() < 1e-12);
}

#[test]
fn signed_distance_of_a_box_mesh_is_exact() {
    let m = box_mesh([-0.5, -1.0, -0.25], [0.5, 1.0, 0.25]);
    let sdf = MeshSdf::new(&m);
    let exact = Cuboid {
        center: [0.0; 3],
        half_extents: [0.5, 1.0, 0.25],
    };
    let mut s = 3u64;
    let mut rnd = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64 * 3.0 - 1.5
    };
    for _ in 0..2000 {
        let p = [rnd(), rnd(), rnd()];
        let (got, want) = (sdf.distance(p), exact.distance(p));
        assert!((got - want).abs() < 1e-12, "at {p:?}: {got} vs {want}");
    }
}

/// Meshes `surface` at `lambda` and conforms it, returning the tets and fit.
fn mesh_and_fit(surface: &TriMesh, lambda: f64) -> (crate::geometry::TetMesh, Conformity) {
    let sdf = MeshSdf::new(surface);
    let mut tets = stuff(&sdf, lambda).expect("stuffing");
    let fit = conform(&mut tets, surface, &sdf, lambda);
    (tets, fit)
}

#[test]
fn sphere_and_box_conform_within_a_quarter_lambda() {
    let lambda = 0.25;
    for (name, surface) in [
        ("sphere", sphere_mesh(1.0, 4)),
        ("box", box_mesh([-1.0, -0.6, -0.4], [1.0, 0.6, 0.4])),
    ] {
        let (tets, fit) = mesh_and_fit(&surface, lambda);
        let q = tets.quality();
        let volume_error = tets.total_volume() / surface.enclosed_volume() - 1.0;
        println!(
            "{name}: {} tets, fit max {:.3}λ mean {:.4}λ, {} snapped, dihedral {:.1}°–{:.1}°, volume {:+.2}%",
            tets.tets.len(),
            fit.max,
            fit.mean,
            fit.snapped,
            q.min_dihedral_deg,
            q.max_dihedral_deg,
            100.0 * volume_error
        );
        assert!(fit.max <= 0.25, "{name}: fit {:.3}λ", fit.max);
        assert!(
            q.min_dihedral_deg >= conformity::MIN_DIHEDRAL_DEG - 1e-9,
            "{name}"
        );
        assert!(
            q.max_dihedral_deg <= conformity::MAX_DIHEDRAL_DEG + 1e-9,
            "{name}"
        );
        assert!((0..tets.tets.len()).all(|t| tets.volume(t) > 0.0));
        // The boundary's chords cut inside a convex surface: −2.1% for a sphere 4λ in radius.
        assert!(volume_error.abs() < 0.03, "{name}: volume {volume_error}");
    }
}

/// Every committed asset (made by tools/make-meshes) loads as a closed, valid
/// surface, and meshes at its scene's resolution to a body of the enclosed
/// volume within 3%, fitting the surface within λ/4 (the figure's limbs 0.3λ).
#[test]
fn committed_assets_mesh_to_their_volume() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/meshes");
    let mut failures = Vec::new();
    // As placed in the scenes: vase-drop tilts the vase 20° about z (its flat
    // bottom is many coplanar triangles; rotated, rounding puts them a hair
    // off one plane, which must not count as a self-intersection: regression,
    // vase-drop.toml was once rejected with 6 intersecting pairs).
    let tilted = Placement {
        rotation_deg: [0.0, 0.0, 20.0],
        ..Placement::default()
    };
    // The worst fit is one point of a thin limb and moves with the lattice's placement:
    // the figure's was 0.236λ with the lattice at its bounds' corner and is 0.289λ with
    // the lattice centred on the bounds (issue 13); its mean fit is 0.02λ either way.
    for (name, lambda, placement, fit_bound) in [
        ("vase.obj", 0.006, tilted, 0.25),
        ("jello.ply", 0.011, Placement::default(), 0.25),
        ("figure.glb", 0.011, Placement::default(), 0.3),
    ] {
        let surface = TriMesh::load(&dir.join(name), &placement).unwrap_or_else(|e| panic!("{e}"));
        let (tets, fit) = mesh_and_fit(&surface, lambda);
        let q = tets.quality();
        let volume_error = tets.total_volume() / surface.enclosed_volume() - 1.0;
        println!(
            "{name}: {} triangles, λ = {lambda}, {} tets, fit max {:.3}λ (at {:.4?}) mean {:.4}λ ({} snapped), dihedral {:.1}°–{:.1}°, volume {:+.2}%",
            surface.triangles.len(),
            tets.tets.len(),
            fit.max,
            fit.worst_point,
            fit.mean,
            fit.snapped,
            q.min_dihedral_deg,
            q.max_dihedral_deg,
            100.0 * volume_error
        );
        if surface.triangles.len() > 20_000
            || volume_error.abs() >= 0.03
            || fit.max > fit_bound
            || q.min_dihedral_deg < conformity::MIN_DIHEDRAL_DEG - 1e-9
        {
            failures.push(name);
        }
    }
    assert!(failures.is_empty(), "out of bounds: {failures:?}");
}

/// A box mesh's creases are its 12 edges (its face diagonals are flat) and its corners
/// its 8 vertices; a sphere mesh fine enough to turn less than 30° across each edge has
/// none. Meshed without a lattice, the box keeps them: its volume is exact to 1e-9.
#[test]
fn a_box_mesh_reports_its_edges_and_a_sphere_mesh_none() {
    let m = box_mesh([-0.15, -0.1, -0.05], [0.15, 0.1, 0.05]);
    let sdf = MeshSdf::new(&m);
    let features = sdf.features(0.01);
    assert_eq!(features.corners.len(), 8);
    assert_eq!(features.creases.len(), 12);
    let length: f64 = features
        .creases
        .iter()
        .flat_map(|c| c.windows(2).map(|s| perifrac_math::dist(s[0], s[1])))
        .sum();
    assert!((length - 4.0 * (0.3 + 0.2 + 0.1)).abs() < 1e-12, "{length}");
    let sphere = MeshSdf::new(&sphere_mesh(1.0, 3));
    assert_eq!(
        sphere.features(0.01),
        crate::geometry::sdf::Features::default()
    );
    let tets = crate::geometry::unstructured::mesh_unstructured(&sdf, 0.02, 0).expect("meshing");
    let error = tets.total_volume() / 0.006 - 1.0;
    println!("box mesh, unstructured: volume error {error:+.2e}");
    assert!(error.abs() < 1e-9, "volume error {error}");
}

/// Acute creases: a tetrahedron mesh (edges of 54.7° and 90° dihedral angle, corners
/// of small solid angle) gives 4 corners and 6 creases, and meshed without a lattice
/// its corners are vertices, its edges lie on the boundary (1e-15λ), the boundary is a
/// closed manifold on the surface, and the volume is within 0.1% (−0.02% to −0.06%
/// over four seeds). Not exact, unlike a box's: beside the 54.7° edges some boundary
/// triangles still cut across the wedge (their middles up to 0.42λ under the surface);
/// why the wedge points do not prevent it at that angle is not yet found.
#[test]
fn a_tetrahedron_mesh_keeps_its_acute_corners() {
    let lambda = 0.02;
    let mut m = tetrahedron();
    for v in &mut m.vertices {
        *v = v.map(|x| 0.3 * x);
    }
    let sdf = MeshSdf::new(&m);
    let features = sdf.features(lambda);
    assert_eq!((features.corners.len(), features.creases.len()), (4, 6));
    for seed in 0..4 {
        let tets =
            crate::geometry::unstructured::mesh_unstructured(&sdf, lambda, seed).expect("meshing");
        let report = crate::geometry::mesh_check::check(&tets, &sdf, true, 1e-9);
        let error = report.volume / (0.027 / 6.0) - 1.0;
        let closest_vertex = |c: [f64; 3]| {
            tets.vertices
                .iter()
                .map(|&v| perifrac_math::dist(v, c))
                .fold(f64::INFINITY, f64::min)
        };
        let gap = features
            .corners
            .iter()
            .map(|&c| closest_vertex(c))
            .fold(0.0, f64::max);
        let faces = tets.boundary_faces();
        let boundary = Bvh::new(
            faces
                .iter()
                .map(|f| f.map(|v| tets.vertices[v as usize]))
                .collect(),
        );
        let deviation = features
            .creases
            .iter()
            .flat_map(|c| (0..=200).map(|k| perifrac_math::lerp(c[0], c[1], f64::from(k) / 200.0)))
            .map(|p| {
                boundary
                    .closest(p)
                    .expect("a boundary")
                    .distance_squared
                    .sqrt()
            })
            .fold(0.0, f64::max);
        let deepest = faces
            .iter()
            .map(|f| {
                let [a, b, c] = f.map(|v| tets.vertices[v as usize]);
                sdf.distance([0, 1, 2].map(|k| (a[k] + b[k] + c[k]) / 3.0))
                    .abs()
            })
            .fold(0.0, f64::max);
        println!(
            "tetrahedron, seed {seed}: volume error {error:+.2e}, corner gap {gap:.1e}, crease \
             deviation {:.1e}λ, deepest boundary face middle {:.2}λ",
            deviation / lambda,
            deepest / lambda
        );
        assert!(gap < 1e-12, "a corner is {gap} m from any vertex");
        assert!(deviation < 0.01 * lambda, "crease deviation {deviation}");
        assert!(error.abs() < 1e-3, "volume error {error}");
    }
}
