//! `perifrac surface OUT --method vdb|embedded`, and the surface stage `perifrac run`
//! runs when the scene's `[output] surface` asks for it: every frame of a cache
//! through `perifrac-surface`, frames in parallel (rayon; OpenVDB's TBB pool capped at
//! the same thread count), each frame's meshes written as `surface/NNNN.glb` by
//! `perifrac-render` (and, for the embedded method, `surface/animated.glb`).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, anyhow};
use indicatif::{ProgressBar, ProgressStyle};
use perifrac_cache::manifest::Manifest;
use perifrac_cache::scene::{EmbeddedSpec, Scene, VdbSpec};
use perifrac_cache::vtu::TetFrame;
use perifrac_cache::{Layout, write_atomic};
use perifrac_render::gltf::{CrackSurface, animated_glb, crack_glb};
use perifrac_surface::embedded::{EmbeddedSurface, RenderMesh, surface};
use rayon::prelude::*;

use crate::args::{SurfaceConfig, SurfaceMethodArg};
use crate::commands::{Failure, set_threads};

/// `perifrac surface`: surfaces the cache in `config.out` with the settings of its
/// resolved scene (`OUT/scene.toml`).
pub fn command(config: &SurfaceConfig, quiet: bool) -> Result<(), Failure> {
    set_threads(config.threads)?;
    let scene = Scene::load(&config.out.join("scene.toml"))?;
    match config.method {
        SurfaceMethodArg::Vdb => stage(&config.out, &scene.output.vdb, quiet),
        SurfaceMethodArg::Embedded => embedded_stage(&config.out, &scene.output.embedded, quiet),
    }
}

fn progress(frames: usize, quiet: bool) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(frames as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:30} surfaced {pos}/{len} frames {msg} ETA {eta}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.enable_steady_tick(Duration::from_millis(200));
    bar
}

/// The frame's surface as written to its .glb.
fn crack_surface<'a>(name: &'a str, m: &'a RenderMesh) -> CrackSurface<'a> {
    CrackSurface {
        name,
        positions: &m.positions,
        normals: &m.normals,
        damage: &m.damage,
        surface_indices: &m.surface_indices,
        crack_indices: &m.crack_indices,
    }
}

/// Positions, in a frame, of the vertices of the final topology: a copy that does
/// not exist yet sits where the vertex it will be split from is (`parent` from the
/// last frame; a frame's vertices are a prefix of the last frame's).
fn follow(final_mesh: &RenderMesh, parent: &[i32], points: &[[f64; 3]]) -> Vec<[f32; 3]> {
    final_mesh
        .vertex
        .iter()
        .map(|&v| {
            let mut v = v as usize;
            while v >= points.len() && parent[v] >= 0 {
                v = parent[v] as usize;
            }
            points[v].map(|c| c as f32)
        })
        .collect()
}

