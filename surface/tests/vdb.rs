//! The `vdb` method on particles from the real mesher: volume and closedness of a
//! sphere, fragments that must stay apart, errors instead of crashes, and the .vdb
//! file read back by an independent reader (the pure-Rust `vdb-rs`).
#![cfg(feature = "openvdb")]

use std::path::Path;

use perifrac_sim::cache::manifest::BodyInfo;
use perifrac_sim::cache::ply::ParticleFrame;
use perifrac_sim::geometry::discretize::discretize;
use perifrac_sim::scene::{Scene, VdbSpec};
use perifrac_surface::SurfaceError;
use perifrac_surface::particles::spacing;
use perifrac_surface::vdb::{FrameSurface, LevelSet, initialize, surface_particles};

/// The particles the simulator places for one body of `shape` (a TOML inline table)
/// at resolution `lambda`, as a frame (fragment 0, body 0), and the body's info.
fn particles_of(shape: &str, lambda: f64) -> (ParticleFrame, Vec<BodyInfo>) {
    let text = format!(
        "[scene]\n[materials.m]\ndensity = 1000.0\nbulk_modulus = 1e6\nshear_modulus = 1e6\n\
         [[body]]\nmaterial = \"m\"\nshape = {shape}\nresolution = {lambda}\n"
    );
    let scene = Scene::parse(&text, Path::new("test.toml"), Path::new(".")).expect("scene");
    let disc = discretize(&scene).expect("discretize");
    let n = disc.position.len();
    let frame = ParticleFrame {
        frame: 1,
        time: 0.0,
        position: disc.position.iter().map(|p| p.map(|x| x as f32)).collect(),
        velocity: vec![[0.0, 0.0, 1.0]; n],
        damage: vec![0.0; n],
        plastic: vec![0.0; n],
        material: vec![0.0; n],
        fragment: vec![0.0; n],
        extra: Vec::new(),
    };
    let body = BodyInfo {
        name: "body0".into(),
        material: "m".into(),
        particles: n,
        mean_edge: disc.quality[0].mean_edge,
        ..BodyInfo::default()
    };
    (frame, vec![body])
}

fn surface(
    particles: &ParticleFrame,
    bodies: &[BodyInfo],
    spec: &VdbSpec,
    dir: &Path,
) -> Result<FrameSurface, SurfaceError> {
    initialize(2);
    surface_particles(
        1,
        particles,
        bodies,
        spec,
        &dir.join("0001.vdb"),
        &dir.join("0001_debris.ply"),
    )
}

#[test]
fn a_sphere_of_particles_gives_a_closed_mesh_of_its_volume() {
    let radius = 0.1;
    let (particles, bodies) = particles_of(
        &format!("{{ type = \"sphere\", center = [0.0, 0.0, 0.0], radius = {radius} }}"),
        0.0125,
    );
    let dir = tempfile::tempdir().unwrap();
    let s = surface(&particles, &bodies, &VdbSpec::default(), dir.path()).expect("surfaced");
    assert_eq!(s.meshes.len(), 1);
    let mesh = &s.meshes[0].mesh;
    assert!(mesh.is_closed(), "{} open edges", mesh.open_edges());
    assert_eq!(mesh.components(), 1);
    let sphere = 4.0 / 3.0 * std::f64::consts::PI * radius * radius * radius;
    let error = mesh.volume() / sphere - 1.0;
    eprintln!(
        "{} particles, voxel {:.5} m, {} triangles, volume error {:+.2}%, {:?}",
        particles.len(),
        s.stats.voxel_size,
        mesh.triangle_count(),
        100.0 * error,
        s.stats.seconds
    );
    assert!(error.abs() < 0.03, "volume off by {:+.2}%", 100.0 * error);
    assert_eq!(s.stats.dropped_particles, 0);
}

