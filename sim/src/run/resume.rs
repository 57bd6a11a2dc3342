//! Continuing an interrupted run: the checkpoint restores the world, the manifest the
//! frame times already on disk, and the last split tet mesh the vertex numbering.

use crate::cache::CacheError;
use crate::cache::Layout;
use crate::cache::checkpoint::{Checkpoint, Decoder};
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
    /// The collider rotations of the frames on disk (from the manifest; scenes with
    /// mesh colliders).
    pub collider_rotations: Vec<Vec<[f64; 4]>>,
}

/// Restores `world` (built from the same scene) from the checkpoint in `layout`; with
/// `tets`, the split tet mesh from the last frame written before the checkpoint.
pub fn restore(layout: &Layout, world: &mut World, scene_hash: u64, tets: bool) -> Result<Resumed> {
    let path = layout.checkpoint();
    let checkpoint = Checkpoint::read(&path)?;
    let mut input = Decoder::new(&checkpoint.payload, &path);
    if checkpoint.scene_hash != scene_hash {
        return Err(CacheError::format(
            &path,
            "the checkpoint was written for a different scene (or different settings); run without --resume",
        )
        .into());
    }
    world.restore(&mut input, checkpoint.time, checkpoint.steps)?;
    input.finish()?;
    let frame = checkpoint.frame as usize;
    if tets {
        // The topology written at the checkpoint's frame keeps the vertex numbering
        // of the frames already on disk.
        let last = TetFrame::read(&layout.tets(frame))?;
        for part in &mut world.parts {
            part.model.restore_tet_frame(last.clone())?;
        }
    }
    let (frame_times, collider_centers, collider_rotations) =
        match Manifest::read(&layout.manifest()) {
            Ok(old) => (
                old.frame_times.into_iter().take(frame).collect(),
                old.collider_centers.into_iter().take(frame).collect(),
                old.collider_rotations.into_iter().take(frame).collect(),
            ),
            Err(_) => (Vec::new(), Vec::new(), Vec::new()),
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
        collider_rotations,
    })
}
