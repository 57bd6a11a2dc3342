//! Keeping particles apart: a pair that touches (of different bodies, or of one body
//! with no intact bond between them) never comes closer than its limit
//!
//! ```text
//! r_min = ½ (l̄_a + l̄_b)/2                  points of bodies a and b
//! r_min = ½ min(l̄, |x_i − x_j|)            one body (fragments, crack faces)
//! ```
//!
//! with l̄ = V̄^{1/3} a body's particle spacing, V̄ the mean volume of its points (a
//! mesh's surface tets are smaller than its inner ones, so the points' own spacings
//! would let surfaces come closer).
//! The spring of the module above is a
//! penalty: at a contact pressure p it lets a pair overlap by about 2.6 p/κ spacings
//! (`docs/contact.md`), and surfaces that meet fast interleave, a particle slipping
//! into the hollow between the other surface's particles. So after the forces of a
//! step, the velocities are corrected so that no pair closer than [`WATCH`] limits
//! closes past its limit in the next drift: a speculative, perfectly inelastic
//! non-penetration constraint (Catto's "speculative contacts", in the velocity form
//! of Moreau's sweeping process). With the velocity a point will drift with,
//! w_i = v_i + Δt a_i (the second half kick of this step and the first of the next),
//! the constraint of a pair is
//!
//! ```text
//! C_ij = (w_i − w_j)·n_ij + max(r − r_min, 0)/Δt ≥ 0,   n_ij = (y_i − y_j)/r
//! ```
//!
//! solved with impulses λ_ij n_ij on i and −λ_ij n_ij on j, λ_ij ≥ 0 (they push, never
//! pull), by projected Jacobi sweeps
//!
//! ```text
//! λ_ij ← max(0, λ_ij − ω_ij m_ij C_ij),   m_ij = 1/(1/m_i + 1/m_j),
//! ω_ij = 1/max(N_i, N_j)
//! ```
//!
//! with N_i the constraints on i: by Gershgorin every eigenvalue of the
//! relaxed constraint matrix is in (0, 1], so every sweep lowers the kinetic energy of
//! the relative motion it corrects and the sweeps converge. Each point gathers its
//! own pairs in list order from the previous sweep's velocities, and i and j compute
//! the same λ_ij bit for bit (every product symmetric, every difference
//! antisymmetric): the impulses of a pair are exactly opposite, so momentum is
//! conserved pair by pair, and the bytes do not depend on the thread count. λ starts
//! from 0 at every step (nothing is saved: a resumed run does the same), and the
//! constraints are the pairs within [`WATCH`] limits, which the Verlet list always
//! holds (its cut-off is max(d_ij, WATCH r_min) plus the skin), so they do not depend
//! on when the list was built.
//!
//! The correction only removes approaching velocity, so it adds no stiffness and
//! leaves the stable time step alone. A pair joined by an intact bond never takes
//! part; a bond that has just broken in tension leaves its pair beyond |x_i − x_j|,
//! one that crushed at (1 − ε_c)|x_i − x_j|: both far from half of it, so the
//! correction never carries load that a bond has just shed.

use perifrac_math::{dot, sub};
use rayon::prelude::*;

use super::{NO_BOND, ParticleContact};
use crate::family::{BROKEN, Bonds};
use crate::model::{Model, Stepping};

/// The limit r_min as a fraction of the pair's spacing (l_i + l_j)/2 (or of its
/// reference distance, for two points of one body).
pub const LIMIT: f64 = 0.5;

/// Pairs closer than this many limits are the step's constraints: a pair further
/// away would have to close by more than (WATCH − 1) r_min = ¼ spacing in one step
/// to pass its limit (about half the P-wave speed at the usual steps, well above the
/// fifth of it this is made for: `docs/contact.md`).
pub const WATCH: f64 = 1.5;

/// The most Jacobi sweeps a step takes.
const SWEEPS: usize = 200;

/// The sweeps stop when no constraint is violated by more than this fraction of its
/// limit per step: C_ij Δt ≥ −TOLERANCE r_min.
const TOLERANCE: f64 = 1e-3;

/// What keeping pairs apart has done since the start of the run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counters {
    /// Steps in which some constraint was violated and impulses were applied.
    pub steps: u64,
    /// Jacobi sweeps, summed over those steps.
    pub sweeps: u64,
    /// The most sweeps one step took.
    pub most_sweeps: u64,
    /// Steps that stopped at the sweep cap with a constraint still violated.
    pub unconverged: u64,
}

