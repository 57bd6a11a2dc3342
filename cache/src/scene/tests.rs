use super::*;

const GOOD: &str = r#"[scene]
name = "t"

[materials.glass]
density = 2200.0
bulk_modulus = 3.3e10
shear_modulus = 2.0e10

[[body]]
material = "glass"
shape = { type = "box", center = [0, 0, 0], size = [1, 1, 1] }
resolution = 0.1
"#;

/// Parses `text`, expecting an error; returns (line, key, message).
fn error(text: &str) -> (usize, String, String) {
    match Scene::parse(text, Path::new("bad.toml"), Path::new("/nonexistent-dir")) {
        Err(CacheError::Scene {
            file,
            line,
            key,
            message,
            ..
        }) => {
            assert_eq!(file, Path::new("bad.toml"));
            (line, key, message)
        }
        other => panic!("expected a scene error, got {other:?}"),
    }
}

#[test]
fn the_good_scene_parses_with_defaults() {
    let s = Scene::parse(GOOD, Path::new("good.toml"), Path::new(".")).expect("valid");
    assert_eq!(s.bodies[0].horizon, 1.45);
    assert_eq!(s.bodies[0].name, "body0");
    assert_eq!(s.scene.fps, 24.0);
    assert!(s.materials["glass"].critical_stretch.is_none());
    let again =
        Scene::parse(&s.to_toml(), Path::new("resolved.toml"), Path::new(".")).expect("round trip");
    assert_eq!(again.to_toml(), s.to_toml());
}

#[test]
fn crushing_needs_a_strain_between_zero_and_one_and_tension_failure() {
    let glass = |keys: &str| {
        GOOD.replace(
            "shear_modulus = 2.0e10",
            &format!("shear_modulus = 2.0e10\n{keys}"),
        )
    };
    let (line, key, message) = error(&glass("critical_compression = 0.005"));
    assert_eq!(
        (line, key.as_str()),
        (8, "materials.glass.critical_compression")
    );
    assert!(message.contains("set critical_stretch"), "{message}");
    let (_, key, message) = error(&glass(
        "critical_stretch = 0.0005\ncritical_compression = -1",
    ));
    assert_eq!(key, "materials.glass.critical_compression");
    assert!(message.contains("positive"), "{message}");
    let (_, key, message) = error(&glass(
        "critical_stretch = 0.0005\ncritical_compression = 1.5",
    ));
    assert_eq!(key, "materials.glass.critical_compression");
    assert!(message.contains("strain below 1"), "{message}");
    let both = glass("critical_stretch = 0.0005\ncritical_compression = 0.005");
    let s = Scene::parse(&both, Path::new("good.toml"), Path::new(".")).expect("valid");
    assert_eq!(s.materials["glass"].critical_compression, Some(0.005));
}

#[test]
fn unknown_key() {
    let (line, key, message) =
        error(&GOOD.replace("density = 2200.0", "density = 2200.0\ndensty = 1.0"));
    assert_eq!(line, 6);
    assert_eq!(key, "materials.glass.densty");
    assert!(message.contains("unknown field `densty`"), "{message}");
}

#[test]
fn negative_density() {
    let (line, key, message) = error(&GOOD.replace("density = 2200.0", "density = -1.0"));
    assert_eq!((line, key.as_str()), (5, "materials.glass.density"));
    assert!(message.contains("positive"), "{message}");
}

#[test]
fn poisson_ratio_at_one_half() {
    let text = GOOD.replace(
        "bulk_modulus = 3.3e10\nshear_modulus = 2.0e10",
        "youngs_modulus = 1e6\npoisson_ratio = 0.5",
    );
    let (line, key, message) = error(&text);
    assert_eq!((line, key.as_str()), (7, "materials.glass.poisson_ratio"));
    assert!(message.contains("(−1, 0.5)"), "{message}");
}

#[test]
fn horizon_below_one_resolution() {
    let (line, key, message) =
        error(&GOOD.replace("resolution = 0.1", "resolution = 0.1\nhorizon = 0.9"));
    assert_eq!((line, key.as_str()), (13, "body.0.horizon"));
    assert!(message.contains("at least 1.0"), "{message}");
}

