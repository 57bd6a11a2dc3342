//! `perifrac surface OUT --method vdb|embedded|sheet`, and the surface stage `perifrac
//! run` runs when the scene's `[output] surface` asks for it: dispatches to
//! `perifrac_surface::embedded::stage`, `perifrac_surface::vdb::stage` or
//! `perifrac_surface::sheet::stage` with
//! `perifrac-render`'s glTF writer, shows a progress bar and prints the summary.

use std::path::{Path, PathBuf};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};
use perifrac_cache::frames::{FrameRange, frame_of_file};
use perifrac_cache::scene::{OutputSpec, Scene};
use perifrac_cache::{CacheError, Layout};
use perifrac_render::gltf::Glb;
use perifrac_surface::SurfaceError;

use crate::args::{SurfaceConfig, SurfaceMethodArg};
use crate::commands::{EXIT_FAILED, EXIT_INPUT, Failure, frames_within, set_threads};

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

/// `perifrac surface`: surfaces the cache in `config.out` (or `config.frames` of it)
/// with the settings of its resolved scene (`OUT/scene.toml`).
pub fn command(config: &SurfaceConfig, quiet: bool) -> Result<(), Failure> {
    set_threads(config.threads)?;
    crate::verify::warn(&config.out)?;
    let scene = Scene::load_cached(&Layout::new(&config.out).scene())?;
    let range = frames_within(&config.out, config.frames)?;
    let (out, output) = (&config.out, &scene.output);
    match config.method {
        SurfaceMethodArg::Vdb => stage(out, output, range, quiet),
        SurfaceMethodArg::Embedded => embedded_stage(out, output, range, quiet),
        SurfaceMethodArg::Sheet => sheet_stage(out, output, range, quiet),
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

/// Once a method has written its surfaces, removes `files` (the other method's) so the
/// two methods never mix in `surface/`, saying so: all but the `surface/NNNN.glb` just
/// written over; with a frame range, only its frames' files and the whole shot's
/// `animated.glb` (which no longer matches them). After, not before: a stage that
/// fails (no tet meshes for the embedded method) leaves the other method's surfaces
/// as they were. Ranges side by side may remove the same file: one that is gone
/// already is fine.
fn remove_other_method(
    mut files: Vec<PathBuf>,
    other: &str,
    layout: &Layout,
    range: Option<FrameRange>,
) -> Result<(), Failure> {
    let surface_dir = layout.surface_dir();
    files.retain(|f| {
        let name = f.to_string_lossy();
        let frame = frame_of_file(&name);
        let written = f.parent() == Some(surface_dir.as_path())
            && name.ends_with(".glb")
            && frame.is_some_and(|k| range.is_none_or(|r| r.contains(k)));
        !written && range.is_none_or(|r| frame.is_none_or(|k| r.contains(k)))
    });
    if files.is_empty() {
        return Ok(());
    }
    for file in &files {
        match std::fs::remove_file(file) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(CacheError::io(file, e).into());
            }
            _ => {}
        }
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

/// ` (frames A..B)` for a range, for the summaries.
fn of(range: Option<FrameRange>) -> String {
    range.map_or_else(String::new, |r| format!(" (frames {r})"))
}

/// Records the surfaces and volumes in the manifest, so `perifrac verify` checks them:
/// all of them, or the files of the frames of `range` (leaving the other ranges').
fn record_surfaces(layout: &Layout, range: Option<FrameRange>) -> Result<(), Failure> {
    let folders = [layout.surface_dir(), layout.vdb_dir()];
    match range {
        Some(range) => layout.record_frame_outputs(&folders, range)?,
        None => layout.record_outputs(&folders)?,
    }
    Ok(())
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

/// Runs the `embedded` method over every frame of the cache in `out`, or `range`.
pub fn embedded_stage(
    out: &Path,
    output: &OutputSpec,
    range: Option<FrameRange>,
    quiet: bool,
) -> Result<(), Failure> {
    let layout = Layout::new(out);
    let bar = progress(quiet);
    let encoder = Glb::new(output);
    let report = perifrac_surface::embedded::stage(
        &layout,
        &output.embedded,
        range,
        &encoder,
        &|done, total| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
        },
    );
    bar.finish_and_clear();
    let r = report?;
    remove_other_method(vdb_files(&layout), "vdb", &layout, range)?;
    record_surfaces(&layout, range)?;
    if !quiet {
        eprintln!(
            "surfaced {} frames{} (embedded) in {:.1} s, extraction {:.2} s a frame: last frame \
             {} triangles ({} crack), its cracks' zig-zag (median height) smoothed from {:.2} to \
             {:.2} mm; at most {} crack vertices smoothed, {} moves backed off, {} vertices of \
             fragments whose volume could not be kept put back, fragment volume kept within \
             {:.1e}; output in {}",
            r.frames,
            of(range),
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

/// Runs the `sheet` method over every frame of the cache in `out`, or `range`.
pub fn sheet_stage(
    out: &Path,
    output: &OutputSpec,
    range: Option<FrameRange>,
    quiet: bool,
) -> Result<(), Failure> {
    let layout = Layout::new(out);
    let bar = progress(quiet);
    let start = std::time::Instant::now();
    let encoder = Glb::new(output);
    let frames = perifrac_surface::sheet::stage(&layout, range, &encoder, &|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    });
    bar.finish_and_clear();
    let frames = frames?;
    remove_other_method(vdb_files(&layout), "vdb", &layout, range)?;
    record_surfaces(&layout, range)?;
    if !quiet {
        eprintln!(
            "surfaced {frames} frames{} (sheet) in {:.1} s; output in {}",
            of(range),
            start.elapsed().as_secs_f64(),
            layout.surface_dir().display()
        );
    }
    Ok(())
}

/// Runs the `vdb` method over every frame of the cache in `out`, or `range`.
#[cfg(not(feature = "openvdb"))]
pub fn stage(
    _out: &Path,
    _output: &OutputSpec,
    _range: Option<FrameRange>,
    _quiet: bool,
) -> Result<(), Failure> {
    Err(Failure::input(anyhow::anyhow!(
        "this perifrac was built without the `openvdb` feature, which the vdb surface method needs"
    )))
}

/// Runs the `vdb` method over every frame of the cache in `out`, or `range`.
#[cfg(feature = "openvdb")]
pub fn stage(
    out: &Path,
    output: &OutputSpec,
    range: Option<FrameRange>,
    quiet: bool,
) -> Result<(), Failure> {
    let layout = Layout::new(out);
    let bar = progress(quiet);
    let start = std::time::Instant::now();
    let encoder = Glb::new(output);
    let total =
        perifrac_surface::vdb::stage(&layout, &output.vdb, range, &encoder, &|done, total| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
        });
    bar.finish_and_clear();
    let (frames, total) = total?;
    remove_other_method(embedded_files(&layout), "embedded", &layout, range)?;
    record_surfaces(&layout, range)?;
    if !quiet {
        let n = frames as f64;
        let s = &total.seconds;
        eprintln!(
            "surfaced {frames} frames{} in {:.1} s on {} threads: {} fragments meshed ({} triangles), \
             {} debris particles in {} fragments, {} particles dropped by the rasterizer; \
             per frame: prepare {:.2} s, level set {:.2} s, filter {:.2} s, mesh {:.2} s, write {:.2} s; \
             output in {} and {}",
            of(range),
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
