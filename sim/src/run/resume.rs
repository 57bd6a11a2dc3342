//! Continuing an interrupted run: first whether the cache can be continued at all
//! ([`plan`]: a manifest that reads, the same scene, no fewer frames than are on disk,
//! not already complete), then the checkpoint restores the world, the manifest the
//! frames already on disk, and the last split tet mesh the vertex numbering.

use super::RunOptions;
use crate::cache::checkpoint::{Checkpoint, Decoder, RERUN};
use crate::cache::manifest::{Manifest, Status};
use crate::cache::vtu::TetFrame;
use crate::cache::{CacheError, Layout};
use crate::error::Result;
use crate::scene::Scene;
use crate::world::World;

/// What `--resume` will do with the cache in a directory.
#[derive(Debug)]
pub enum Plan {
    /// There is no cache there: run from the start.
    Fresh,
    /// Continue the cache this manifest describes (from its checkpoint, or from the
    /// start when it has none).
    Continue(Box<Manifest>),
    /// Every frame is written already: nothing to run.
    Complete(Box<Manifest>),
}

/// Decides whether the cache in `layout` can be resumed with `scene` and `options`,
/// before anything is written: refuses a manifest that cannot be read, a cache written
/// for another scene, and a `--frames` that stops before the frames already on disk.
pub fn plan(layout: &Layout, scene: &Scene, options: &RunOptions) -> Result<Plan> {
    if !layout.holds_cache() {
        return Ok(Plan::Fresh);
    }
    let refuse = |path: &std::path::Path, message: String| -> Result<Plan> {
        Err(CacheError::format(path, message).into())
    };
    let manifest = match Manifest::read(&layout.manifest()) {
        Ok(m) => m,
        // Killed after its first frame and before its first manifest: nothing to keep.
        Err(_) if !layout.manifest().exists() && !layout.checkpoint().exists() => {
            return Ok(Plan::Fresh);
        }
        Err(e) => {
            return refuse(
                &layout.root,
                format!(
                    "cannot resume: {e}; without its manifest the frames on disk cannot be \
                     trusted: rerun with --force (replaces the cache) instead of --resume"
                ),
            );
        }
    };
    if let Ok(old) = std::fs::read_to_string(layout.scene())
        && old != scene.to_toml()
    {
        return refuse(
            &layout.scene(),
            "cannot resume: the cache was written by another scene (or other settings): \
             its resolved scene differs from this one; rerun with --force to replace it, or \
             write to another directory with -o"
                .into(),
        );
    }
    let all = scene.frame_count() + 1;
    if manifest.status == Status::Complete && manifest.frames() >= all {
        return Ok(Plan::Complete(Box::new(manifest)));
    }
    let last = options.frames.map_or(all, |n| (n + 1).min(all));
    if last < manifest.frames() {
        return refuse(
            &layout.root,
            format!(
                "cannot resume with --frames {}: that stops at frame {last}, but the cache \
                 already holds {} frames; resume without --frames (or with --frames {} or \
                 more), or rerun with --force to start over",
                last - 1,
                manifest.frames(),
                manifest.frames() - 1
            ),
        );
    }
    Ok(Plan::Continue(Box::new(manifest)))
}

/// Where a restored run continues.
#[derive(Debug, Clone, PartialEq)]
pub struct Resumed {
    /// The last frame written before the checkpoint.
    pub frame: usize,
    /// Bonds broken so far.
    pub broken_bonds: u64,
    /// The earlier manifest, cut back to the checkpoint's frame: the frame times,
    /// collider centres and file records of the frames on disk.
    pub manifest: Manifest,
}

/// The run a checkpoint must belong to: the scene's hash and clock.
#[derive(Debug, Clone, Copy)]
pub struct Expected {
    /// [`super::scene_hash`] of the scene.
    pub scene_hash: u64,
    /// Steps between frames.
    pub steps_per_frame: usize,
    /// Frames of the whole scene after the initial one.
    pub frame_count: usize,
    /// Seconds a frame at the start.
    pub frame_length: f64,
}

/// Restores `world` (built from the same scene) from the checkpoint in `layout`; with
/// `tets`, the split tet mesh from the last frame written before the checkpoint.
/// `expected` is the scene's hash and clock, `earlier` the cache's manifest (read by
/// [`plan`]).
pub fn restore(
    layout: &Layout,
    world: &mut World,
    expected: Expected,
    tets: bool,
    earlier: Manifest,
) -> Result<Resumed> {
    let path = layout.checkpoint();
    let checkpoint = Checkpoint::read(&path)?;
    let mut input = Decoder::new(&checkpoint.payload, &path);
    if checkpoint.scene_hash != expected.scene_hash {
        return Err(CacheError::checkpoint(
            &path,
            format!(
                "the checkpoint was written for a different scene (or different settings); {RERUN}"
            ),
        )
        .into());
    }
    world.clock.steps_per_frame = expected.steps_per_frame as u64;
    world.clock.frame_length = expected.frame_length;
    world.restore(
        &mut input,
        checkpoint.time,
        checkpoint.steps,
        checkpoint.broken_bonds,
    )?;
    input.finish()?;
    check_clock(&checkpoint, world, expected)
        .map_err(|message| CacheError::checkpoint(&path, format!("{message}; {RERUN}")))?;
    let frame = checkpoint.frame as usize;
    if tets {
        // The topology written at the checkpoint's frame keeps the vertex numbering
        // of the frames already on disk.
        let file = layout.tets(frame);
        let last = TetFrame::read(&file)?;
        for part in &mut world.parts {
            part.model
                .restore_tet_frame(last.clone())
                .map_err(|e| CacheError::checkpoint(&file, format!("{e}; {RERUN}")))?;
        }
    }
    if earlier.frames() < frame {
        return Err(CacheError::format(
            layout.manifest(),
            format!(
                "the manifest records {} frames but the checkpoint is at frame {frame}; rerun with --force instead of --resume",
                earlier.frames()
            ),
        )
        .into());
    }
    let mut manifest = earlier;
    manifest.truncate_to_frame(frame);
    Ok(Resumed {
        frame,
        broken_bonds: checkpoint.broken_bonds,
        manifest,
    })
}

/// Checks the checkpoint's clock against the scene's: the frame within the run, the
/// steps those frames take (a checkpoint written between frames has the steps of its
/// last whole frame and fewer than one frame's more). The time those steps reach was
/// checked to the bit by [`World::restore`].
fn check_clock(checkpoint: &Checkpoint, world: &World, expected: Expected) -> Result<(), String> {
    let Checkpoint { frame, steps, .. } = *checkpoint;
    let last = expected.frame_count as u64 + 1;
    if frame == 0 || frame > last {
        return Err(format!(
            "it is at frame {frame}, the scene has frames 1 to {last}"
        ));
    }
    let per_frame = world.clock.steps_per_frame.max(1);
    if frame < world.clock.frame + 1 {
        return Err(format!(
            "it is at frame {frame}, before its clock's start at frame {}",
            world.clock.frame
        ));
    }
    let first = world.frame_end(frame as usize);
    if steps < first || steps - first >= per_frame {
        return Err(format!(
            "it is at frame {frame} after {steps} steps, where the scene takes {first} steps \
             to that frame ({per_frame} a frame)"
        ));
    }
    Ok(())
}