/// Runs the `embedded` method over every frame of the cache in `out`: reads
/// `tets/NNNN.vtu`, writes `surface/NNNN.glb` and `surface/animated.glb`, and
/// records the extraction time in the manifest (`timings.surface`).
pub fn embedded_stage(out: &Path, spec: &EmbeddedSpec, quiet: bool) -> Result<(), Failure> {
    let layout = Layout::new(out);
    let mut manifest = Manifest::read(&layout.manifest())?;
    let frames = manifest.frame_times.len();
    if frames == 0 {
        return Err(Failure::input(anyhow!(
            "{}: the cache has no frames to surface",
            layout.manifest().display()
        )));
    }
    if !layout.tets(1).is_file() {
        return Err(Failure::input(anyhow!(
            "{} is missing: the embedded method reads the split tet meshes; run the scene with \
             [output] tets = true (or surface = \"embedded\")",
            layout.tets(1).display()
        )));
    }
    let dir = layout.root.join("surface");
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let glb = |frame: usize| -> PathBuf { dir.join(format!("{frame:04}.glb")) };
    let start = Instant::now();
    // The last frame first: its topology is the animation's.
    let last = TetFrame::read(&layout.tets(frames))?;
    let t = Instant::now();
    let final_surface = surface(&last, spec.smoothing_passes);
    let final_mesh = final_surface.render_mesh(&last.damage);
    let mut extraction = t.elapsed().as_secs_f64();
    let bar = progress(frames, quiet);
    let name = manifest.scene.clone();
    let per_frame: Vec<(Vec<[f32; 3]>, f64, EmbeddedSurfaceSummary)> = (1..=frames)
        .into_par_iter()
        .map(|frame| -> Result<_, Failure> {
            let tets = if frame == frames {
                last.clone()
            } else {
                TetFrame::read(&layout.tets(frame))?
            };
            let t = Instant::now();
            let surf = surface(&tets, spec.smoothing_passes);
            let mesh = surf.render_mesh(&tets.damage);
            let seconds = t.elapsed().as_secs_f64();
            let bytes = crack_glb(&crack_surface(&name, &mesh))
                .with_context(|| format!("frame {frame}"))?;
            write_atomic(&glb(frame), &bytes)?;
            bar.inc(1);
            Ok((
                follow(&final_mesh, &last.parent, &surf.points),
                seconds,
                EmbeddedSurfaceSummary::of(&surf),
            ))
        })
        .collect::<Result<_, Failure>>()?;
    bar.finish_and_clear();
    extraction += per_frame.iter().map(|f| f.1).sum::<f64>();
    let times: Vec<f32> = manifest.frame_times.iter().map(|&t| t as f32).collect();
    let positions: Vec<Vec<[f32; 3]>> = per_frame.iter().map(|f| f.0.clone()).collect();
    let base_points: Vec<[f64; 3]> = positions[0].iter().map(|p| p.map(f64::from)).collect();
    let mut base = final_mesh.clone();
    base.positions = positions[0].clone();
    base.normals = normals_at(&final_mesh, &base_points);
    let bytes = animated_glb(&crack_surface(&name, &base), &times, &positions)
        .context("surface/animated.glb")?;
    write_atomic(&dir.join("animated.glb"), &bytes)?;
    manifest.timings.surface = extraction;
    manifest.write(&layout.manifest())?;
    if !quiet {
        let s = per_frame
            .iter()
            .fold(EmbeddedSurfaceSummary::default(), |a, f| a.max(&f.2));
        eprintln!(
            "surfaced {frames} frames (embedded) in {:.1} s, extraction {:.2} s a frame: last frame \
             {} triangles ({} crack), at most {} crack vertices smoothed, {} moves backed off, \
             {} vertices of fragments whose volume could not be kept put back, fragment volume \
             kept within {:.1e}; output in {}",
            start.elapsed().as_secs_f64(),
            extraction / frames as f64,
            final_surface.triangles.len(),
            final_surface.crack.iter().filter(|&&c| c).count(),
            s.crack_vertices,
            s.backed_off,
            s.reverted,
            s.volume_error,
            dir.display()
        );
    }
    Ok(())
}

/// Normals of the render vertices at positions given per render vertex.
fn normals_at(mesh: &RenderMesh, positions: &[[f64; 3]]) -> Vec<[f32; 3]> {
    let local = RenderMesh {
        vertex: (0..mesh.vertex.len() as u32).collect(),
        ..mesh.clone()
    };
    EmbeddedSurface::default().normals(&local, positions)
}

/// The largest smoothing figures over frames, for the summary line.
#[derive(Debug, Clone, Copy, Default)]
struct EmbeddedSurfaceSummary {
    crack_vertices: usize,
    backed_off: usize,
    reverted: usize,
    volume_error: f64,
}

impl EmbeddedSurfaceSummary {
    fn of(s: &EmbeddedSurface) -> Self {
        EmbeddedSurfaceSummary {
            crack_vertices: s.stats.crack_vertices,
            backed_off: s.stats.backed_off,
            reverted: s.stats.reverted,
            volume_error: s.stats.volume_error,
        }
    }

    fn max(self, o: &Self) -> Self {
        EmbeddedSurfaceSummary {
            crack_vertices: self.crack_vertices.max(o.crack_vertices),
            backed_off: self.backed_off + o.backed_off,
            reverted: self.reverted + o.reverted,
            volume_error: self.volume_error.max(o.volume_error),
        }
    }
}

/// Runs the `vdb` method over every frame of the cache in `out`.
#[cfg(not(feature = "openvdb"))]
pub fn stage(_out: &Path, _spec: &VdbSpec, _quiet: bool) -> Result<(), Failure> {
    Err(Failure::input(anyhow::anyhow!(
        "this perifrac was built without the `openvdb` feature, which the vdb surface method needs"
    )))
}

/// Runs the `vdb` method over every frame of the cache in `out`.
#[cfg(feature = "openvdb")]
pub fn stage(out: &Path, spec: &VdbSpec, quiet: bool) -> Result<(), Failure> {
    vdb::stage(out, spec, quiet)
}

#[cfg(feature = "openvdb")]
mod vdb {
    use std::path::{Path, PathBuf};
    use std::sync::Mutex;
    use std::time::{Duration, Instant};

