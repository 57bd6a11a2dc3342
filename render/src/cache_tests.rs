//! Tests of [`super`]: framing, colliders, particle sizes, surfaces and debris.

use super::*;
use crate::geometry::Shading;
use crate::gltf::read_surfaces;
use perifrac_cache::mesh::SurfaceMesh;

#[test]
fn percentile_bounds_leave_out_far_debris() {
    // 1000 points on [0, 1) and 8 debris points far out: the 98 % range is the
    // body's, to within its outer 1 %.
    let mut pts: Vec<[f32; 3]> = (0..1000).map(|i| [i as f32 / 1000.0, 0.0, 0.0]).collect();
    pts.extend((0..8).map(|i| [10.0 + i as f32, 0.0, 0.0]));
    pts.push([f32::NAN, 0.0, 0.0]);
    let b = percentile_bounds(&pts, FRAMING_TAIL, 0.0);
    assert!(
        b.max[0] < 1.0 && b.max[0] > 0.95 && b.min[0] >= 0.0,
        "{b:?}"
    );
    // With 3 % of the points far out, the bounds reach them.
    pts.extend((0..20).map(|i| [20.0 + i as f32, 0.0, 0.0]));
    let b = percentile_bounds(&pts, FRAMING_TAIL, 0.5);
    assert!(b.max[0] > 20.5, "{b:?}");
    assert_eq!(
        percentile_bounds(&[[1.0, 2.0, 3.0]], FRAMING_TAIL, 0.0).min,
        [1.0, 2.0, 3.0]
    );
}

#[test]
fn missing_temperature_is_named() {
    let mut f = ParticleFrame {
        frame: 1,
        position: vec![[0.0; 3]],
        velocity: vec![[0.0; 3]],
        damage: vec![0.0],
        plastic: vec![0.0],
        material: vec![0.0],
        fragment: vec![0.0],
        ..ParticleFrame::default()
    };
    let err = temperature(&f, Path::new("p/0001.ply")).unwrap_err();
    let text = err.to_string();
    assert!(
        text.contains("p/0001.ply") && text.contains("temperature"),
        "{text}"
    );
    f.extra = vec![("temperature".into(), vec![300.0])];
    assert_eq!(temperature(&f, Path::new("p")).unwrap(), [300.0]);
}

#[test]
fn a_mesh_collider_is_drawn_at_the_frames_pose() {
    use perifrac_cache::collider::ColliderMesh;
    let dir = tempfile::tempdir().unwrap();
    let layout = Layout::new(dir.path());
    layout.create().unwrap();
    let table = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/meshes/table.obj");
    let scene = format!(
        "[scene]\nname = \"t\"\n\n[materials.m]\ndensity = 1000.0\nbulk_modulus = 1e5\n\
         shear_modulus = 1e5\n\n[[body]]\nmaterial = \"m\"\nresolution = 0.02\nshape = \
         {{ type = \"box\", center = [0, 0.4, 0], size = [0.1, 0.1, 0.1] }}\n\n\
         [[collider]]\ntype = \"mesh\"\npath = {:?}\n",
        table.to_str().unwrap()
    );
    std::fs::write(layout.scene(), scene).unwrap();
    // A quarter turn about y at frame 1: x ↦ −z.
    let h = std::f64::consts::FRAC_1_SQRT_2;
    Manifest {
        frame_times: vec![0.0],
        collider_centers: vec![vec![[1.0, 2.0, 3.0]]],
        collider_rotations: vec![vec![[0.0, h, 0.0, h]]],
        ..Manifest::default()
    }
    .write(&layout.manifest())
    .unwrap();
    ParticleFrame {
        frame: 1,
        position: vec![[0.0, 0.4, 0.0]],
        velocity: vec![[0.0; 3]],
        damage: vec![0.0],
        plastic: vec![0.0],
        material: vec![0.0],
        fragment: vec![0.0],
        ..ParticleFrame::default()
    }
    .write(&layout.particles(1))
    .unwrap();
    let err = Cache::open(dir.path()).unwrap_err();
    let text = err.to_string();
    assert!(
        matches!(&err, RenderError::Cache(c) if c.is_bad_input())
            && text.contains("colliders/mesh_0.ply")
            && text.contains("--force"),
        "{text}"
    );
    std::fs::create_dir_all(layout.colliders_dir()).unwrap();
    let mesh = ColliderMesh {
        positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        pivot: [0.0, 0.15, 0.0],
    };
    mesh.write(&layout.collider_mesh(0)).unwrap();
    let cache = Cache::open(dir.path()).unwrap();
    let g = cache
        .geometry(1, ColorBy::Material, &Ranges::default())
        .unwrap();
    let corners: Vec<[f32; 3]> = g
        .mesh_vertices
        .chunks_exact(geometry::MESH_STRIDE)
        .filter(|v| v[9] == Shading::Collider as u32 as f32)
        .map(|v| [v[0], v[1], v[2]])
        .collect();
    // Four flat triangles; the file's vertex 1, (1, 0, 0), at (1, 2, 2).
    assert_eq!(corners.len(), 12);
    assert_eq!(corners[0], [1.0, 2.0, 3.0]);
    let moved = corners[2];
    assert!(
        (0..3).all(|k| (moved[k] - [1.0, 2.0, 2.0][k]).abs() < 1e-6),
        "{moved:?}"
    );
}

