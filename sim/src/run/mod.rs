//! From a scene to frames on disk: `setup` builds the world, `frames` steps it
//! frame by frame writing the cache and checkpoints, `resume` continues an
//! interrupted run from its checkpoint.

mod frames;
mod resume;
mod setup;

use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::Instant;

pub use resume::{Plan, plan as resume_plan};
pub use setup::{Prepared, prepare, prepare_discretized, prepare_shared, uses_fem, uses_membrane};

use crate::cache::manifest::Manifest;
use crate::cache::{Layout, write_atomic};
use crate::error::{Result, SimError};
use crate::geometry::discretize::discretize;
use crate::memory::{MemoryLimit, estimate_before_meshing, estimate_memory};
use crate::ranks::Ranks;
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
    pub memory_limit: Option<MemoryLimit>,
    /// Asked from outside to stop (the CLI asks on SIGINT, SIGTERM, SIGHUP): the run
    /// finishes the step it is on (or the frame it is writing), writes a checkpoint
    /// there, marks the manifest interrupted and returns [`SimError::Interrupted`].
    pub stop: StopRequest,
    /// The ranks of a distributed run (`mpirun -np N perifrac run`): every rank runs
    /// every particle, the models split their bond work (and peridynamics its bonds'
    /// constants) over the ranks
    /// ([`crate::model::Model::share`]), and rank 0 alone writes the cache. `None` in
    /// one process.
    pub ranks: Option<Arc<dyn Ranks>>,
}

impl RunOptions {
    /// Whether this process writes the cache: rank 0, or the only process.
    pub fn writes(&self) -> bool {
        self.ranks.as_ref().is_none_or(|r| r.rank() == 0)
    }
}

/// A request to stop a run, shared between the run and whoever may ask (a signal
/// watcher): the run looks at it before each step and after each frame. The physics
/// never sees it.
#[derive(Debug, Clone, Default)]
pub struct StopRequest {
    reason: Arc<Mutex<Option<String>>>,
    /// Stop once this many steps are taken, whatever is asked (a stop reproduced at
    /// a known step).
    after_steps: Option<u64>,
}

impl StopRequest {
    /// A request that stops the run once `steps` steps are taken (a signal
    /// reproduced at a known place between two steps: the resume tests).
    pub fn after_steps(steps: u64) -> StopRequest {
        StopRequest {
            after_steps: Some(steps),
            ..StopRequest::default()
        }
    }

    /// Asks the run to stop; `reason` (e.g. `SIGTERM`) goes into the manifest and the
    /// error. The first reason stays.
    pub fn request(&self, reason: impl Into<String>) {
        let mut slot = self.reason.lock().unwrap_or_else(|e| e.into_inner());
        if slot.is_none() {
            *slot = Some(reason.into());
        }
    }

    /// The reason, if a stop was asked for.
    pub fn reason(&self) -> Option<String> {
        self.reason
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    /// The reason to stop a run that has taken `steps` steps, if any.
    pub fn reason_after(&self, steps: u64) -> Option<String> {
        match self.after_steps {
            Some(after) if steps >= after => Some(format!("a stop after {after} steps")),
            _ => self.reason(),
        }
    }
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

/// Runs a scene into `out`; `progress` is called after each frame. On a blow-up (or a
/// write that fails) the frames written so far stay on disk, the manifest is marked
/// failed with the message and the error names the step, the particle and the last
/// good frame. With `options.resume`, a cache that is already complete is returned as
/// it is, and one that cannot be resumed is refused before anything is written.
pub fn run(
    scene: &Scene,
    out: &Path,
    options: &RunOptions,
    progress: &mut dyn FnMut(Progress),
) -> Result<Manifest> {
    let start = Instant::now();
    if let Some(limit) = &options.memory_limit {
        estimate_before_meshing(scene)?.refuse_above(limit)?;
    }
    let layout = Layout::new(out);
    if options.resume
        && let resume::Plan::Complete(manifest) = resume::plan(&layout, scene, options)?
    {
        return Ok(*manifest);
    }
    if options.writes() {
        layout.create()?;
    }
    let disc = discretize(scene)?;
    if let Some(limit) = &options.memory_limit {
        estimate_memory(scene, &disc).refuse_above(limit)?;
    }
    let t_disc = start.elapsed().as_secs_f64();
    let mut prepared = prepare_shared(scene, disc, options.ranks.as_ref())?;
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
    let plan = match options.resume {
        true => resume::plan(layout, scene, options)?,
        false => resume::Plan::Fresh,
    };
    let earlier = match plan {
        resume::Plan::Complete(manifest) => return Ok(*manifest),
        resume::Plan::Fresh => None,
        resume::Plan::Continue(manifest) => Some(manifest),
    };
    if options.writes() {
        layout.create()?;
        layout.remove_temporary_files();
        for (writes, dir) in [
            (scene.output.writes_tets(), layout.tets_dir()),
            (scene.output.writes_sheets(), layout.sheet_dir()),
        ] {
            if writes {
                std::fs::create_dir_all(&dir).map_err(|e| SimError::io(&dir, e))?;
            }
        }
        write_atomic(&layout.scene(), scene.to_toml().as_bytes())?;
    }
    if let Some(ranks) = &options.ranks {
        for part in &mut prepared.world.parts {
            part.model.share(ranks.clone());
        }
    }
    let mut frames = frames::Frames::new(scene, layout, &prepared, options, start, progress);
    frames.write_collider_meshes(&prepared.world)?;
    if let Some(earlier) = earlier
        && layout.checkpoint().is_file()
    {
        let expected = resume::Expected {
            scene_hash: scene_hash(scene),
            steps_per_frame: prepared.steps_per_frame,
            frame_count: scene.frame_count(),
            frame_length: scene.frame_time(),
        };
        let from = resume::restore(
            layout,
            &mut prepared.world,
            expected,
            scene.output.writes_tets(),
            *earlier,
        )?;
        frames.resume_from(from);
    }
    frames.run(&mut prepared.world, &prepared.timings)
}
