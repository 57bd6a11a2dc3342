//! The diffusion of a quantity θ through the sheet (Han Eq. 25–26, 28): its rate,
//! the forward Euler step with the sources and sinks of [`super::source`], and the
//! conserved total. The rate is also found in the force pass over the bonds
//! ([`MembraneModel::internal_forces`]), from [`conductance`].

use std::time::Instant;

use perifrac_math::det_sum;
use rayon::prelude::*;

use super::{Effect, MembraneModel};
use crate::family::{BROKEN, INDEX};

/// W_ij/|ξ_ij|² of bond `k`, the bond's factor in the diffusion law (Eq. 25).
#[inline]
pub(super) fn conductance(weight: &[f64], inverse_rest: &[f64], k: usize) -> f64 {
    weight[k] * inverse_rest[k] * inverse_rest[k]
}

impl MembraneModel {
    /// The rate θ̇_i of Eq. 25 over intact bonds (Eq. 28), for every particle.
    pub fn quantity_rate(&self) -> Vec<f64> {
        let (theta, area, body, bodies) = (&self.quantity, &self.area, &self.body, &self.bodies);
        let bonds = &self.bonds;
        (0..self.len())
            .into_par_iter()
            .with_min_len(256)
            .map(|i| {
                let b = &bodies[body[i] as usize];
                if b.conductivity == 0.0 {
                    return 0.0;
                }
                let mut sum = 0.0;
                for k in bonds.range(i) {
                    let nb = bonds.neighbours[k];
                    if nb & BROKEN != 0 {
                        continue;
                    }
                    let j = (nb & INDEX) as usize;
                    sum += (theta[j] - theta[i])
                        * conductance(&self.weight, &self.inverse_rest, k)
                        * area[j];
                }
                b.conductivity * sum / (b.density * b.capacity * area[i])
            })
            .collect()
    }

    /// One forward Euler step of the diffusion (Eq. 26, first line, with γ* of
    /// Eq. 28) from the current state: the rates of [`MembraneModel::quantity_rate`],
    /// then [`MembraneModel::step_quantity`].
    pub fn diffuse(&mut self, dt: f64) {
        if !self.rate.is_empty() {
            self.rate = self.quantity_rate();
        }
        self.step_quantity(dt);
    }

    /// The diffusion step with the rates the last [`MembraneModel::internal_forces`]
    /// found: θ_i ← θ_i + Δt θ̇_i, then the sources active at the step's start
    /// ([`source`](super::source)): a rate adds Δt × rate, a value holds θ (sources
    /// in scene order, so a later value wins).
    pub fn step_quantity(&mut self, dt: f64) {
        if self.rate.is_empty() && self.sources.is_empty() {
            return;
        }
        let t = Instant::now();
        self.quantity
            .par_iter_mut()
            .zip(self.rate.par_iter())
            .with_min_len(8192)
            .for_each(|(theta, r)| *theta += dt * r);
        for source in self.sources.iter().filter(|s| s.active(self.elapsed)) {
            for &i in &source.particles {
                let theta = &mut self.quantity[i as usize];
                match source.effect {
                    Effect::Rate(rate) => *theta += dt * rate,
                    Effect::Value(value) => *theta = value,
                }
            }
        }
        self.elapsed += dt;
        self.times.diffusion += t.elapsed().as_secs_f64();
    }

    /// The total quantity Σ_i ρ C A_i θ_i, which Eq. 25 conserves without sources.
    pub fn total_quantity(&self) -> f64 {
        det_sum(self.len(), |i| {
            let b = &self.bodies[self.body[i] as usize];
            b.density * b.capacity * self.area[i] * self.quantity[i]
        })
    }
}
