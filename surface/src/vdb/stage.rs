//! The `vdb` surface stage over a cache or a range of its frames: each frame's particles become
//! `vdb/NNNN.vdb`, `surface/NNNN_debris.ply` and `surface/NNNN.glb` (one mesh a
//! fragment), frames in parallel (rayon; OpenVDB's TBB pool capped at the same
//! thread count).

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use perifrac_cache::Layout;
use perifrac_cache::frames::FrameRange;
use perifrac_cache::manifest::Manifest;
use perifrac_cache::mesh::{SurfaceEncoder, SurfaceMesh};
use perifrac_cache::scene::VdbSpec;
use rayon::prelude::*;

use super::{FrameStats, StepSeconds, initialize, surface_frame};
use crate::error::{Result, SurfaceError};
use crate::frame_range;
use crate::write_encoded as write;

impl FrameStats {
    /// Adds another frame's counts and times (the voxel size is the largest).
    fn add(&mut self, s: &FrameStats) {
        self.particles += s.particles;
        self.fragments += s.fragments;
        self.debris_fragments += s.debris_fragments;
        self.debris_particles += s.debris_particles;
        self.dropped_particles += s.dropped_particles;
        self.active_voxels += s.active_voxels;
        self.triangles += s.triangles;
        self.voxel_size = self.voxel_size.max(s.voxel_size);
        let (t, u) = (&mut self.seconds, &s.seconds);
        *t = StepSeconds {
            prepare: t.prepare + u.prepare,
            level_set: t.level_set + u.level_set,
            filter: t.filter + u.filter,
            mesh: t.mesh + u.mesh,
            write: t.write + u.write,
        };
    }
}

/// Runs the `vdb` method over frames `range` of the cache at `layout` (every frame
/// with `None`): writes the `.vdb` and debris files, and each frame's meshes as
/// `surface/NNNN.glb` through `encoder`; calls `progress(done, total)` after each
/// frame. A frame's files depend on that frame alone, so ranges run side by side
/// (a farm's array job) give the bytes one run over every frame gives. Returns the
/// number of frames and their counts and times summed.
pub fn stage(
    layout: &Layout,
    spec: &VdbSpec,
    range: Option<FrameRange>,
    encoder: &dyn SurfaceEncoder,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<(usize, FrameStats)> {
    let manifest = Manifest::read(&layout.manifest())?;
    let range = frame_range(layout, &manifest, range)?;
    let dir = layout.surface_dir();
    std::fs::create_dir_all(&dir).map_err(|e| SurfaceError::io(&dir, e))?;
    initialize(rayon::current_num_threads());
    let total = Mutex::new(FrameStats::default());
    let done = AtomicUsize::new(0);
    range
        .frames()
        .into_par_iter()
        .try_for_each(|frame| -> Result<()> {
            let surface = surface_frame(layout, &manifest, frame, spec)?;
            let w = Instant::now();
            let meshes: Vec<SurfaceMesh> =
                surface.meshes.iter().map(|m| m.surface_mesh()).collect();
            write(
                &layout.surface(frame),
                format!("frame {frame}"),
                encoder.meshes(&meshes),
            )?;
            let mut stats = surface.stats;
            stats.seconds.write += w.elapsed().as_secs_f64();
            if let Ok(mut total) = total.lock() {
                total.add(&stats);
            }
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, range.len());
            Ok(())
        })?;
    Ok((range.len(), total.into_inner().unwrap_or_default()))
}
