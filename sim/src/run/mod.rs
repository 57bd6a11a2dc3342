//! From a scene to frames on disk: `setup` builds the world, `frames` steps it
//! frame by frame writing the cache and checkpoints, `resume` continues an
//! interrupted run from its checkpoint.

mod frames;
mod resume;
mod setup;

use std::path::Path;
use std::time::Instant;

pub use setup::{Prepared, prepare, prepare_discretized, uses_fem, uses_membrane};

use crate::cache::manifest::Manifest;
use crate::cache::{Layout, write_atomic};
use crate::error::{Result, SimError};
use crate::geometry::discretize::discretize;
use crate::memory::{estimate_before_meshing, estimate_memory};
use crate::scene::Scene;

/// Options of a run.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Stop after this many frames (after the initial one).
    pub frames: Option<usize>,
    /// Continue from the checkpoint in the output directory.
    pub resume: bool,
    /// Refuse a scene whose estimated peak memory is above this many bytes: before
    /// meshing ([`crate::memory::estimate_before_meshing`]), and again from the
    /// meshes before any bond is built ([`crate::memory::estimate_memory`]).
    pub memory_limit: Option<u64>,
}

/// Progress of a run, reported after each frame.
#[derive(Debug, Clone, Copy)]
pub struct Progress {
    /// Frames written (including the initial one).
    pub frame: usize,
    /// Frames the run will write.
    pub frames: usize,
    /// Steps taken.
    pub steps: u64,
    /// Steps per frame.
    pub steps_per_frame: usize,
}

/// FNV-1a of the resolved scene: ties checkpoints to their scene.
pub fn scene_hash(scene: &Scene) -> u64 {
    scene.to_toml().bytes().fold(0xcbf29ce484222325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x100000001b3)
    })
}

/// Runs a scene into `out`; `progress` is called after each frame. On a blow-up the
/// frames written so far stay on disk, the manifest records what happened and the
/// error names the step, the particle and the last good frame.
pub fn run(
    scene: &Scene,
    out: &Path,
    options: &RunOptions,
    progress: &mut dyn FnMut(Progress),
) -> Result<Manifest> {
    let start = Instant::now();
    if let Some(limit) = options.memory_limit {
        estimate_before_meshing(scene)?.refuse_above(limit)?;
    }
    let layout = Layout::new(out);
    layout.create()?;
    write_atomic(&layout.scene(), scene.to_toml().as_bytes())?;
    let disc = discretize(scene)?;
    if let Some(limit) = options.memory_limit {
        estimate_memory(scene, &disc).refuse_above(limit)?;
    }
    let t_disc = start.elapsed().as_secs_f64();
    let mut prepared = prepare_discretized(scene, disc)?;
    prepared.timings.discretize = t_disc;
    run_prepared(scene, &layout, options, prepared, start, progress)
}

/// Runs a world already built (by [`prepare`], or by the caller with models of its
/// own) into `layout`, resuming from its checkpoint if asked; `start` is when the run
/// began (for the manifest's total time).
pub fn run_prepared(
    scene: &Scene,
    layout: &Layout,
    options: &RunOptions,
    mut prepared: Prepared,
    start: Instant,
    progress: &mut dyn FnMut(Progress),
) -> Result<Manifest> {
    layout.create()?;
    if scene.output.writes_tets() {
        let dir = layout.root.join("tets");
        std::fs::create_dir_all(&dir).map_err(|e| SimError::io(&dir, e))?;
    }
    let mut frames = frames::Frames::new(scene, layout, &prepared, options, start, progress);
    if options.resume && layout.checkpoint().is_file() {
        let expected = resume::Expected {
            scene_hash: scene_hash(scene),
            steps_per_frame: prepared.steps_per_frame,
            frame_count: scene.frame_count(),
        };
        let from = resume::restore(
            layout,
            &mut prepared.world,
            expected,
            scene.output.writes_tets(),
        )?;
        frames.resume_from(from);
    }
    frames.run(&mut prepared.world, &prepared.timings)
}
