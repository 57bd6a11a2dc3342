//! `perifrac surface OUT --method vdb|embedded|sheet`, and the surface stage `perifrac
//! run` runs when the scene's `[output] surface` asks for it: dispatches to
//! `perifrac_surface::embedded::stage`, `perifrac_surface::vdb::stage` or
//! `perifrac_surface::sheet::stage` with
//! `perifrac-render`'s glTF writer, shows a progress bar and prints the summary.

use std::path::{Path, PathBuf};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};
use perifrac_cache::scene::{OutputSpec, Scene};
use perifrac_cache::{CacheError, Layout};
use perifrac_render::gltf::Glb;
use perifrac_surface::SurfaceError;

use crate::args::{SurfaceConfig, SurfaceMethodArg};
use crate::commands::{EXIT_FAILED, EXIT_INPUT, Failure, set_threads};

impl From<SurfaceError> for Failure {
    fn from(e: SurfaceError) -> Failure {
        // A damaged cache file is bad input here as in `render` (the same code for
        // the same damage).
        let code = match &e {
            SurfaceError::Frame { .. } | SurfaceError::SingleLayer { .. } => EXIT_INPUT,
            SurfaceError::Input(_) => EXIT_INPUT,
            SurfaceError::Cache(c) if c.is_bad_input() => EXIT_INPUT,
            _ => EXIT_FAILED,
        };
        Failure {
            error: e.into(),
            code,
        }
    }
}

/// `perifrac surface`: surfaces the cache in `config.out` with the settings of its
/// resolved scene (`OUT/scene.toml`).
pub fn command(config: &SurfaceConfig, quiet: bool) -> Result<(), Failure> {
    set_threads(config.threads)?;
    crate::verify::warn(&config.out)?;
    let scene = Scene::load_cached(&Layout::new(&config.out).scene())?;
    match config.method {
        SurfaceMethodArg::Vdb => stage(&config.out, &scene.output, quiet),
        SurfaceMethodArg::Embedded => embedded_stage(&config.out, &scene.output, quiet),
        SurfaceMethodArg::Sheet => sheet_stage(&config.out, &scene.output, quiet),
    }
}

/// A progress bar over frames (hidden with `quiet`); its length is set by the stage.
fn progress(quiet: bool) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(0);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:30} surfaced {pos}/{len} frames {msg} ETA {eta}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.enable_steady_tick(Duration::from_millis(200));
    bar
}

/// Removes `files` (the other method's surfaces) so the two methods never mix in
/// `surface/`, saying so.
fn remove_other_method(files: Vec<PathBuf>, other: &str, layout: &Layout) -> Result<(), Failure> {
    if files.is_empty() {
        return Ok(());
    }
    for file in &files {
        std::fs::remove_file(file).map_err(|e| CacheError::io(file, e))?;
    }
    eprintln!(
        "note: removed the {other} method's {} file{} from {} (the two methods' surfaces \
         share file names and never mix)",
        files.len(),
        if files.len() == 1 { "" } else { "s" },
        layout.root.display()
    );
    Ok(())
}

/// The `vdb` method's files: `vdb/NNNN.vdb`, `surface/NNNN_debris.ply` and, when
/// there are any of those, `surface/NNNN.glb`.
fn vdb_files(layout: &Layout) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = frame_files(&layout.vdb_dir(), ".vdb");
    files.extend(frame_files(&layout.surface_dir(), "_debris.ply"));
    if !files.is_empty() {
        files.extend(layout.surface_frames().iter().map(|&k| layout.surface(k)));
    }
    files
}

/// The `embedded` method's files: `surface/animated.glb` and, with it,
/// `surface/NNNN.glb`.
#[cfg(feature = "openvdb")]
fn embedded_files(layout: &Layout) -> Vec<PathBuf> {
    if !layout.animated_surface().exists() {
        return Vec::new();
    }
    let mut files = vec![layout.animated_surface()];
    files.extend(layout.surface_frames().iter().map(|&k| layout.surface(k)));
    files
}

/// Records the surfaces and volumes in the manifest, so `perifrac verify` checks them.
fn record_surfaces(layout: &Layout) -> Result<(), Failure> {
    Ok(layout.record_outputs(&[layout.surface_dir(), layout.vdb_dir()])?)
}

