//! The per-step stages of the peridynamic model, monomorphized on what a scene needs:
//! `dilatation (+ plasticity) → forces (+ fracture)`. Each particle gathers over its own
//! family in a fixed order, so results do not depend on the thread count.

use std::ops::Range;
use std::time::Instant;

use perifrac_math::det_sum;
use rayon::iter::Either;
use rayon::prelude::*;

use super::{PdModel, family_volume, share};
use crate::family::{BROKEN, INDEX, rows_mut};

/// Wall time spent in each stage, in seconds, accumulated over a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StageTimes {
    /// θ (Eq. 6), with the return mapping (Eq. 13–16) in the same pass when a
    /// material yields.
    pub dilatation: f64,
    /// Force densities (Eq. 2–4, 8, 12), with bond breaking and damage
    /// (Eq. 18–19) in the same pass when the scene can fracture.
    pub forces: f64,
    /// Sending this rank's results of both and taking in the other ranks' (a
    /// distributed run, [`super::share`]; 0 in one process).
    #[serde(default)]
    pub exchange: f64,
}

macro_rules! dispatch_features {
    ($m:expr, $($p:literal $f:literal $a:literal $l:literal),*) => {{
        let f = $m.features;
        match (f.plastic, f.fracture, f.anisotropic, f.paper_form) {
            $(($p, $f, $a, $l) => step_stages::<$p, $f, $a, $l>($m),)*
        }
    }};
}

/// Runs the stages with the kernel compiled for the scene's features.
pub(super) fn dispatch(m: &mut PdModel) -> usize {
    dispatch_features!(m,
        false false false false, false false false true, false false true false, false false true true,
        false true false false, false true false true, false true true false, false true true true,
        true false false false, true false false true, true false true false, true false true true,
        true true false false, true true false true, true true true false, true true true true)
}

/// Each stage runs over the particles this process owns (all of them but in a
/// distributed run, [`super::share`]); a shared model then takes in the other ranks'
/// results before the next stage reads them.
fn step_stages<const P: bool, const F: bool, const A: bool, const L: bool>(
    m: &mut PdModel,
) -> usize {
    let owned = m.owned();
    let t = Instant::now();
    let before = share::Before::dilatation(m, &owned);
    dilatation_plasticity::<P, F, A, L>(m, &owned);
    let exchange = Instant::now();
    m.times.dilatation += (exchange - t).as_secs_f64();
    share::after_dilatation(m, &owned, before);
    m.times.exchange += exchange.elapsed().as_secs_f64();
    let t = Instant::now();
    let before = share::Before::forces(m, &owned);
    let broken = forces::<P, F, A, L>(m, &owned);
    let exchange = Instant::now();
    m.times.forces += (exchange - t).as_secs_f64();
    let broken = share::after_forces(m, &owned, before, broken);
    m.times.exchange += exchange.elapsed().as_secs_f64();
    broken
}

/// ŷ·ξ̂ for the paper's form, 1 otherwise.
#[inline(always)]
fn projection<const L: bool>(m: &PdModel, i: usize, j: usize, d: [f64; 3], l: f64, r: f64) -> f64 {
    if L {
        let x = &m.reference.position;
        let xi = [x[j][0] - x[i][0], x[j][1] - x[i][1], x[j][2] - x[i][2]];
        (d[0] * xi[0] + d[1] * xi[1] + d[2] * xi[2]) / (l * r)
    } else {
        1.0
    }
}