#[test]
fn missing_mesh_file() {
    let text = GOOD.replace(
        r#"shape = { type = "box", center = [0, 0, 0], size = [1, 1, 1] }"#,
        r#"shape = { type = "mesh", path = "bunny.obj" }"#,
    );
    let (line, key, message) = error(&text);
    assert_eq!((line, key.as_str()), (11, "body.0.shape.path"));
    assert!(
        message.contains("bunny.obj") && message.contains("does not exist"),
        "{message}"
    );
}

#[test]
fn resolved_scene_finds_its_mesh_from_anywhere() {
    // Regression: OUT/scene.toml kept the mesh path relative to the original
    // scene file, so `perifrac surface OUT` could not load it.
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("cube.obj"), "v 0 0 0\n").expect("write");
    let text = GOOD.replace(
        r#"shape = { type = "box", center = [0, 0, 0], size = [1, 1, 1] }"#,
        r#"shape = { type = "mesh", path = "cube.obj", scale = [1, 2, 3] }"#,
    );
    let s = Scene::parse(&text, Path::new("good.toml"), dir.path()).expect("valid");
    let resolved = s.to_toml();
    let again = Scene::parse(
        &resolved,
        Path::new("OUT/scene.toml"),
        Path::new("/elsewhere"),
    )
    .expect("the resolved scene is valid from another directory");
    match &again.bodies[0].shape {
        ShapeSpec::Mesh { path, scale, .. } => {
            assert!(path.is_absolute() && path.ends_with("cube.obj"), "{path:?}");
            assert_eq!(scale.factors(), [1.0, 2.0, 3.0]);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn playback_fps_defaults_to_24_and_must_be_positive() {
    let s = Scene::parse(GOOD, Path::new("good.toml"), Path::new(".")).expect("valid");
    assert_eq!(s.output.playback_fps, 24.0);
    assert!(!s.output.gltf_damage_colour);
    let text = format!("{GOOD}\n[output]\nplayback_fps = 30\n");
    let s = Scene::parse(&text, Path::new("good.toml"), Path::new(".")).expect("valid");
    assert_eq!(s.output.playback_fps, 30.0);
    let (_, key, message) = error(&format!("{GOOD}\n[output]\nplayback_fps = 0\n"));
    assert_eq!(key, "output.playback_fps");
    assert!(message.contains("positive"), "{message}");
}

#[test]
fn vdb_surface_keys() {
    let text =
        format!("{GOOD}\n[output]\nsurface = \"vdb\"\n\n[output.vdb]\nfilter = \"gaussian\"\n");
    let s = Scene::parse(&text, Path::new("good.toml"), Path::new(".")).expect("valid");
    assert_eq!(s.output.surface, SurfaceMethod::Vdb);
    assert_eq!(s.output.vdb.filter, VdbFilter::Gaussian);
    assert_eq!(s.output.vdb.voxel_size, 0.8);
    assert!(s.output.vdb.per_fragment);
    let (line, key, message) = error(&format!("{GOOD}\n[output.vdb]\nadaptivity = 1.5\n"));
    assert_eq!((line, key.as_str()), (15, "output.vdb.adaptivity"));
    assert!(message.contains("[0, 1]"), "{message}");
    let (_, key, message) = error(&format!("{GOOD}\n[output.vdb]\nvoxel_size = 1.0\n"));
    assert_eq!(key, "output.vdb.voxel_size");
    assert!(message.contains("voxel_size ≤ 0.931"), "{message}");
    let (_, key, _) = error(&format!("{GOOD}\n[output]\nsurface = \"marching\"\n"));
    assert_eq!(key, "output.surface");
}

#[test]
fn unknown_material_and_bad_toml() {
    let (line, key, _) = error(&GOOD.replace("material = \"glass\"", "material = \"steel\""));
    assert_eq!((line, key.as_str()), (10, "body.0.material"));
    let (line, _, message) = error("[scene\nname = 1");
    assert_eq!(line, 1);
    assert!(!message.is_empty());
    let (_, _, message) = error("");
    assert!(message.contains("scene"), "{message}");
}