/// Two blocks of particles whose nearest particles are 2 voxels apart, less than a
/// sphere's diameter (3.5 voxels at the defaults), as across a fresh crack: surfaced
/// per fragment they stay two closed meshes; in one level set they merge.
#[test]
fn fragments_two_voxels_apart_stay_apart_only_per_fragment() {
    let (block, bodies) = particles_of(
        "{ type = \"box\", center = [0.0, 0.0, 0.0], size = [0.1, 0.1, 0.1] }",
        0.0125,
    );
    let spec = VdbSpec::default();
    let voxel = spec.voxel_size * spacing(bodies[0].mean_edge);
    let (lo, hi) = block
        .position
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), p| {
            (lo.min(p[0]), hi.max(p[0]))
        });
    let shift = (hi - lo) + 2.0 * voxel as f32;
    let mut two = block.clone();
    for p in &block.position {
        two.position.push([p[0] + shift, p[1], p[2]]);
    }
    let n = block.len();
    two.velocity.extend_from_slice(&block.velocity);
    two.damage.extend_from_slice(&block.damage);
    two.plastic.extend_from_slice(&block.plastic);
    two.material.extend_from_slice(&block.material);
    two.fragment.extend(std::iter::repeat_n(1.0, n));

    let dir = tempfile::tempdir().unwrap();
    let apart = surface(&two, &bodies, &spec, dir.path()).expect("surfaced");
    assert_eq!(apart.meshes.len(), 2);
    for m in &apart.meshes {
        assert!(
            m.mesh.is_closed(),
            "fragment {}: {} open edges",
            m.fragment,
            m.mesh.open_edges()
        );
        assert_eq!(m.mesh.components(), 1);
        assert_eq!(m.particles, n);
    }
    let merged_spec = VdbSpec {
        per_fragment: false,
        ..spec
    };
    let merged = surface(&two, &bodies, &merged_spec, dir.path()).expect("surfaced");
    assert_eq!(merged.meshes.len(), 1);
    assert_eq!(
        merged.meshes[0].mesh.components(),
        1,
        "one blob: the crack closed"
    );
}

#[test]
fn small_fragments_become_debris_points() {
    let (mut particles, bodies) = particles_of(
        "{ type = \"box\", center = [0.0, 0.0, 0.0], size = [0.06, 0.06, 0.06] }",
        0.0125,
    );
    for (i, f) in particles.fragment.iter_mut().take(3).enumerate() {
        *f = 10.0 + i as f32;
    }
    let dir = tempfile::tempdir().unwrap();
    let s = surface(&particles, &bodies, &VdbSpec::default(), dir.path()).expect("surfaced");
    assert_eq!((s.stats.debris_fragments, s.stats.debris_particles), (3, 3));
    assert_eq!(s.meshes.len(), 1);
    let ply = std::fs::read(dir.path().join("0001_debris.ply")).unwrap();
    let text = String::from_utf8_lossy(&ply);
    assert!(text.contains("element vertex 3\n"), "{text}");
}

#[test]
fn empty_and_nan_frames_are_errors_not_crashes() {
    let dir = tempfile::tempdir().unwrap();
    let (particles, bodies) = particles_of(
        "{ type = \"box\", center = [0.0, 0.0, 0.0], size = [0.05, 0.05, 0.05] }",
        0.0125,
    );
    let empty = ParticleFrame::default();
    let err = surface(&empty, &bodies, &VdbSpec::default(), dir.path()).unwrap_err();
    assert!(err.to_string().contains("no particles"), "{err}");
    let mut nan = particles.clone();
    nan.position[5][1] = f32::NAN;
    let err = surface(&nan, &bodies, &VdbSpec::default(), dir.path()).unwrap_err();
    assert!(
        err.to_string()
            .contains("particle 5 has a non-finite position"),
        "{err}"
    );

    // The same inputs straight at the C++ shim: refused there too, with text.
    initialize(2);
    let radii = vec![0.005f32; nan.len()];
    let err = LevelSet::from_spheres(1, &nan.position, &radii, 0.002, 3.0)
        .err()
        .expect("refused");
    assert!(matches!(err, SurfaceError::OpenVdb { .. }), "{err}");
    assert!(err.to_string().contains("particle 5"), "{err}");
    let err = LevelSet::from_spheres(1, &[], &[], 0.002, 3.0)
        .err()
        .expect("refused");
    assert!(err.to_string().contains("no particles"), "{err}");

    // An exception thrown inside OpenVDB (writing to a directory that does not exist)
    // comes back as an error with OpenVDB's text.
    let missing = dir.path().join("no-such-dir");
    let err = surface_particles(
        1,
        &particles,
        &bodies,
        &VdbSpec::default(),
        &missing.join("0001.vdb"),
        &missing.join("0001_debris.ply"),
    )
    .unwrap_err();
    assert!(matches!(err, SurfaceError::OpenVdb { .. }), "{err}");
    eprintln!("{err}");
}