/// θ_i for every particle of `owned` (Chen Eq. 6) and, when a material yields, the
/// return mapping of its bonds right after (the family's data is still in cache).
fn dilatation_plasticity<const P: bool, const F: bool, const A: bool, const L: bool>(
    m: &mut PdModel,
    owned: &Range<usize>,
) {
    let mut theta = std::mem::take(&mut m.theta);
    let mut plastic = if P { m.plastic.take() } else { None };
    {
        let m = &*m;
        match plastic.as_mut() {
            Some(p) => {
                let rows = rows_mut(&mut p.extension, &m.bonds.offsets);
                theta
                    .par_iter_mut()
                    .zip(rows)
                    .zip(p.yielded.par_iter_mut())
                    .enumerate()
                    .skip(owned.start)
                    .take(owned.len())
                    .with_min_len(64)
                    .for_each_init(Vec::new, |stretch, (i, ((th, ext), yielded))| {
                        if m.is_frozen(i) {
                            *th = 0.0;
                            return;
                        }
                        *th = dilatation::<F, L, true>(m, i, stretch);
                        *yielded = return_mapping::<F, A>(m, i, *th, ext, stretch);
                    });
            }
            None => theta
                .par_iter_mut()
                .enumerate()
                .skip(owned.start)
                .take(owned.len())
                .with_min_len(64)
                .for_each(|(i, th)| {
                    *th = if m.is_frozen(i) {
                        0.0
                    } else {
                        dilatation::<F, L, false>(m, i, &mut Vec::new())
                    }
                }),
        }
    }
    m.theta = theta;
    m.plastic = plastic;
}

/// θ_i = 3/(δ V_H∞) Σ_j ω_ij q_ij Λ e_ij V_j (Chen Eq. 6 with ω|ξ| s = ω e). With
/// `KEEP`, each bond's (e, Λ) goes into `kept` (in family order) for the return
/// mapping that follows.
#[inline(always)]
fn dilatation<const F: bool, const L: bool, const KEEP: bool>(
    m: &PdModel,
    i: usize,
    kept: &mut Vec<[f64; 2]>,
) -> f64 {
    let y = &m.particles.position;
    let v = &m.reference.volume;
    let bonds = &m.bonds;
    let delta = m.bodies[m.reference.body[i] as usize].constants.delta;
    let yi = y[i];
    let mut sum = 0.0;
    if KEEP {
        kept.clear();
    }
    let first = m.coef.first;
    for k in bonds.range(i) {
        let nb = bonds.neighbours[k];
        if F && nb & BROKEN != 0 {
            if KEEP {
                kept.push([0.0, 0.0]);
            }
            continue;
        }
        let j = (nb & INDEX) as usize;
        let d = [y[j][0] - yi[0], y[j][1] - yi[1], y[j][2] - yi[2]];
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let r = m.coef.rest_length[k - first];
        let e = l - r;
        let lam = projection::<L>(m, i, j, d, l, r);
        if KEEP {
            kept.push([e, lam]);
        }
        sum += m.coef.dil[k - first] as f64 * e * lam * v[j];
    }
    3.0 * sum / (delta * family_volume(delta))
}

/// Return mapping of Chen Eq. 13–16 on each bond i→j:
/// A_dev = 4ωb p_ij(e − (δ/4)qΛθ_i − e^p); if A_dev²/2 > Ψ0 the increment
/// Δe^p = (A_dev − A_dev^c)/(4ωb p_ij) puts A_dev on the yield surface A_dev^c = √(2Ψ0)
/// sign(A_dev). (Eq. 15 prints 1/(2b); that leaves |A_dev| off the surface by a
/// factor that depends on ω — the test `return_mapping_lands_on_yield_surface`
/// shows 1/(4ωb) is the one that lands on it.) Eq. 16 then caps |e^p| at γ.
/// `kept` holds each bond's (e, Λ) from [`dilatation`]. Returns whether any bond of
/// the particle has a plastic extension.
#[inline(always)]
fn return_mapping<const F: bool, const A: bool>(
    m: &PdModel,
    i: usize,
    theta: f64,
    ext: &mut [f64],
    kept: &[[f64; 2]],
) -> bool {
    let bonds = &m.bonds;
    let c = &m.bodies[m.reference.body[i] as usize].constants;
    if !c.psi0.is_finite() {
        return false;
    }
    let critical = (2.0 * c.psi0).sqrt();
    let inv_delta = 1.0 / c.delta;
    let mut yielded = false;
    let coef = &m.coef;
    for (slot, k) in bonds.range(i).enumerate() {
        if F && bonds.neighbours[k] & BROKEN != 0 {
            continue;
        }
        let [e, lam] = kept[slot];
        let k = k - coef.first;
        let r = coef.rest_length[k];
        let ep = ext[slot];
        // q_ij = (ω q_ij)/ω with ω = δ/|ξ| (or the stored anisotropic ω);
        // 4ω b p_ij = 4 × the deviatoric coefficient.
        let q = if A {
            coef.dil[k] as f64 / coef.omega.as_ref().map_or(1.0, |w| w[k] as f64)
        } else {
            coef.dil[k] as f64 * r * inv_delta
        };
        let e_dev = e - 0.25 * c.delta * q * lam * theta;
        let stiffness = 4.0 * coef.dev[k] as f64;
        let a_dev = stiffness * (e_dev - ep);
        if 0.5 * a_dev * a_dev > c.psi0 {
            let a_c = critical.copysign(a_dev);
            let trial = ep + (a_dev - a_c) / stiffness;
            let limit = c.plastic_limit * r;
            ext[slot] = if trial.abs() > limit {
                limit.copysign(trial)
            } else {
                trial
            };
        }
        yielded |= ext[slot] != 0.0;
    }
    yielded
}

