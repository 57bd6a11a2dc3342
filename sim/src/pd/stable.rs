//! The stable time step of velocity Verlet for the peridynamic model (Gershgorin's
//! bound on the linearized stiffness).

use rayon::prelude::*;

use super::{PdModel, family_volume};
use crate::family::INDEX;

/// The stable time step of velocity Verlet for the linearized model, 2/√λ_max with
/// λ_max ≤ max_i R_i/ρ_i by Gershgorin's theorem. R_i bounds the row sum of the
/// stiffness of particle i (force density per unit displacement):
///
/// ```text
/// R_i = 4 Σ_j ω b (p_ij + p_ji) V_j + 4 h_i Σ_j ω |a'| q_ij V_j + 4 Σ_j ω |a'| q_ji V_j h_j
/// h_i = Σ_j 3 ω q_ij V_j / (δ V_H∞)   (the sensitivity of θ_i)
/// ```
///
/// For a bond-based model this reduces to the Silling–Askari bound
/// Δt < √(2ρ / Σ_j V_j c_ij/|ξ_ij|). Returns the time step and the particle that
/// limits it.
///
/// A shared model ([`super::share`]) computes its rank's rows and gathers both
/// sums in particle order, so every rank finds the single process's step.
pub fn stable_time_step(m: &PdModel) -> (f64, usize) {
    let bonds = &m.bonds;
    let coef = &m.coef;
    let rows = coef.rows.clone();
    let gather = |mine: Vec<f64>| match &m.share {
        Some(share) => share.ranks.gather(&mine).concat(),
        None => mine,
    };
    let h = gather(
        rows.clone()
            .into_par_iter()
            .map(|i| {
                let delta = m.bodies[m.reference.body[i] as usize].constants.delta;
                let s: f64 = bonds
                    .range(i)
                    .map(|k| {
                        coef.dil[k - coef.first] as f64
                            * m.reference.volume[(bonds.neighbours[k] & INDEX) as usize]
                    })
                    .sum();
                3.0 * s / (delta * family_volume(delta))
            })
            .collect(),
    );
    let rate = gather(
        rows.into_par_iter()
            .map(|i| {
                let body = &m.bodies[m.reference.body[i] as usize];
                let ap = body.a_prime.abs();
                let (mut dev, mut dil_i, mut dil_j) = (0.0, 0.0, 0.0);
                for k in bonds.range(i) {
                    let j = (bonds.neighbours[k] & INDEX) as usize;
                    let v = m.reference.volume[j];
                    let k = k - coef.first;
                    dev += v * (coef.dev[k] + coef.dev_rev[k]) as f64;
                    dil_i += v * ap * coef.dil[k] as f64;
                    dil_j += v * ap * coef.dil_rev[k] as f64 * h[j];
                }
                4.0 * (dev + h[i] * dil_i + dil_j) / body.material.density
            })
            .collect(),
    );
    let (worst, lambda) =
        rate.iter().copied().enumerate().fold(
            (0, 0.0f64),
            |(bi, bl), (i, l)| if l > bl { (i, l) } else { (bi, bl) },
        );
    if lambda <= 0.0 {
        return (f64::INFINITY, worst);
    }
    (2.0 / lambda.sqrt(), worst)
}