/// One constraint of a point: its partner's slot and the pair's fixed data.
#[derive(Debug, Clone, Copy)]
struct Constraint {
    /// The partner's slot among the points that take part.
    j: u32,
    /// n_ij = (y_i − y_j)/r.
    n: [f64; 3],
    /// max(r − r_min, 0)/Δt: how fast the pair may still close.
    allowance: f64,
    /// TOLERANCE r_min/Δt: the violation the sweeps leave.
    slack: f64,
    /// The reduced mass m_ij (kg).
    mass: f64,
    /// ω_ij = 1/max(N_i, N_j).
    weight: f64,
    /// The pair's impulse λ_ij (N s).
    impulse: f64,
}

impl Constraint {
    /// C_ij at the velocities `wi` of i and `wj` of j.
    fn violation(&self, wi: [f64; 3], wj: [f64; 3]) -> f64 {
        dot(sub(wi, wj), self.n) + self.allowance
    }
}

/// The data of a pair's constraint, as point i sees it: n_ij, the allowance and the
/// reduced mass. Swapping i and j gives −n_ij and the same two numbers, bit for bit.
fn pair_data(
    yi: [f64; 3],
    yj: [f64; 3],
    limit: f64,
    inverse_i: f64,
    inverse_j: f64,
    dt: f64,
) -> ([f64; 3], f64, f64) {
    let d = sub(yi, yj);
    let r = dot(d, d).sqrt();
    let n = d.map(|x| x / r);
    (n, (r - limit).max(0.0) / dt, 1.0 / (inverse_i + inverse_j))
}

impl ParticleContact {
    /// Keeps the pairs that touch at least their limit apart (module doc), after
    /// [`ParticleContact::compute`] at the same state: `acceleration[p]` are part p's
    /// accelerations (with the contact forces) and `held[p]` its anchored points. A
    /// point whose velocity is not the world's to change (anchored, or of a model
    /// that is not Verlet-stepped) acts as infinitely heavy. Returns the velocity
    /// change of every point whose velocity changes, as (part, point of the part,
    /// Δv) in increasing global order, to be added to v (the half-step velocity,
    /// before the second kick).
    pub fn separate(
        &mut self,
        models: &[&dyn Model],
        dt: f64,
        acceleration: &[&[[f64; 3]]],
        held: &[&[bool]],
    ) -> Vec<(usize, usize, [f64; 3])> {
        let points: Vec<usize> = (0..self.len()).filter(|&i| self.near[i]).collect();
        if points.is_empty() {
            return Vec::new();
        }
        let local = |i: usize| {
            let p = self.part[i] as usize;
            (p, i - self.offsets[p])
        };
        let masses: Vec<&[f64]> = models.iter().map(|m| m.points().mass).collect();
        let inverse = |i: usize| {
            let (p, k) = local(i);
            let free = models[p].stepping() == Stepping::Verlet
                && !held[p].get(k).copied().unwrap_or(true);
            if free { 1.0 / masses[p][k] } else { 0.0 }
        };
        let mut slot = vec![u32::MAX; self.len()];
        for (s, &i) in points.iter().enumerate() {
            slot[i] = s as u32;
        }
        // w = v + Δt a: the velocity of the next drift.
        let mut w: Vec<[f64; 3]> = points
            .iter()
            .map(|&i| {
                let (p, k) = local(i);
                let a = acceleration[p].get(k).copied().unwrap_or([0.0; 3]);
                [0, 1, 2].map(|x| self.velocity[i][x] + dt * a[x])
            })
            .collect();
        let inverses: Vec<f64> = points.iter().map(|&i| inverse(i)).collect();
        let bonds: Vec<Option<&Bonds>> = models
            .iter()
            .map(|m| m.contact_points().and_then(|c| c.bonds))
            .collect();
        let mut constraints: Vec<Vec<Constraint>> = points
            .par_iter()
            .map(|&i| self.constraints_of(i, dt, &slot, &bonds, &inverse))
            .collect();
        let counts: Vec<usize> = constraints.iter().map(Vec::len).collect();
        constraints
            .par_iter_mut()
            .zip(counts.par_iter())
            .for_each(|(list, &mine)| {
                for c in list {
                    c.weight = 1.0 / mine.max(counts[c.j as usize]) as f64;
                }
            });
        let mut sweeps = 0;
        loop {
            let violated = constraints.par_iter().enumerate().any(|(s, list)| {
                list.iter()
                    .any(|c| c.violation(w[s], w[c.j as usize]) < -c.slack)
            });
            if !violated {
                break;
            }
            if sweeps == SWEEPS {
                self.apart.unconverged += 1;
                break;
            }
            let change: Vec<[f64; 3]> = constraints
                .par_iter_mut()
                .enumerate()
                .map(|(s, list)| {
                    let mut total = [0.0; 3];
                    for c in list {
                        let c_ij = c.violation(w[s], w[c.j as usize]);
                        let next = (c.impulse - c.weight * c.mass * c_ij).max(0.0);
                        let step = next - c.impulse;
                        c.impulse = next;
                        for (t, n) in total.iter_mut().zip(c.n) {
                            *t += step * n;
                        }
                    }
                    total.map(|x| x * inverses[s])
                })
                .collect();
            for (ws, dw) in w.iter_mut().zip(&change) {
                for x in 0..3 {
                    ws[x] += dw[x];
                }
            }
            sweeps += 1;
        }
        if sweeps == 0 {
            return Vec::new();
        }
        self.apart.steps += 1;
        self.apart.sweeps += sweeps as u64;
        self.apart.most_sweeps = self.apart.most_sweeps.max(sweeps as u64);
        // Each point's velocity change from its pairs' final impulses, in list order.
        points
            .iter()
            .zip(&constraints)
            .zip(&inverses)
            .filter(|((_, list), inv)| **inv > 0.0 && list.iter().any(|c| c.impulse > 0.0))
            .map(|((&i, list), &inv)| {
                let mut total = [0.0; 3];
                for c in list {
                    for (t, n) in total.iter_mut().zip(c.n) {
                        *t += c.impulse * n;
                    }
                }
                let (p, k) = local(i);
                (p, k, total.map(|x| x * inv))
            })
            .collect()
    }