/// Files `NNNN<suffix>` in `dir`.
fn frame_files(dir: &Path, suffix: &str) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = entries
        .flatten()
        .filter(|e| {
            e.file_name().to_str().is_some_and(|n| {
                n.strip_suffix(suffix)
                    .is_some_and(|s| s.len() == 4 && s.bytes().all(|b| b.is_ascii_digit()))
            })
        })
        .map(|e| e.path())
        .collect();
    files.sort();
    files
}

/// Runs the `embedded` method over every frame of the cache in `out`.
pub fn embedded_stage(out: &Path, output: &OutputSpec, quiet: bool) -> Result<(), Failure> {
    let layout = Layout::new(out);
    remove_other_method(vdb_files(&layout), "vdb", &layout)?;
    let bar = progress(quiet);
    let encoder = Glb::new(output);
    let report =
        perifrac_surface::embedded::stage(&layout, &output.embedded, &encoder, &|done, total| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
        });
    bar.finish_and_clear();
    let r = report?;
    record_surfaces(&layout)?;
    if !quiet {
        eprintln!(
            "surfaced {} frames (embedded) in {:.1} s, extraction {:.2} s a frame: last frame \
             {} triangles ({} crack), its cracks' zig-zag (median height) smoothed from {:.2} to \
             {:.2} mm; at most {} crack vertices smoothed, {} moves backed off, {} vertices of \
             fragments whose volume could not be kept put back, fragment volume kept within \
             {:.1e}; output in {}",
            r.frames,
            r.seconds,
            r.extraction / r.frames as f64,
            r.triangles,
            r.crack_triangles,
            1e3 * r.roughness[0],
            1e3 * r.roughness[1],
            r.crack_vertices,
            r.backed_off,
            r.reverted,
            r.volume_error,
            layout.surface_dir().display()
        );
    }
    Ok(())
}

/// Runs the `sheet` method over every frame of the cache in `out`.
pub fn sheet_stage(out: &Path, output: &OutputSpec, quiet: bool) -> Result<(), Failure> {
    let layout = Layout::new(out);
    remove_other_method(vdb_files(&layout), "vdb", &layout)?;
    let bar = progress(quiet);
    let start = std::time::Instant::now();
    let encoder = Glb::new(output);
    let frames = perifrac_surface::sheet::stage(&layout, &encoder, &|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    });
    bar.finish_and_clear();
    let frames = frames?;
    record_surfaces(&layout)?;
    if !quiet {
        eprintln!(
            "surfaced {frames} frames (sheet) in {:.1} s; output in {}",
            start.elapsed().as_secs_f64(),
            layout.surface_dir().display()
        );
    }
    Ok(())
}

/// Runs the `vdb` method over every frame of the cache in `out`.
#[cfg(not(feature = "openvdb"))]
pub fn stage(_out: &Path, _output: &OutputSpec, _quiet: bool) -> Result<(), Failure> {
    Err(Failure::input(anyhow::anyhow!(
        "this perifrac was built without the `openvdb` feature, which the vdb surface method needs"
    )))
}

/// Runs the `vdb` method over every frame of the cache in `out`.
#[cfg(feature = "openvdb")]
pub fn stage(out: &Path, output: &OutputSpec, quiet: bool) -> Result<(), Failure> {
    let layout = Layout::new(out);
    remove_other_method(embedded_files(&layout), "embedded", &layout)?;
    let bar = progress(quiet);
    let start = std::time::Instant::now();
    let encoder = Glb::new(output);
    let total = perifrac_surface::vdb::stage(&layout, &output.vdb, &encoder, &|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    });
    bar.finish_and_clear();
    let (frames, total) = total?;
    record_surfaces(&layout)?;
    if !quiet {
        let n = frames as f64;
        let s = &total.seconds;
        eprintln!(
            "surfaced {frames} frames in {:.1} s on {} threads: {} fragments meshed ({} triangles), \
             {} debris particles in {} fragments, {} particles dropped by the rasterizer; \
             per frame: prepare {:.2} s, level set {:.2} s, filter {:.2} s, mesh {:.2} s, write {:.2} s; \
             output in {} and {}",
            start.elapsed().as_secs_f64(),
            rayon::current_num_threads(),
            total.fragments,
            total.triangles,
            total.debris_particles,
            total.debris_fragments,
            total.dropped_particles,
            s.prepare / n,
            s.level_set / n,
            s.filter / n,
            s.mesh / n,
            s.write / n,
            layout.surface_dir().display(),
            layout.vdb_dir().display()
        );
    }
    Ok(())
}