#[test]
fn a_single_layer_is_refused() {
    let s = 0.005f32;
    let n = 40 * 40;
    let plane = ParticleFrame {
        frame: 1,
        position: (0..n)
            .map(|i| {
                [
                    (i % 40) as f32 * s,
                    0.3 * (i / 40) as f32 * s,
                    0.95 * (i / 40) as f32 * s,
                ]
            })
            .collect(),
        velocity: vec![[0.0; 3]; n],
        damage: vec![0.0; n],
        plastic: vec![0.0; n],
        material: vec![0.0; n],
        fragment: vec![0.0; n],
        ..ParticleFrame::default()
    };
    // A mean edge whose spacing is the plane's.
    let bodies = vec![BodyInfo {
        name: "membrane".into(),
        mean_edge: f64::from(s) * 9.1f64.cbrt(),
        ..BodyInfo::default()
    }];
    let dir = tempfile::tempdir().unwrap();
    let err = surface(&plane, &bodies, &VdbSpec::default(), dir.path()).unwrap_err();
    assert!(matches!(err, SurfaceError::SingleLayer { .. }), "{err}");
    // A body that had volume at rest and is a sheet of shreds later is surfaced: the
    // run that made it is not thrown away at its surface stage.
    surface_particles(
        9,
        &plane,
        &bodies,
        &VdbSpec::default(),
        &dir.path().join("0009.vdb"),
        &dir.path().join("0009_debris.ply"),
    )
    .expect("a later frame is surfaced");
    let text = err.to_string();
    assert!(
        text.contains("membrane") && text.contains("sheet surface method"),
        "{text}"
    );
}

#[test]
fn the_vdb_file_reads_back_with_vdb_rs() {
    let (particles, bodies) = particles_of(
        "{ type = \"sphere\", center = [0.0, 0.0, 0.0], radius = 0.05 }",
        0.0125,
    );
    let dir = tempfile::tempdir().unwrap();
    let s = surface(&particles, &bodies, &VdbSpec::default(), dir.path()).expect("surfaced");
    let file = std::fs::File::open(dir.path().join("0001.vdb")).unwrap();
    let mut reader = vdb_rs::VdbReader::new(std::io::BufReader::new(file)).expect("a .vdb file");
    let mut names = reader.available_grids();
    names.sort();
    assert_eq!(names, ["surface", "v"]);
    let class = |reader: &vdb_rs::VdbReader<_>, name: &str| {
        reader.grid_descriptors[name]
            .meta_data
            .0
            .get("class")
            .cloned()
    };
    assert_eq!(
        class(&reader, "surface"),
        Some(vdb_rs::MetadataValue::String("level set".into()))
    );
    assert_eq!(
        reader.grid_descriptors["surface"].grid_type,
        "Tree_float_5_4_3"
    );
    assert_eq!(reader.grid_descriptors["v"].grid_type, "Tree_vec3s_5_4_3");
    let grid = reader.read_grid::<f32>("surface").expect("the level set");
    match grid.transform {
        vdb_rs::Map::UniformScaleMap { voxel_size, .. } => {
            for k in 0..3 {
                assert!(
                    (voxel_size[k] - s.stats.voxel_size).abs() < 1e-9,
                    "{voxel_size:?}"
                );
            }
        }
        other => panic!("unexpected transform {other:?}"),
    }
    // A narrow band of signed distance: values within ±3 voxels, both signs present,
    // and voxels as deep as the band goes (a raw union of spheres only holds the
    // distance to the nearest sphere, never deeper than its radius, 1.74 voxels).
    let dx = s.stats.voxel_size as f32;
    let (mut inside, mut outside, mut deep) = (0, 0, 0);
    for (_, value, _) in grid.iter() {
        assert!(value.abs() <= 3.001 * dx, "{value} outside ±3 voxels");
        if value < 0.0 {
            inside += 1;
        } else {
            outside += 1;
        }
        if value < -2.5 * dx {
            deep += 1;
        }
    }
    assert!(
        inside > 100 && outside > 100,
        "{inside} inside, {outside} outside"
    );
    assert!(deep > 100, "{deep} voxels deeper than 2.5 voxels");
    let v = reader
        .read_grid::<[f32; 3]>("v")
        .expect("the velocity grid");
    assert!(
        v.iter()
            .take(100)
            .all(|(_, value, _)| value == [0.0, 0.0, 1.0])
    );
}
