//! The peridynamic [`Simulation`]'s state in a checkpoint (the container is
//! `perifrac_cache::checkpoint`): positions, velocities, Verlet's acceleration, the
//! anchors' work, bonds (their broken bits), plastic extensions and the colliders.
//! Scratch buffers (θ, forces) are not saved: the next step recomputes them.

use std::path::Path;

use perifrac_cache::checkpoint::{Checkpoint, Decoder, Encoder};

use crate::error::Result;
use crate::family::INDEX;
use crate::step::Simulation;

/// Where a checkpoint leaves the run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resume {
    /// The last frame written before the checkpoint.
    pub frame: usize,
    /// Bonds broken so far.
    pub broken_bonds: u64,
}

/// The checkpoint file's bytes for the state of `sim` after `frame`; `scene_hash`
/// ties it to its scene.
pub fn encode(sim: &Simulation, frame: usize, broken_bonds: u64, scene_hash: u64) -> Vec<u8> {
    let m = &sim.model;
    let mut e = Encoder::new();
    e.put_f64x3_slice(&m.particles.position);
    e.put_f64x3_slice(&m.particles.velocity);
    e.put_f64x3_slice(sim.acceleration());
    e.put_f64(sim.anchor_work);
    e.put_u32_slice(&m.bonds.neighbours);
    if let Some(p) = &m.plastic {
        e.put_f64_slice(&p.extension);
    }
    let colliders: Vec<[f64; 3]> = sim
        .colliders
        .iter()
        .flat_map(|c| [c.center, c.velocity])
        .collect();
    e.put_f64x3_slice(&colliders);
    Checkpoint {
        scene_hash,
        frame: frame as u64,
        steps: sim.steps,
        broken_bonds,
        time: sim.time,
        payload: e.finish(),
    }
    .encode()
}

/// Restores the checkpoint at `path` into `sim` (built from the same scene).
pub fn restore(path: &Path, sim: &mut Simulation, scene_hash: u64) -> Result<Resume> {
    let checkpoint = Checkpoint::read(path)?;
    if checkpoint.scene_hash != scene_hash {
        return Err(perifrac_cache::CacheError::format(
            path,
            "the checkpoint was written for a different scene (or different settings); run without --resume",
        )
        .into());
    }
    let m = &mut sim.model;
    let n = m.len();
    let mut d = Decoder::new(&checkpoint.payload, path);
    let position = d.take_f64x3_slice("position", n)?;
    let velocity = d.take_f64x3_slice("velocity", n)?;
    let acceleration = d.take_f64x3_slice("acceleration", n)?;
    let anchor_work = d.take_f64("anchor work")?;
    let neighbours =
        d.take_u32_slice_checked("neighbours", m.bonds.len(), |v| ((v & INDEX) as usize) < n)?;
    let extension = match &m.plastic {
        Some(p) => Some(d.take_f64_slice("plastic extension", p.extension.len())?),
        None => None,
    };
    let colliders = d.take_f64x3_slice("colliders", 2 * sim.colliders.len())?;
    d.finish()?;
    m.particles.position = position;
    m.particles.velocity = velocity;
    m.bonds.neighbours = neighbours;
    if let (Some(p), Some(e)) = (&mut m.plastic, extension) {
        p.extension = e;
    }
    for (c, cv) in sim.colliders.iter_mut().zip(colliders.chunks_exact(2)) {
        c.center = cv[0];
        c.velocity = cv[1];
    }
    sim.time = checkpoint.time;
    sim.anchor_work = anchor_work;
    sim.steps = checkpoint.steps;
    sim.model.update_damage();
    sim.model.update_yielded();
    sim.restore_acceleration(acceleration);
    Ok(Resume {
        frame: checkpoint.frame as usize,
        broken_bonds: checkpoint.broken_bonds,
    })
}
