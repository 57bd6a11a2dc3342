use super::*;

#[test]
fn paths_and_frame_listing() {
    let dir = tempfile::tempdir().expect("tempdir");
    let layout = Layout::new(dir.path());
    assert!(layout.particles(7).ends_with("particles/0007.ply"));
    assert!(layout.surface(12).ends_with("surface/0012.glb"));
    assert!(layout.debris(3).ends_with("surface/0003_debris.ply"));
    assert!(layout.tets_collection().ends_with("tets/tets.pvd"));
    assert!(layout.usd().ends_with("cache.usd"));
    assert!(layout.usd_clip(4).ends_with("usd/0004.usdc"));
    assert!(layout.usd_clip_manifest().ends_with("usd/manifest.usdc"));
    assert!(layout.collider_mesh(2).ends_with("colliders/mesh_2.ply"));
    assert!(layout.turntable(2).ends_with("preview/turntable_002.png"));
    layout.create().expect("create");
    for frame in [3, 1] {
        write_atomic(&layout.particles(frame), b"x").expect("write");
    }
    write_atomic(&layout.particles_dir().join("notes.ply"), b"x").expect("write");
    assert_eq!(layout.particle_frames(), vec![1, 3]);
    assert!(layout.surface_frames().is_empty());
    assert!(layout.holds_cache());
    // The stage goes with its clips: one without the other would read no frames.
    std::fs::create_dir_all(layout.usd_dir()).expect("usd/");
    write_atomic(&layout.usd_clip(1), b"x").expect("write");
    write_atomic(&layout.usd(), b"x").expect("write");
    layout.clear().expect("clear");
    assert!(!layout.holds_cache() && layout.root.exists());
    assert!(!layout.usd().exists() && !layout.usd_dir().exists());
}

#[test]
fn temporary_files_of_gone_processes_are_swept_and_live_ones_kept() {
    let dir = tempfile::tempdir().expect("tempdir");
    let layout = Layout::new(dir.path());
    layout.create().expect("create");
    let own = temporary_path(&layout.particles(2));
    // PID 1 is always running; u32::MAX never is.
    let live = layout.particles_dir().join(".0003.ply.tmp-1");
    let gone = layout.root.join(format!(".manifest.json.tmp-{}", u32::MAX));
    let not_temporary = layout.particles_dir().join("0004.ply.tmp-x");
    for path in [&own, &live, &gone, &not_temporary] {
        std::fs::write(path, b"partial").expect("write");
    }
    let mut expected = vec![own, gone];
    expected.sort();
    assert_eq!(layout.remove_temporary_files(), expected);
    assert!(live.exists() && not_temporary.exists());
}

#[test]
fn a_failed_write_names_the_file_once_and_leaves_no_temporary() {
    let dir = tempfile::tempdir().expect("tempdir");
    let missing = dir.path().join("gone").join("0001.ply");
    let err = write_atomic(&missing, b"x").expect_err("no directory");
    let text = err.to_string();
    assert!(
        text.starts_with(&format!("could not write {}:", missing.display())),
        "{text}"
    );
    assert!(!text.contains(".tmp-"), "{text}");
    assert_eq!(text.matches("os error").count(), 1, "{text}");
    assert!(std::error::Error::source(&err).is_none());
    assert_eq!(human_bytes(1536), "1.5 KiB");
    assert_eq!(human_bytes(12), "12 B");
    assert!(free_space(dir.path()).is_some());
}