#[test]
fn particles_are_drawn_at_their_own_size() {
    let (dir, layout) = one_box_cache("");
    let mut frame = ParticleFrame {
        frame: 1,
        position: vec![[0.0, 0.4, 0.0], [0.05, 0.4, 0.0]],
        velocity: vec![[0.0; 3]; 2],
        damage: vec![0.0; 2],
        plastic: vec![0.0; 2],
        material: vec![0.0; 2],
        fragment: vec![0.0; 2],
        ..ParticleFrame::default()
    };
    let radii = |frame: &ParticleFrame| {
        frame.write(&layout.particles(1)).unwrap();
        let cache = Cache::open(dir.path()).unwrap();
        let g = cache
            .geometry(1, ColorBy::Material, &Ranges::default())
            .unwrap();
        g.points
            .chunks_exact(geometry::POINT_STRIDE)
            .map(|p| p[3])
            .collect::<Vec<f32>>()
    };
    // An old cache without volumes: half the body's λ.
    assert_eq!(radii(&frame), [0.01, 0.01]);
    // Half the cube root of each volume: 1e-6 m³ → 5 mm, 8e-6 m³ → 10 mm.
    frame.extra = vec![("volume".into(), vec![1e-6, 8e-6])];
    let r = radii(&frame);
    assert!(
        (r[0] - 0.005).abs() < 1e-7 && (r[1] - 0.01).abs() < 1e-7,
        "{r:?}"
    );
}

/// A vdb frame's debris points are drawn beside its meshes, at their body's
/// particle size and in its colour; a debris file without a material is named.
#[test]
fn a_vdb_frames_debris_is_drawn_beside_its_meshes() {
    let (dir, layout) = one_box_cache("color = \"#ff0000\"\n");
    let mesh = SurfaceMesh {
        positions: vec![[0.0, 0.4, 0.0], [0.1, 0.4, 0.0], [0.0, 0.5, 0.0]],
        normals: vec![[0.0, 0.0, 1.0]; 3],
        surface_indices: vec![0, 1, 2],
        ..SurfaceMesh::default()
    };
    std::fs::create_dir_all(layout.surface_dir()).unwrap();
    std::fs::write(layout.surface(1), crate::gltf::to_glb(&[mesh]).unwrap()).unwrap();
    let debris = |scalars: &[(&str, &[f32])]| {
        let bytes = perifrac_cache::ply::encode_points(
            "debris",
            &[[0.3, 0.1, 0.0], [0.4, 0.1, 0.0]],
            &[[0.0; 3]; 2],
            scalars,
        );
        std::fs::write(layout.debris(1), bytes).unwrap();
    };
    debris(&[
        ("radius", &[0.004, 0.006]),
        ("fragment", &[5.0, 6.0]),
        ("material", &[0.0, 0.0]),
    ]);
    let cache = Cache::open(dir.path()).unwrap();
    let g = cache
        .geometry(1, ColorBy::Material, &Ranges::default())
        .unwrap();
    assert!(!g.mesh_vertices.is_empty(), "the mesh is drawn");
    let points: Vec<&[f32]> = g.points.chunks_exact(geometry::POINT_STRIDE).collect();
    assert_eq!(points.len(), 2);
    assert_eq!(&points[1][..4], &[0.4, 0.1, 0.0, 0.01], "half λ");
    assert_eq!(&points[0][4..7], &[1.0, 0.0, 0.0], "the body's colour");
    debris(&[("radius", &[0.004, 0.006]), ("fragment", &[5.0, 6.0])]);
    let err = cache
        .geometry(1, ColorBy::Material, &Ranges::default())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("0001_debris.ply") && err.contains("'material'"),
        "{err}"
    );
}

#[test]
fn surfaces_read_back_as_written() {
    let mesh = SurfaceMesh {
        name: "block".into(),
        positions: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        normals: vec![[0.0, 0.0, 1.0]; 4],
        damage: vec![0.0, 0.25, 0.5, 1.0],
        surface_indices: vec![0, 2, 1, 0, 1, 3],
        crack_indices: vec![1, 2, 3],
        ..SurfaceMesh::default()
    };
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("0001.glb");
    let options = crate::gltf::Glb::default();
    std::fs::write(&file, crate::gltf::crack_glb(&mesh, &options).unwrap()).unwrap();
    assert_eq!(read_surfaces(&file).unwrap(), vec![mesh.clone()]);
    let plain = SurfaceMesh {
        damage: Vec::new(),
        crack_indices: Vec::new(),
        ..mesh
    };
    std::fs::write(
        &file,
        crate::gltf::to_glb(&[plain.clone(), plain.clone()]).unwrap(),
    )
    .unwrap();
    assert_eq!(read_surfaces(&file).unwrap(), vec![plain.clone(), plain]);
}

/// An empty cache directory whose scene is one box of λ = 0.02 m, its material given
/// the extra keys `material`.
fn one_box_cache(material: &str) -> (tempfile::TempDir, Layout) {
    let dir = tempfile::tempdir().unwrap();
    let layout = Layout::new(dir.path());
    layout.create().unwrap();
    let scene = format!(
        "[scene]\nname = \"t\"\n\n[materials.m]\ndensity = 1000.0\n\
         bulk_modulus = 1e5\nshear_modulus = 1e5\n{material}\n[[body]]\nmaterial = \"m\"\n\
         resolution = 0.02\nshape = {{ type = \"box\", center = [0, 0.4, 0], \
         size = [0.1, 0.1, 0.1] }}\n"
    );
    std::fs::write(layout.scene(), scene).unwrap();
    (dir, layout)
}
