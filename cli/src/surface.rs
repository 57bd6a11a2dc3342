//! `perifrac surface OUT --method vdb`, and the surface stage `perifrac run` runs when
//! the scene's `[output] surface` asks for it: every frame of a cache through
//! `perifrac-surface`, frames in parallel (rayon; OpenVDB's TBB pool capped at the
//! same thread count), each frame's meshes written as `surface/NNNN.glb` by
//! `perifrac-render`.

use std::path::Path;

use perifrac_sim::scene::{Scene, VdbSpec};

use crate::args::{SurfaceConfig, SurfaceMethodArg};
use crate::commands::{Failure, set_threads};

/// `perifrac surface`: surfaces the cache in `config.out` with the settings of its
/// resolved scene (`OUT/scene.toml`).
pub fn command(config: &SurfaceConfig, quiet: bool) -> Result<(), Failure> {
    set_threads(config.threads)?;
    let scene = Scene::load(&config.out.join("scene.toml"))?;
    match config.method {
        SurfaceMethodArg::Vdb => stage(&config.out, &scene.output.vdb, quiet),
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
    use perifrac_render::gltf::{MeshData, to_glb};
    use perifrac_sim::cache::Layout;
    use perifrac_sim::cache::manifest::Manifest;
    use perifrac_sim::cache::write_atomic;
    use perifrac_sim::scene::VdbSpec;
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
