//! The membrane's pass over its bonds: strains, fracture, forces and diffusion rates
//! (Han Eq. 10, 18, 22, 25, 27–28), and the state-based option's dilatations.

use std::ops::Range;
use std::time::Instant;

use perifrac_math::dist;
use rayon::iter::Either;
use rayon::prelude::*;

use super::diffusion::conductance;
use super::{BLOCK, MembraneModel, share};
use crate::family::{BROKEN, INDEX};
use crate::family::{blocks_mut, rows_mut};

impl MembraneModel {
    /// Bond strains η_ij (Eq. 10), fracture (Eq. 27–28: a bond whose strain passes
    /// η_c breaks for good), the force densities of Eq. 18 and 22 into
    /// [`MembraneModel::force`] and the diffusion rates of Eq. 25 over the bonds left
    /// intact (Eq. 28; for [`MembraneModel::step_quantity`]), in one pass gathering
    /// over each particle's bonds in a fixed order; for the state-based option, the
    /// force states of [state](crate::membrane#the-state-based-option) after a first pass for
    /// the dilatations. Returns the number of directed bonds that broke.
    pub fn internal_forces(&mut self) -> usize {
        let (t, exchanged) = (Instant::now(), self.times.exchange);
        let owned = self.owned();
        let before = share::before(self, &owned);
        let broken_first = if self.weighted_volume.is_empty() {
            0
        } else {
            let broken = self.dilatations(&owned);
            share::after_dilatations(self, &owned);
            broken
        };
        let (y, volume, body, bodies) = (&self.position, &self.volume, &self.body, &self.bodies);
        let (theta, area) = (&self.quantity, &self.area);
        let (m, dilatation) = (&self.weighted_volume, &self.dilatation);
        let (rest, weight, offsets) = (&self.rest_length, &self.weight, &self.bonds.offsets);
        let inverse_rest = &self.inverse_rest;
        let initial = &self.initial_bonds;
        // Particle i's bonds, force, damage and rate (when a body conducts); returns
        // the bonds that broke.
        let particle = |i: usize,
                        row: &mut [u32],
                        force: &mut [f64; 3],
                        damage: &mut f64,
                        rate: Option<&mut f64>| {
            let constants = &bodies[body[i] as usize];
            let (c, critical) = (constants.micromodulus, constants.critical_strain);
            let (law, alpha) = (constants.law, constants.expansion);
            let yi = y[i];
            let conducts = rate.is_some() && constants.conductivity != 0.0;
            let mut f = [0.0; 3];
            let mut flow = 0.0;
            let (mut broke, mut intact) = (0, 0);
            for (k, nb) in (offsets[i]..).zip(row.iter_mut()) {
                if *nb & BROKEN != 0 {
                    continue;
                }
                let j = (*nb & INDEX) as usize;
                let r = [y[j][0] - yi[0], y[j][1] - yi[1], y[j][2] - yi[2]];
                let length = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
                // The strain over the expanded rest length |ξ|(1 + αθ̄) (see [`law`]).
                let expanded = 1.0 + alpha * 0.5 * (theta[i] + theta[j]);
                let stretch = length * inverse_rest[k];
                let eta = if alpha == 0.0 {
                    stretch - 1.0
                } else {
                    stretch / expanded - 1.0
                };
                if eta > critical {
                    *nb |= BROKEN;
                    broke += 1;
                    continue;
                }
                intact += 1;
                if conducts {
                    flow += (theta[j] - theta[i]) * conductance(weight, inverse_rest, k) * area[j];
                }
                if length > 0.0 {
                    let s = match constants.state {
                        None => c * law.force(eta) * weight[k] * volume[j] / length,
                        Some(plane) => {
                            let (w, xi) = (weight[k], rest[k]);
                            let e = length - xi * expanded;
                            let t = |p: usize| {
                                2.0 * plane.bulk * dilatation[p] / m[p] * w * xi
                                    + 8.0 * plane.shear / m[p] * w * (e - 0.5 * dilatation[p] * xi)
                            };
                            (t(i) + t(j)) * area[j] / length
                        }
                    };
                    for a in 0..3 {
                        f[a] += s * r[a];
                    }
                }
            }
            *force = f;
            if let Some(rate) = rate {
                *rate = if conducts {
                    constants.conductivity * flow
                        / (constants.density * constants.capacity * area[i])
                } else {
                    0.0
                };
            }
            *damage = if initial[i] == 0 {
                0.0
            } else {
                1.0 - intact as f64 / initial[i] as f64
            };
            broke
        };
        let blocks = blocks_mut(&mut self.bonds.neighbours, offsets, BLOCK);
        let rates = if self.rate.is_empty() {
            Either::Right((0..blocks.len()).into_par_iter().map(|_| None))
        } else {
            Either::Left(self.rate.par_chunks_mut(BLOCK).map(Some))
        };
        let mine = &owned;
        let broken: usize = blocks
            .into_par_iter()
            .zip(self.force.par_chunks_mut(BLOCK))
            .zip(self.damage.par_chunks_mut(BLOCK))
            .zip(rates)
            .filter(|((((first, _), _), _), _)| *first < mine.end && first + BLOCK > mine.start)
            .map(|((((first, mut rows), forces), damages), mut rates)| {
                let mut broke = 0;
                for (p, (force, damage)) in forces.iter_mut().zip(damages.iter_mut()).enumerate() {
                    let i = first + p;
                    let (row, rest) = rows.split_at_mut(offsets[i + 1] - offsets[i]);
                    rows = rest;
                    if mine.contains(&i) {
                        let rate = rates.as_mut().map(|r| &mut r[p]);
                        broke += particle(i, row, force, damage, rate);
                    }
                }
                broke
            })
            .sum();
        let broken = share::after_forces(self, &owned, before, broken_first + broken);
        self.times.forces += t.elapsed().as_secs_f64() - (self.times.exchange - exchanged);
        broken
    }

