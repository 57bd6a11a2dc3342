//! The `embedded` surface stage over a cache or a range of its frames: each frame's
//! split tet mesh (`tets/NNNN.vtu`) becomes `surface/NNNN.glb`, and the whole shot's frames together
//! `surface/animated.glb` (the last frame's topology, one morph target a frame, crack
//! faces folded to a point of the surface until they open: `animated`);
//! the extraction time goes into the manifest (`timings.surface`).

use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use perifrac_cache::Layout;
use perifrac_cache::collider::mesh_colliders;
use perifrac_cache::frames::FrameRange;
use perifrac_cache::manifest::Manifest;
use perifrac_cache::mesh::SurfaceEncoder;
use perifrac_cache::scene::{EmbeddedSpec, Scene};
use perifrac_cache::vtu::TetFrame;
use rayon::prelude::*;

use super::animated::{FrameView, animate, view};
use super::{EmbeddedSurface, RenderMesh, SmoothingStats, surface};
use crate::error::{Result, SurfaceError};
use crate::frame_range;
use crate::write_encoded as write;

/// What an `embedded` stage did, for its summary line.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EmbeddedReport {
    /// Frames surfaced.
    pub frames: usize,
    /// Wall-clock seconds of the whole stage.
    pub seconds: f64,
    /// Seconds of surface extraction over all frames (not the writing of files).
    pub extraction: f64,
    /// Triangles of the last frame.
    pub triangles: usize,
    /// Crack triangles of the last frame.
    pub crack_triangles: usize,
    /// Most crack vertices smoothed in a frame.
    pub crack_vertices: usize,
    /// Smoothing moves backed off, over all frames.
    pub backed_off: usize,
    /// Vertices of fragments whose volume could not be kept, put back, over all frames.
    pub reverted: usize,
    /// Largest relative volume change of a smoothed fragment.
    pub volume_error: f64,
    /// How far the last frame's crack surface zig-zags before and after smoothing
    /// (m; [`SmoothingStats::roughness`]).
    pub roughness: [f64; 2],
}

impl EmbeddedReport {
    /// Adds one frame's smoothing figures.
    fn add(mut self, s: &SmoothingStats) -> Self {
        self.crack_vertices = self.crack_vertices.max(s.crack_vertices);
        self.backed_off += s.backed_off;
        self.reverted += s.reverted;
        self.volume_error = self.volume_error.max(s.volume_error);
        self
    }
}

/// Normals of the mesh vertices at positions given per mesh vertex.
fn normals_at(mesh: &RenderMesh, positions: &[[f64; 3]]) -> Vec<[f32; 3]> {
    let local = RenderMesh {
        vertex: (0..mesh.vertex.len() as u32).collect(),
        ..mesh.clone()
    };
    EmbeddedSurface::default().normals(&local, positions)
}

/// Runs the `embedded` method over frames `range` of the cache at `layout` (every
/// frame with `None`), frames in parallel (rayon): reads `tets/NNNN.vtu`, writes
/// `surface/NNNN.glb` through `encoder` and calls `progress(done, total)` after each
/// frame. Over every frame it also writes `surface/animated.glb` (which needs them
/// all) and records the extraction time in the manifest; over a range (a farm's
/// array job) it writes that range's frames only, the bytes a run over every frame
/// writes for them. The report's last-frame figures are of the range's last frame.
pub fn stage(
    layout: &Layout,
    spec: &EmbeddedSpec,
    range: Option<FrameRange>,
    encoder: &dyn SurfaceEncoder,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<EmbeddedReport> {
    let manifest = Manifest::read(&layout.manifest())?;
    let range = frame_range(layout, &manifest, range)?;
    let frames = manifest.frame_times.len();
    let whole = range.is_all(frames);
    if !layout.tets(range.first).is_file() {
        return Err(SurfaceError::Input(format!(
            "{} is missing: the embedded method reads the split tet meshes; run the scene with \
             [output] tets = true (or surface = \"embedded\")",
            layout.tets(range.first).display()
        )));
    }
    let dir = layout.surface_dir();
    std::fs::create_dir_all(&dir).map_err(|e| SurfaceError::io(&dir, e))?;
    let start = Instant::now();
    // The range's last frame first: over the whole shot its topology is the
    // animation's.
    let last = TetFrame::read(&layout.tets(range.last))?;
    let t = Instant::now();
    let final_surface = surface(&last, spec.smoothing_passes);
    let mut final_mesh = final_surface.render_mesh(&last.damage);
    final_mesh.mesh.name = manifest.scene.clone();
    let mut extraction = t.elapsed().as_secs_f64();
    let done = AtomicUsize::new(0);
    let per_frame: Vec<(Option<FrameView>, f64, SmoothingStats)> = range
        .frames()
        .into_par_iter()
        .map(|frame| -> Result<_> {
            let tets = if frame == range.last {
                last.clone()
            } else {
                TetFrame::read(&layout.tets(frame))?
            };
            let t = Instant::now();
            let surf = surface(&tets, spec.smoothing_passes);
            let mut mesh = surf.render_mesh(&tets.damage);
            let seconds = t.elapsed().as_secs_f64();
            mesh.mesh.name = manifest.scene.clone();
            write(
                &layout.surface(frame),
                format!("frame {frame}"),
                encoder.fractured(&mesh.mesh),
            )?;
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, range.len());
            let view = whole.then(|| view(&final_mesh, &last.parent, &surf));
            Ok((view, seconds, surf.stats))
        })
        .collect::<Result<_>>()?;
    extraction += per_frame.iter().map(|f| f.1).sum::<f64>();
    let report = per_frame
        .iter()
        .fold(EmbeddedReport::default(), |r, f| r.add(&f.2));
    if whole {
        // The scene's mesh colliders, which animated.glb carries beside the surface.
        let scene = Scene::load_cached(&layout.scene())?;
        let colliders = mesh_colliders(layout, &scene, Some(&manifest))?;
        let times: Vec<f32> = manifest.frame_times.iter().map(|&t| t as f32).collect();
        let views: Vec<FrameView> = per_frame.into_iter().filter_map(|f| f.0).collect();
        let (mut base, positions) = animate(&final_mesh, &views);
        let base_points: Vec<[f64; 3]> = positions[0].iter().map(|p| p.map(f64::from)).collect();
        base.mesh.positions = positions[0].clone();
        base.mesh.normals = normals_at(&base, &base_points);
        write(
            &layout.animated_surface(),
            "surface/animated.glb".into(),
            encoder.animated(&base.mesh, &times, &positions, &[], &colliders),
        )?;
        layout.update_manifest(|m| {
            m.timings.surface = extraction;
            Ok(())
        })?;
    }
    Ok(EmbeddedReport {
        frames: range.len(),
        seconds: start.elapsed().as_secs_f64(),
        extraction,
        triangles: final_surface.triangles.len(),
        crack_triangles: final_surface.crack.iter().filter(|&&c| c).count(),
        roughness: final_surface.stats.roughness,
        ..report
    })
}