/// f_i = Σ_j ½(A_ij + A_ji) ŷ_ij V_j (Chen Eq. 2–3), for every particle of `owned`, with
/// A_ij = 4ω[a'_i q_ij Λ θ_i + b p_ij (e − e^p_ij)], the sum of Eq. 4 and Eq. 12 written
/// with a' = a − bδ/4 (see the module doc of [`super`]).
///
/// With fracture, the same pass then breaks each bond whose weighted elastic stretch
/// s^ω = (e − e^p)/(ω|ξ|) (Eq. 18–19) exceeds (1 + αφ) s_c in either direction (so
/// both ends agree, reading φ of the previous step), or, for a material with a
/// `critical_compression` ε_c, is compressed past the strain −(1 + αφ) ε_c
/// (crushing: (e − e^p)/|ξ| < −ε_c, a strain, not Eq. 19's weighted stretch; see
/// the comment in [`particle_force`]), and updates φ. A crushed bond goes on pushing
/// back in compression (see the module doc of [`super`]).
///
/// Eq. 19 prints s^ω = (1 + αφ)(e − e^p)/δ, which makes a damaged particle's bonds
/// break *sooner*: in the test `alpha_leaves_fewer_larger_fragments` that form gave
/// 10202 fragments with α = 20 against 3697 with α = 0. Chen's text says α works by
/// "continuously increasing the crack threshold as the material gets damaged" to avoid
/// small fragments, so the factor divides the stretch here, as the text intends.
/// Returns the number of directed bonds broken.
fn forces<const P: bool, const F: bool, const A: bool, const L: bool>(
    m: &mut PdModel,
    owned: &Range<usize>,
) -> usize {
    let n = m.len();
    // a'_j θ_j: one gather per neighbour.
    let packed: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|j| m.bodies[m.reference.body[j] as usize].a_prime * m.theta[j])
        .collect();
    let mut force = std::mem::take(&mut m.force);
    let mut neighbours = std::mem::take(&mut m.bonds.neighbours);
    let mut crushed = m.crushed.take();
    let mut damage = if F {
        m.particles.damage.clone()
    } else {
        Vec::new()
    };
    let broken = {
        let m = &*m;
        let rows = rows_mut(&mut neighbours, &m.bonds.offsets);
        if F {
            // e^c of each particle's bonds; empty rows, not stored, when no material
            // crushes.
            let crushed_rows = match crushed.as_mut() {
                Some(c) => Either::Left(rows_mut(c, &m.bonds.offsets).into_par_iter()),
                None => Either::Right((0..n).into_par_iter().map(|_| Default::default())),
            };
            rows.into_par_iter()
                .zip(crushed_rows)
                .zip(force.par_iter_mut())
                .zip(damage.par_iter_mut())
                .enumerate()
                .skip(owned.start)
                .take(owned.len())
                .with_min_len(64)
                .map(|(i, (((row, cr), fi), phi))| {
                    let (f, broken, intact) = particle_force::<P, F, A, L>(m, &packed, i, row, cr);
                    *fi = f;
                    if broken > 0 {
                        *phi = 1.0 - intact as f64 / m.reference.initial_bonds[i].max(1) as f64;
                    }
                    broken
                })
                .sum()
        } else {
            rows.into_par_iter()
                .zip(force.par_iter_mut())
                .enumerate()
                .skip(owned.start)
                .take(owned.len())
                .with_min_len(64)
                .for_each(|(i, (row, fi))| {
                    *fi = particle_force::<P, F, A, L>(m, &packed, i, row, &mut []).0
                });
            0
        }
    };
    m.bonds.neighbours = neighbours;
    m.crushed = crushed;
    m.force = force;
    if F {
        m.particles.damage = damage;
    }
    broken
}

