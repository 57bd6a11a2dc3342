//! Particles seeded in each body's shape: [`PARTICLES_PER_CELL_AXIS`]³ particles in
//! every cell of side `resolution`, each jittered inside its sub-cell with the
//! scene's seed, kept where the shape's signed distance is negative. Particles are
//! then ordered by grid block (body and seeding order within a block) for locality;
//! that order is the cache's and never changes.

use perifrac_math::SplitMix64;
use rayon::prelude::*;

use super::{MpmParticles, at_rest, empty_body, grid};
use crate::error::{Result, SimError};
use crate::geometry::shape::to_sdf;
use crate::scene::Scene;

/// Particles along each axis of a cell (8 a cell).
pub const PARTICLES_PER_CELL_AXIS: usize = 2;
/// Jitter amplitude as a fraction of the sub-cell side: offsets are uniform in
/// ±`SEED_JITTER`/2 sub-cells about the sub-cell centre.
pub const SEED_JITTER: f64 = 0.5;

/// Seeds every body of the scene (all MPM) on the grid of spacing the smallest
/// resolution.
pub(super) fn seed(scene: &Scene) -> Result<MpmParticles> {
    let mut rng = SplitMix64::new(scene.scene.seed);
    let mut position = Vec::new();
    let mut volume = Vec::new();
    let mut mass = Vec::new();
    let mut body = Vec::new();
    for (b, spec) in scene.bodies.iter().enumerate() {
        let sdf = to_sdf(&spec.shape, &scene.base_dir).map_err(|message| SimError::Mesh {
            body: spec.name.clone(),
            message,
        })?;
        let s = spec.resolution / PARTICLES_PER_CELL_AXIS as f64;
        let v = s * s * s;
        let rho = scene.materials[&spec.material].density;
        let (lo, hi) = sdf.bounds();
        let first = lo.map(|l| (l / s).floor() as i64);
        let last = hi.map(|h| (h / s).ceil() as i64);
        let before = position.len();
        for k in first[2]..last[2] {
            for j in first[1]..last[1] {
                for i in first[0]..last[0] {
                    let x = [i, j, k]
                        .map(|c| (c as f64 + 0.5 + SEED_JITTER * (rng.next_f64() - 0.5)) * s);
                    if sdf.distance(x) < 0.0 {
                        position.push(x);
                        volume.push(v);
                        mass.push(rho * v);
                        body.push(b as u32);
                    }
                }
            }
        }
        if position.len() == before {
            return Err(empty_body(&spec.name));
        }
    }
    let dx = grid::spacing(scene);
    let mut order: Vec<(u64, usize)> = position
        .par_iter()
        .enumerate()
        .map(|(p, x)| (grid::block_order(*x, dx), p))
        .collect();
    order.par_sort_unstable();
    Ok(at_rest(
        pick(&order, &position),
        pick(&order, &volume),
        pick(&order, &mass),
        pick(&order, &body),
    ))
}

/// `values` in the order of `order`'s indices.
fn pick<T: Copy>(order: &[(u64, usize)], values: &[T]) -> Vec<T> {
    order.iter().map(|&(_, p)| values[p]).collect()
}