    use anyhow::{Context, anyhow};
    use indicatif::{ProgressBar, ProgressStyle};
    use perifrac_cache::Layout;
    use perifrac_cache::manifest::Manifest;
    use perifrac_cache::scene::VdbSpec;
    use perifrac_cache::write_atomic;
    use perifrac_render::gltf::{MeshData, to_glb};
    use perifrac_surface::SurfaceError;
    use perifrac_surface::vdb::{FrameStats, FrameSurface, StepSeconds, initialize, surface_frame};
    use rayon::prelude::*;

    use crate::commands::Failure;

    impl From<SurfaceError> for Failure {
        fn from(e: SurfaceError) -> Failure {
            let code = match e {
                SurfaceError::Frame { .. } | SurfaceError::SingleLayer { .. } => 2,
                _ => 1,
            };
            Failure {
                error: e.into(),
                code,
            }
        }
    }

    /// `surface/NNNN.glb`.
    fn glb_path(layout: &Layout, frame: usize) -> PathBuf {
        layout.root.join("surface").join(format!("{frame:04}.glb"))
    }

    /// Writes a frame's meshes, one glTF mesh and node per fragment.
    fn write_glb(path: &Path, surface: &FrameSurface) -> anyhow::Result<()> {
        let names: Vec<String> = surface
            .meshes
            .iter()
            .map(|m| format!("fragment {}", m.fragment))
            .collect();
        let normals: Vec<Vec<[f32; 3]>> = surface
            .meshes
            .iter()
            .map(|m| m.mesh.vertex_normals())
            .collect();
        let data: Vec<MeshData<'_>> = surface
            .meshes
            .iter()
            .zip(&names)
            .zip(&normals)
            .map(|((m, name), normals)| MeshData {
                name,
                positions: &m.mesh.positions,
                normals,
                indices: &m.mesh.indices,
            })
            .collect();
        let bytes = to_glb(&data).with_context(|| format!("frame {}", surface.frame))?;
        write_atomic(path, &bytes)?;
        Ok(())
    }

    fn add(total: &mut FrameStats, s: &FrameStats) {
        total.particles += s.particles;
        total.fragments += s.fragments;
        total.debris_fragments += s.debris_fragments;
        total.debris_particles += s.debris_particles;
        total.dropped_particles += s.dropped_particles;
        total.active_voxels += s.active_voxels;
        total.triangles += s.triangles;
        total.voxel_size = total.voxel_size.max(s.voxel_size);
        let (t, u) = (&mut total.seconds, &s.seconds);
        *t = StepSeconds {
            prepare: t.prepare + u.prepare,
            level_set: t.level_set + u.level_set,
            filter: t.filter + u.filter,
            mesh: t.mesh + u.mesh,
            write: t.write + u.write,
        };
    }

    pub(super) fn stage(out: &Path, spec: &VdbSpec, quiet: bool) -> Result<(), Failure> {
        let layout = Layout::new(out);
        let manifest = Manifest::read(&layout.manifest())?;
        let frames = manifest.frame_times.len();
        if frames == 0 {
            return Err(Failure::input(anyhow!(
                "{}: the cache has no frames to surface",
                layout.manifest().display()
            )));
        }
        let dir = layout.root.join("surface");
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        initialize(rayon::current_num_threads());
        let bar = if quiet {
            ProgressBar::hidden()
        } else {
            let bar = ProgressBar::new(frames as u64);
            bar.set_style(
                ProgressStyle::with_template("{spinner} [{elapsed_precise}] {bar:30} surfaced {pos}/{len} frames {msg} ETA {eta}")
                    .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            bar.enable_steady_tick(Duration::from_millis(200));
            bar
        };
        let start = Instant::now();
        let total = Mutex::new(FrameStats::default());
        let result = (1..=frames)
            .into_par_iter()
            .try_for_each(|frame| -> Result<(), Failure> {
                let t = Instant::now();
                let surface = surface_frame(&layout, &manifest, frame, spec)?;
                let w = Instant::now();
                write_glb(&glb_path(&layout, frame), &surface)?;
                let mut stats = surface.stats.clone();
                stats.seconds.write += w.elapsed().as_secs_f64();
                if let Ok(mut total) = total.lock() {
                    add(&mut total, &stats);
                }
                bar.inc(1);
                bar.set_message(format!("{:.2} s a frame", t.elapsed().as_secs_f64()));
                Ok(())
            });
        bar.finish_and_clear();
        result?;
        let total = total.into_inner().unwrap_or_default();
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
                dir.display(),
                layout.root.join("vdb").display()
            );
        }
        Ok(())
    }
}
