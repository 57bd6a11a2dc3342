//! The stage written from small hand-made caches, read back.

use super::*;

/// A cache of two particle frames and one collider, written by hand.
fn small_cache(root: &std::path::Path) -> Layout {
    let layout = Layout::new(root);
    layout.create().unwrap();
    let scene = "[scene]\nname = \"t\"\nfps = 1000.0\n\n[materials.m]\ndensity = 1000.0\n\
                 bulk_modulus = 1e5\nshear_modulus = 1e5\n\n[[body]]\nmaterial = \"m\"\n\
                 resolution = 0.02\nshape = { type = \"box\", center = [0, 0, 0], size = [0.1, 0.1, 0.1] }\n\n\
                 [[collider]]\ntype = \"sphere\"\ncenter = [0.0, 1.0, 0.0]\nradius = 0.1\n\n\
                 [output]\nplayback_fps = 30\n";
    std::fs::write(layout.scene(), scene).unwrap();
    let manifest = Manifest {
        scene: "t".into(),
        fps: 1000.0,
        frame_times: vec![0.0, 0.001],
        collider_centers: vec![vec![[0.0, 1.0, 0.0]], vec![[0.0, 0.9, 0.0]]],
        collider_rotations: vec![vec![[0.0, 0.0, 0.0, 1.0]], vec![[0.6, 0.0, 0.0, 0.8]]],
        ..Manifest::default()
    };
    manifest.write(&layout.manifest()).unwrap();
    for frame in 1..=2 {
        ParticleFrame {
            frame,
            time: manifest.frame_times[frame - 1],
            position: vec![[0.0, frame as f32, 0.0], [1.0, 0.0, 0.0]],
            velocity: vec![[0.0, 3.0, 0.0], [0.0, 0.0, 0.0]],
            damage: vec![0.0, 0.5],
            plastic: vec![0.0, 0.0],
            material: vec![0.0, 0.0],
            fragment: vec![0.0, 1.0],
            extra: vec![
                ("volume".into(), vec![1e-6, 0.0]),
                ("quantity".into(), vec![1.0, 2.0]),
            ],
        }
        .write(&layout.particles(frame))
        .unwrap();
    }
    layout
}