/// The force density on particle i, and (with fracture) how many of its bonds broke
/// and how many stay intact; `crushed` holds e^c of i's bonds (empty when no
/// material crushes) and is updated. A particle in the rigid phase has no force and
/// keeps its bonds as they are ([`PdModel::frozen`]).
#[inline(always)]
fn particle_force<const P: bool, const F: bool, const A: bool, const L: bool>(
    m: &PdModel,
    packed: &[f64],
    i: usize,
    row: &mut [u32],
    crushed: &mut [f32],
) -> ([f64; 3], usize, usize) {
    let y = &m.particles.position;
    let v = &m.reference.volume;
    let bonds = &m.bonds;
    let coef = &m.coef;
    let c = &m.bodies[m.reference.body[i] as usize].constants;
    let delta = c.delta;
    let phi = &m.particles.damage;
    let yi = y[i];
    let pti = packed[i];
    // Eq. 19's (1 + αφ) raises the threshold as the material is damaged (see below).
    let gi = 1.0 / (1.0 + c.alpha * phi[i]);
    // Bond k's constants are at k − first ([`super::Coefficients`]).
    let first_bond = bonds.offsets[i];
    let start = first_bond - coef.first;
    let mut f = [0.0f64; 3];
    let (mut broken, mut intact) = (0, 0);
    if m.is_frozen(i) {
        return (f, 0, row.iter().filter(|&&nb| nb & BROKEN == 0).count());
    }
    for (slot, nb) in row.iter_mut().enumerate() {
        // A bond broken in tension does nothing; a crushed one (finite e^c) pushes back.
        let crushed_bond = F && *nb & BROKEN != 0;
        if crushed_bond && !crushed.get(slot).is_some_and(|ec| ec.is_finite()) {
            continue;
        }
        let k = start + slot;
        let j = (*nb & INDEX) as usize;
        let d = [y[j][0] - yi[0], y[j][1] - yi[1], y[j][2] - yi[2]];
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let r = coef.rest_length[k];
        let e = l - r;
        if crushed_bond {
            if m.is_frozen(j) {
                // Rigid pieces meet the free particles through contact instead.
                continue;
            }
            // Crushed glass yields at the strain ε_c: e^c follows e down.
            let ec = &mut crushed[slot];
            *ec = ec.min((e + c.critical_compression * r) as f32);
            let elastic = e - f64::from(*ec);
            if elastic < 0.0 && l > 0.0 {
                // ½ (A_ij + A_ji) with A = 4ω b p (e − e^c): compression only.
                let half_a = 2.0 * (coef.dev[k] as f64 + coef.dev_rev[k] as f64) * elastic;
                let s = half_a * v[j] / l;
                f[0] += s * d[0];
                f[1] += s * d[1];
                f[2] += s * d[2];
            }
            continue;
        }
        let (ep_ij, ep_ji) = match (&m.plastic, &coef.reverse, P) {
            (Some(p), Some(reverse), true) => (
                if p.yielded[i] {
                    p.extension[first_bond + slot]
                } else {
                    0.0
                },
                if p.yielded[j] {
                    p.extension[reverse[k] as usize]
                } else {
                    0.0
                },
            ),
            _ => (0.0, 0.0),
        };
        if l > 0.0 {
            let lam = projection::<L>(m, i, j, d, l, r);
            let ptj = packed[j];
            // ½ (A_ij + A_ji) = 2 [Λ (a'θ_i ω q_ij + a'θ_j ω q_ji) + ω b p_ij (e − e^p_ij) + ω b p_ji (e − e^p_ji)]
            let half_a = 2.0
                * (lam * (pti * coef.dil[k] as f64 + ptj * coef.dil_rev[k] as f64)
                    + coef.dev[k] as f64 * (e - ep_ij)
                    + coef.dev_rev[k] as f64 * (e - ep_ji));
            let s = half_a * v[j] / l;
            f[0] += s * d[0];
            f[1] += s * d[1];
            f[2] += s * d[2];
        }
        if F {
            // s^ω > s_c ⟺ (1 + αφ)(e − e^p) > s_c ω|ξ|, and ω|ξ| = δ when isotropic.
            let omega_r = if A {
                coef.omega.as_ref().map_or(0.0, |w| w[k] as f64) * r
            } else {
                delta
            };
            let gj = if c.alpha != 0.0 {
                1.0 / (1.0 + c.alpha * phi[j])
            } else {
                1.0
            };
            let (s_i, s_j) = (gi * (e - ep_ij), gj * (e - ep_ji));
            // Crushing (ours; Chen's bonds break only in tension, so they store any
            // compression and give it back as speed) compares the bond's strain
            // (e − e^p)/|ξ| with −ε_c. Eq. 19's weighting, (e − e^p)/δ, would let a bond
            // of |ξ| = 0.3δ carry 3.3× the strain (and stress) of one of δ before it
            // crushes: a strain bounds every bond's compressive stress alike, near E ε_c,
            // and so what a crushed zone can give back, about ε_c c_p (52 m/s for the
            // demo's glass at ε_c = 0.01). Measured on the demo at seed 1 with the same
            // contact (docs/lattice.md): the weighted form threw a particle at 2.11×
            // the ball's speed, the strain 1.29×.
            let crush = s_i.min(s_j) < -c.critical_compression * r;
            if s_i.max(s_j) > c.critical_stretch * omega_r || crush {
                *nb |= BROKEN;
                broken += 1;
                // A crushed bond pushes back from here (module doc of `super`).
                if crush && let Some(ec) = crushed.get_mut(slot) {
                    *ec = (e + c.critical_compression * r) as f32;
                }
            } else {
                intact += 1;
            }
        }
    }
    (f, broken, intact)
}

