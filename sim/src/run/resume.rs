//! Continuing an interrupted run: the checkpoint restores the world, the manifest the
//! frame times already on disk, and the last split tet mesh the vertex numbering.

use crate::cache::CacheError;
use crate::cache::Layout;
use crate::cache::checkpoint::{Checkpoint, Decoder, RERUN};
use crate::cache::manifest::Manifest;
use crate::cache::vtu::TetFrame;
use crate::error::Result;
use crate::world::World;

/// Where a restored run continues.
#[derive(Debug, Clone, PartialEq)]
pub struct Resumed {
    /// The last frame written before the checkpoint.
    pub frame: usize,
    /// Bonds broken so far.
    pub broken_bonds: u64,
    /// The frame times of the frames on disk (from the manifest).
    pub frame_times: Vec<f64>,
    /// The collider centres of the frames on disk (from the manifest).
    pub collider_centers: Vec<Vec<[f64; 3]>>,
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
}

/// Restores `world` (built from the same scene) from the checkpoint in `layout`; with
/// `tets`, the split tet mesh from the last frame written before the checkpoint.
pub fn restore(
    layout: &Layout,
    world: &mut World,
    expected: Expected,
    tets: bool,
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
    check_clock(&checkpoint, world.dt, expected)
        .map_err(|message| CacheError::checkpoint(&path, format!("{message}; {RERUN}")))?;
    world.restore(
        &mut input,
        checkpoint.time,
        checkpoint.steps,
        checkpoint.broken_bonds,
    )?;
    input.finish()?;
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
    let (frame_times, collider_centers) = match Manifest::read(&layout.manifest()) {
        Ok(old) => (
            old.frame_times.into_iter().take(frame).collect(),
            old.collider_centers.into_iter().take(frame).collect(),
        ),
        Err(_) => (Vec::new(), Vec::new()),
    };
    if frame_times.len() != frame {
        return Err(CacheError::format(
            layout.manifest(),
            format!(
                "the manifest records {} frames but the checkpoint is at frame {frame}; rerun without --resume",
                frame_times.len()
            ),
        )
        .into());
    }
    Ok(Resumed {
        frame,
        broken_bonds: checkpoint.broken_bonds,
        frame_times,
        collider_centers,
    })
}

/// Checks the checkpoint's clock against the scene's: the frame within the run, the
/// steps those frames take (a checkpoint written between frames has the steps of its
/// last whole frame and fewer than one frame's more), and the time those steps reach,
/// to the bit (the world's time is steps × dt).
fn check_clock(checkpoint: &Checkpoint, dt: f64, expected: Expected) -> Result<(), String> {
    let Checkpoint {
        frame, steps, time, ..
    } = *checkpoint;
    let last = expected.frame_count as u64 + 1;
    if frame == 0 || frame > last {
        return Err(format!(
            "it is at frame {frame}, the scene has frames 1 to {last}"
        ));
    }
    let per_frame = expected.steps_per_frame.max(1) as u64;
    let first = (frame - 1) * per_frame;
    if steps < first || steps - first >= per_frame {
        return Err(format!(
            "it is at frame {frame} after {steps} steps, where the scene takes {first} steps \
             to that frame ({per_frame} a frame)"
        ));
    }
    if time.to_bits() != (steps as f64 * dt).to_bits() {
        return Err(format!(
            "its time {time:e} s is not {steps} steps of {dt:e} s"
        ));
    }
    Ok(())
}