    /// The first pass of the state-based option: fracture (Eq. 27–28) and the
    /// dilatation ϑ_i = (2/m_i) Σ_j W_ij |ξ_ij| e_ij A_j of every particle of a
    /// state-based body of `owned`, over its intact bonds. Returns the bonds that
    /// broke.
    fn dilatations(&mut self, owned: &Range<usize>) -> usize {
        let (y, body, bodies) = (&self.position, &self.body, &self.bodies);
        let (theta, area, m) = (&self.quantity, &self.area, &self.weighted_volume);
        let (rest, weight, offsets) = (&self.rest_length, &self.weight, &self.bonds.offsets);
        let rows = rows_mut(&mut self.bonds.neighbours, offsets);
        rows.into_par_iter()
            .zip(self.dilatation.par_iter_mut())
            .enumerate()
            .skip(owned.start)
            .take(owned.len())
            .with_min_len(256)
            .map(|(i, (row, dilatation))| {
                let constants = &bodies[body[i] as usize];
                *dilatation = 0.0;
                if constants.state.is_none() || m[i] == 0.0 {
                    return 0;
                }
                let mut sum = 0.0;
                let mut broke = 0;
                for (k, nb) in (offsets[i]..).zip(row.iter_mut()) {
                    if *nb & BROKEN != 0 {
                        continue;
                    }
                    let j = (*nb & INDEX) as usize;
                    let length = dist(y[i], y[j]);
                    let expanded = 1.0 + constants.expansion * 0.5 * (theta[i] + theta[j]);
                    if length / (rest[k] * expanded) - 1.0 > constants.critical_strain {
                        *nb |= BROKEN;
                        broke += 1;
                        continue;
                    }
                    sum += weight[k] * rest[k] * (length - rest[k] * expanded) * area[j];
                }
                *dilatation = 2.0 * sum / m[i];
                broke
            })
            .sum()
    }
}
