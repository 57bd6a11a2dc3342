//! What a scene will cost in memory, estimated before any bond is built. Whether to
//! refuse a scene is the caller's policy (the CLI compares it with what the machine
//! has); the estimate is the simulator's.

use crate::error::{Result, SimError};
use crate::family;
use crate::geometry::discretize::Discretization;
use crate::scene::Scene;

/// Bytes per particle of state and scratch (positions, velocities, reference data,
/// θ, forces, accelerations, masses, flags).
pub const BYTES_PER_PARTICLE: usize = 8 * 3 * 5 + 8 * 5 + 4 * 3 + 2;

/// What a scene will cost in memory.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MemoryEstimate {
    /// Particles.
    pub particles: usize,
    /// Directed bonds expected from each body's particle density and horizon.
    pub bonds: f64,
    /// Bytes a bond takes (more with plasticity).
    pub bytes_per_bond: usize,
    /// Total bytes of the run's state.
    pub bytes: f64,
}

/// Estimates the memory of a discretized scene: a particle's family holds about
/// V_H / (mean particle volume) − 1 bonds (fewer near surfaces).
pub fn estimate_memory(scene: &Scene, disc: &Discretization) -> MemoryEstimate {
    let plastic = scene
        .materials
        .values()
        .any(|m| (m.yield_psi0.is_some() || m.yield_stretch.is_some()) && m.plastic_limit > 0.0);
    let bytes_per_bond = family::BYTES_PER_BOND + if plastic { 12 } else { 0 };
    let bonds: f64 = scene
        .bodies
        .iter()
        .enumerate()
        .map(|(b, spec)| {
            let mesh = &disc.meshes[b];
            let count = mesh.tets.len() as f64;
            if count == 0.0 {
                return 0.0;
            }
            let mean_volume = mesh.total_volume() / count;
            let family = crate::pd::family_volume(spec.delta()) / mean_volume;
            count * (family - 1.0).max(0.0)
        })
        .sum();
    let particles = disc.position.len();
    MemoryEstimate {
        particles,
        bonds,
        bytes_per_bond,
        bytes: bonds * bytes_per_bond as f64 + (particles * BYTES_PER_PARTICLE) as f64,
    }
}

impl MemoryEstimate {
    /// Refuses a run that needs more than `limit` bytes (the caller's policy: the CLI
    /// passes the memory the machine has available).
    pub fn refuse_above(&self, limit: u64) -> Result<()> {
        if self.bytes > limit as f64 {
            let gib = |b: f64| b / (1u64 << 30) as f64;
            return Err(SimError::Refused(format!(
                "the run needs about {:.1} GiB ({} particles, {:.3e} bonds of {} bytes) but {:.1} GiB are \
                 available: use a coarser resolution or a smaller horizon",
                gib(self.bytes),
                self.particles,
                self.bonds,
                self.bytes_per_bond,
                gib(limit as f64)
            )));
        }
        Ok(())
    }
}