#[test]
fn a_small_cache_reads_back_through_the_usdc_reader() {
    let dir = tempfile::tempdir().unwrap();
    let layout = small_cache(dir.path());
    let report = write_stage(&layout).unwrap();
    assert_eq!(
        (report.frames, report.particles, report.colliders),
        (2, 2, 1)
    );
    let data = openusd::usdc::read_file(layout.usd()).unwrap();
    let root = openusd::sdf::Path::abs_root();
    let field = |path: &openusd::sdf::Path, key: &str| data.get_field(path, key).unwrap();
    assert_eq!(*field(&root, "upAxis"), Value::token("Y"));
    assert_eq!(*field(&root, "timeCodesPerSecond"), Value::Double(30.0));
    assert_eq!(*field(&root, "endTimeCode"), Value::Double(2.0));
    // Each frame's particle samples are in its clip, usd/NNNN.usdc, at its time code.
    let clips: Vec<_> = (1..=2)
        .map(|k| openusd::usdc::read_file(layout.usd_clip(k)).unwrap())
        .collect();
    let sample = |frame: usize, attribute: &str| -> Value {
        let path = openusd::sdf::Path::new(attribute).unwrap();
        let field = clips[frame - 1].get_field(&path, "timeSamples").unwrap();
        let Value::TimeSamples(samples) = field.into_owned() else {
            panic!("{attribute} is not time-sampled");
        };
        assert_eq!(samples.len(), 1, "{attribute}: one sample a clip");
        assert_eq!(
            samples[0].0, frame as f64,
            "{attribute}: at the frame's time code"
        );
        samples[0].1.clone()
    };
    assert_eq!(
        sample(2, "/World/Particles.points"),
        vec3f(&[[0.0, 2.0, 0.0], [1.0, 0.0, 0.0]])
    );
    // Velocities in m/s of playback: 3 m/s × 30 / 1000.
    assert_eq!(
        sample(1, "/World/Particles.velocities"),
        vec3f(&[[0.0, 3.0 * 0.03, 0.0], [0.0; 3]])
    );
    // Widths: the cube root of the volume (1e-6 m³ → 0.01 m), not the body's λ
    // (0.02 m), which the particle without a volume falls back to.
    let Value::FloatVec(w) = sample(1, "/World/Particles.widths") else {
        panic!("widths are not floats");
    };
    assert!((w[0] - 0.01).abs() < 1e-7 && w[1] == 0.02, "{w:?}");
    // The stage declares what the clips give, and names the clips frame by frame.
    let points = openusd::sdf::Path::new("/World/Particles.points").unwrap();
    assert_eq!(*field(&points, "typeName"), Value::token("point3f[]"));
    let world = openusd::sdf::Path::new("/World").unwrap();
    let Value::Dictionary(clips_field) = field(&world, "clips").into_owned() else {
        panic!("/World has no clips");
    };
    let Some(Value::Dictionary(set)) = clips_field.get("default") else {
        panic!("no default clip set: {clips_field:?}");
    };
    assert_eq!(
        set.get("assetPaths"),
        Some(&Value::AssetPathVec(vec![
            AssetPath::new("./usd/0001.usdc"),
            AssetPath::new("./usd/0002.usdc")
        ]))
    );
    let quantity = openusd::sdf::Path::new("/World/Particles.primvars:quantity").unwrap();
    assert!(data.has_spec(&quantity), "the extra column is a primvar");
    let sphere = openusd::sdf::Path::new("/World/Colliders/sphere_0.xformOp:translate").unwrap();
    let Value::TimeSamples(samples) = field(&sphere, "timeSamples").into_owned() else {
        panic!("the collider does not move");
    };
    assert_eq!(samples[1].1, Value::Vec3d(gf::vec3d(0.0, 0.9, 0.0)));
    let orient = openusd::sdf::Path::new("/World/Colliders/sphere_0.xformOp:orient").unwrap();
    let Value::TimeSamples(samples) = field(&orient, "timeSamples").into_owned() else {
        panic!("the collider's rotations are not time-sampled");
    };
    // [x, y, z, w] in the manifest, (w, x, y, z) in USD.
    assert_eq!(samples[1].1, Value::Quatd(gf::quatd(0.8, 0.6, 0.0, 0.0)));
    // The looks read the per-face colour primvar (Blender follows it per frame).
    let varname =
        openusd::sdf::Path::new("/World/Looks/crack/DisplayColor.inputs:varname").unwrap();
    assert_eq!(
        *field(&varname, "default"),
        Value::String("displayColor".into())
    );
    // The same cache gives the same bytes, the stage's and the clips'.
    let files = [layout.usd(), layout.usd_clip(1), layout.usd_clip(2)];
    let first: Vec<_> = files.iter().map(|f| std::fs::read(f).unwrap()).collect();
    write_stage(&layout).unwrap();
    for (file, bytes) in files.iter().zip(first) {
        assert_eq!(bytes, std::fs::read(file).unwrap(), "{}", file.display());
    }
    // A cache of fewer frames leaves no clip of the old export behind.
    let mut manifest = Manifest::read(&layout.manifest()).unwrap();
    manifest.frame_times.truncate(1);
    manifest.collider_centers.truncate(1);
    manifest.collider_rotations.truncate(1);
    manifest.write(&layout.manifest()).unwrap();
    write_stage(&layout).unwrap();
    assert!(layout.usd_clip(1).is_file() && !layout.usd_clip(2).exists());
}

#[test]
fn a_missing_frame_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let layout = small_cache(dir.path());
    std::fs::remove_file(layout.particles(2)).unwrap();
    let err = write_stage(&layout).unwrap_err();
    assert!(err.is_bad_input());
    let text = err.to_string();
    assert!(
        text.contains("0002.ply") && text.contains("--resume"),
        "{text}"
    );
}
