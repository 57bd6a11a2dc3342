//! Checkpoints: the saved state (positions, velocities, bonds, plastic extensions,
//! Verlet's acceleration, colliders, clock) from which an interrupted run resumes
//! exactly as if it had not stopped. Scratch buffers (θ, forces) are not saved: the
//! next step recomputes them.

use std::path::Path;

use crate::error::{Result, SimError};
use crate::step::Simulation;

const MAGIC: &[u8; 8] = b"PFCKPT01";

/// Where a checkpoint leaves the run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resume {
    /// The last frame written before the checkpoint.
    pub frame: usize,
    /// Bonds broken so far.
    pub broken_bonds: u64,
}

/// Encodes the saved state of `sim` after `frame`; `scene_hash` ties it to its scene.
pub fn encode(sim: &Simulation, frame: usize, broken_bonds: u64, scene_hash: u64) -> Vec<u8> {
    let m = &sim.model;
    let mut out = Vec::new();
    out.extend_from_slice(MAGIC);
    for v in [
        scene_hash,
        m.len() as u64,
        m.bonds.len() as u64,
        sim.colliders.len() as u64,
        frame as u64,
        sim.steps,
        broken_bonds,
    ] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out.extend_from_slice(&sim.time.to_le_bytes());
    for p in m
        .particles
        .position
        .iter()
        .chain(&m.particles.velocity)
        .chain(sim.acceleration())
    {
        for x in p {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
    out.extend_from_slice(&sim.anchor_work.to_le_bytes());
    for nb in &m.bonds.neighbours {
        out.extend_from_slice(&nb.to_le_bytes());
    }
    if let Some(p) = &m.plastic {
        for e in &p.extension {
            out.extend_from_slice(&e.to_le_bytes());
        }
    }
    for c in &sim.colliders {
        for x in c.center.iter().chain(&c.velocity) {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
    out
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> std::result::Result<[u8; N], String> {
        let s = self
            .bytes
            .get(self.at..self.at + N)
            .ok_or("checkpoint is truncated")?;
        self.at += N;
        let mut a = [0u8; N];
        a.copy_from_slice(s);
        Ok(a)
    }
    fn u64(&mut self) -> std::result::Result<u64, String> {
        Ok(u64::from_le_bytes(self.take()?))
    }
    fn f64(&mut self) -> std::result::Result<f64, String> {
        Ok(f64::from_le_bytes(self.take()?))
    }
}

/// Restores a checkpoint into `sim` (built from the same scene).
pub fn restore(path: &Path, sim: &mut Simulation, scene_hash: u64) -> Result<Resume> {
    let bytes = std::fs::read(path).map_err(|e| SimError::io(path, e))?;
    let fail = |message: String| SimError::Cache {
        path: path.to_path_buf(),
        message,
    };
    if bytes.get(..8) != Some(MAGIC.as_slice()) {
        return Err(fail("not a perifrac checkpoint".into()));
    }
    let mut r = Reader {
        bytes: &bytes,
        at: 8,
    };
    let header: Vec<u64> = (0..7)
        .map(|_| r.u64())
        .collect::<std::result::Result<_, _>>()
        .map_err(fail)?;
    let [hash, n, bonds, colliders, frame, steps, broken] = header[..] else {
        return Err(fail("checkpoint header is incomplete".into()));
    };
    if hash != scene_hash {
        return Err(fail("the checkpoint was written for a different scene (or different settings); run without --resume".into()));
    }
    let m = &mut sim.model;
    if n as usize != m.len()
        || bonds as usize != m.bonds.len()
        || colliders as usize != sim.colliders.len()
    {
        return Err(fail(format!(
            "checkpoint has {n} particles, {bonds} bonds, {colliders} colliders; the scene gives {}, {}, {}",
            m.len(),
            m.bonds.len(),
            sim.colliders.len()
        )));
    }
    let mut acceleration = vec![[0.0f64; 3]; m.len()];
    let mut read = || -> std::result::Result<(), String> {
        sim.time = r.f64()?;
        let vectors = m
            .particles
            .position
            .iter_mut()
            .chain(m.particles.velocity.iter_mut());
        for p in vectors.chain(acceleration.iter_mut()) {
            for x in p.iter_mut() {
                *x = r.f64()?;
            }
        }
        sim.anchor_work = r.f64()?;
        for nb in m.bonds.neighbours.iter_mut() {
            *nb = u32::from_le_bytes(r.take()?);
        }
        if let Some(p) = &mut m.plastic {
            for e in p.extension.iter_mut() {
                *e = f64::from_le_bytes(r.take()?);
            }
        }
        for c in sim.colliders.iter_mut() {
            for x in c.center.iter_mut().chain(c.velocity.iter_mut()) {
                *x = r.f64()?;
            }
        }
        Ok(())
    };
    read().map_err(fail)?;
    sim.steps = steps;
    sim.model.update_damage();
    sim.model.update_yielded();
    sim.restore_acceleration(acceleration);
    Ok(Resume {
        frame: frame as usize,
        broken_bonds: broken,
    })
}