/// Σ_i V_i (c θ_i² + b Σ_j p_ij ω (e − e^p)² V_j), c = a'δV_H∞/3 = (κ − 5μ/3)/2, with
/// crushed bonds' min(e − e^c, 0) for e − e^p. Uses the θ of the last force evaluation.
/// A shared model sums each rank's particles' terms, gathered in particle order, so
/// the sum is the single process's to the bit.
pub(super) fn strain_energy(m: &PdModel) -> f64 {
    let y = &m.particles.position;
    let v = &m.reference.volume;
    let (bonds, coef) = (&m.bonds, &m.coef);
    let energy = |i: usize| {
        let body = &m.bodies[m.reference.body[i] as usize];
        let delta = body.constants.delta;
        let c = body.a_prime * delta * family_volume(delta) / 3.0;
        let yi = y[i];
        let mut dev = 0.0;
        for k in bonds.range(i) {
            let nb = bonds.neighbours[k];
            // e^c of a crushed bond, which stores energy only while compressed; a bond
            // broken in tension stores none.
            let crushed = (nb & BROKEN != 0).then(|| {
                m.crushed
                    .as_ref()
                    .map_or(f64::INFINITY, |c| f64::from(c[k]))
            });
            if crushed.is_some_and(|ec| !ec.is_finite()) {
                continue;
            }
            let j = (nb & INDEX) as usize;
            let d = [y[j][0] - yi[0], y[j][1] - yi[1], y[j][2] - yi[2]];
            let r = coef.rest_length[k - coef.first];
            let e = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() - r;
            let elastic = match crushed {
                Some(ec) => (e - ec).min(0.0),
                None => e - m.plastic.as_ref().map_or(0.0, |p| p.extension[k]),
            };
            dev += coef.dev[k - coef.first] as f64 * elastic * elastic * v[j];
        }
        v[i] * (c * m.theta[i] * m.theta[i] + dev)
    };
    match &m.share {
        None => det_sum(m.len(), energy),
        Some(share) => {
            let mine: Vec<f64> = share.owned().into_par_iter().map(energy).collect();
            let all = share.ranks.gather(&mine).concat();
            det_sum(all.len(), |i| all[i])
        }
    }
}