    /// The constraints of point i: its pairs in list order that no intact bond
    /// joins, closer than [`WATCH`] limits, and not both infinitely heavy; `slot`
    /// maps a point to its place among the points that take part.
    fn constraints_of(
        &self,
        i: usize,
        dt: f64,
        slot: &[u32],
        bonds: &[Option<&Bonds>],
        inverse: &(impl Fn(usize) -> f64 + Sync),
    ) -> Vec<Constraint> {
        let part_bonds = bonds[self.part[i] as usize];
        let intact = |k: u32| {
            k != NO_BOND && part_bonds.is_some_and(|b| b.neighbours[k as usize] & BROKEN == 0)
        };
        let mut out = Vec::new();
        for pair in &self.pairs[self.pair_offsets[i]..self.pair_offsets[i + 1]] {
            let j = pair.j as usize;
            let d = sub(self.position[i], self.position[j]);
            let r2 = dot(d, d);
            let watch = WATCH * pair.limit;
            if r2 >= watch * watch || r2 == 0.0 || intact(pair.bond) || intact(pair.reverse) {
                continue;
            }
            let (inverse_i, inverse_j) = (inverse(i), inverse(j));
            if inverse_i + inverse_j == 0.0 {
                continue;
            }
            let (n, allowance, mass) = pair_data(
                self.position[i],
                self.position[j],
                (1.0 + 2.0 * TOLERANCE) * pair.limit,
                inverse_i,
                inverse_j,
                dt,
            );
            out.push(Constraint {
                j: slot[j],
                n,
                allowance,
                slack: TOLERANCE * pair.limit / dt,
                mass,
                weight: 0.0,
                impulse: 0.0,
            });
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The constraint of a pair seen from j is that of i with n reversed, bit for bit:
    /// λ_ij = λ_ji in every sweep, and the pair's impulses λ n_ij and λ n_ji are
    /// exactly opposite (momentum conserved pair by pair).
    #[test]
    fn a_pair_sees_one_constraint_from_both_ends() {
        let mut rng = perifrac_math::SplitMix64::new(7);
        let mut value = |scale: f64| scale * (2.0 * rng.next_f64() - 1.0);
        for _ in 0..1000 {
            let yi = [0, 1, 2].map(|_| value(0.3));
            let yj = [0, 1, 2].map(|_| value(0.3));
            let wi = [0, 1, 2].map(|_| value(7.0));
            let wj = [0, 1, 2].map(|_| value(7.0));
            let (limit, dt) = (0.2 + value(0.1), 1e-4 * (1.5 + value(1.0)));
            let (mi, mj) = (1.0 / (1.0 + value(0.9)), 1.0 / (1.0 + value(0.9)));
            let (ni, ai, mass_i) = pair_data(yi, yj, limit, mi, mj, dt);
            let (nj, aj, mass_j) = pair_data(yj, yi, limit, mj, mi, dt);
            assert_eq!(ni, nj.map(|x| -x));
            assert_eq!((ai, mass_i), (aj, mass_j));
            let c = |n, allowance, mass| Constraint {
                j: 0,
                n,
                allowance,
                slack: 0.0,
                mass,
                weight: 0.25,
                impulse: 0.0,
            };
            let (ci, cj) = (c(ni, ai, mass_i), c(nj, aj, mass_j));
            assert_eq!(ci.violation(wi, wj), cj.violation(wj, wi));
        }
    }
}
