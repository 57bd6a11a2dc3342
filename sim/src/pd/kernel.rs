//! The per-step stages of the peridynamic model, monomorphized on what a scene needs:
//! `dilatation → plasticity → fracture → forces`. Each particle gathers over its own
//! family in a fixed order, so results do not depend on the thread count.

use std::time::Instant;

use rayon::prelude::*;

use super::{PdModel, family_volume};
use crate::family::{BROKEN, INDEX};

/// Wall time spent in each stage, in seconds, accumulated over a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StageTimes {
    /// θ (Eq. 6).
    pub dilatation: f64,
    /// Return mapping (Eq. 13–16).
    pub plasticity: f64,
    /// Bond breaking and damage (Eq. 18–19).
    pub fracture: f64,
    /// Force densities (Eq. 2–4, 8, 12).
    pub forces: f64,
}

/// Chunk size for deterministic parallel reductions (independent of thread count).
const REDUCE_CHUNK: usize = 4096;

/// Σ f(i) for i in 0..n, summed in fixed chunks and then in chunk order, so the
/// result is the same whatever the number of threads.
pub(crate) fn det_sum(n: usize, f: impl Fn(usize) -> f64 + Sync) -> f64 {
    let chunks = n.div_ceil(REDUCE_CHUNK);
    let partial: Vec<f64> = (0..chunks)
        .into_par_iter()
        .map(|c| (c * REDUCE_CHUNK..((c + 1) * REDUCE_CHUNK).min(n)).map(&f).sum())
        .collect();
    partial.into_iter().sum()
}

/// Splits `data` into the CSR rows given by `offsets`.
fn rows_mut<'a, T>(mut data: &'a mut [T], offsets: &[usize]) -> Vec<&'a mut [T]> {
    let mut rows = Vec::with_capacity(offsets.len().saturating_sub(1));
    for w in offsets.windows(2) {
        let (row, rest) = data.split_at_mut(w[1] - w[0]);
        rows.push(row);
        data = rest;
    }
    rows
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

fn step_stages<const P: bool, const F: bool, const A: bool, const L: bool>(m: &mut PdModel) -> usize {
    let t = Instant::now();
    dilatation::<F, A, L>(m);
    m.times.dilatation += t.elapsed().as_secs_f64();
    if P {
        let t = Instant::now();
        plasticity::<F, A, L>(m);
        m.times.plasticity += t.elapsed().as_secs_f64();
    }
    let mut broken = 0;
    if F {
        let t = Instant::now();
        broken = fracture::<P, A>(m);
        m.times.fracture += t.elapsed().as_secs_f64();
    }
    let t = Instant::now();
    forces::<P, F, A, L>(m);
    m.times.forces += t.elapsed().as_secs_f64();
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

/// θ_i = 3/(δ V_H∞) Σ_j ω_ij q_ij Λ e_ij V_j (Chen Eq. 6 with ω|ξ| s = ω e).
fn dilatation<const F: bool, const A: bool, const L: bool>(m: &mut PdModel) {
    let mut theta = std::mem::take(&mut m.theta);
    {
        let m = &*m;
        let y = &m.particles.position;
        let v = &m.reference.volume;
        let bonds = &m.bonds;
        theta.par_iter_mut().enumerate().with_min_len(64).for_each(|(i, th)| {
            let delta = m.bodies[m.reference.body[i] as usize].constants.delta;
            let yi = y[i];
            let mut sum = 0.0;
            for k in bonds.range(i) {
                let nb = bonds.neighbours[k];
                if F && nb & BROKEN != 0 {
                    continue;
                }
                let j = (nb & INDEX) as usize;
                let d = [y[j][0] - yi[0], y[j][1] - yi[1], y[j][2] - yi[2]];
                let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                let r = bonds.rest_length[k];
                let e = l - r;
                let lam = projection::<L>(m, i, j, d, l, r);
                let omega_e = if A {
                    m.omega.as_ref().map_or(0.0, |w| w[k] as f64) * e
                } else {
                    delta * e / r
                };
                sum += omega_e * bonds.weight[k] as f64 * lam * v[j];
            }
            *th = 3.0 * sum / (delta * family_volume(delta));
        });
    }
    m.theta = theta;
}

/// Return mapping of Chen Eq. 13–16 on each bond i→j:
/// A_dev = 4ωb p_ij(e − (δ/4)qΛθ_i − e^p); if A_dev²/2 > Ψ0 the increment
/// Δe^p = (A_dev − A_dev^c)/(4ωb p_ij) puts A_dev on the yield surface A_dev^c = √(2Ψ0)
/// sign(A_dev). (Eq. 15 prints 1/(2b); that leaves |A_dev| off the surface by a
/// factor that depends on ω — the test `return_mapping_lands_on_yield_surface`
/// shows 1/(4ωb) is the one that lands on it.) Eq. 16 then caps |e^p| at γ.
fn plasticity<const F: bool, const A: bool, const L: bool>(m: &mut PdModel) {
    let Some(mut plastic) = m.plastic.take() else { return };
    {
        let m = &*m;
        let y = &m.particles.position;
        let bonds = &m.bonds;
        let rows = rows_mut(&mut plastic.extension, &bonds.offsets);
        rows.into_par_iter().enumerate().with_min_len(64).for_each(|(i, ext)| {
            let body = &m.bodies[m.reference.body[i] as usize];
            let c = &body.constants;
            if !c.psi0.is_finite() {
                return;
            }
            let critical = (2.0 * c.psi0).sqrt();
            let yi = y[i];
            let theta = m.theta[i];
            for (slot, k) in bonds.range(i).enumerate() {
                let nb = bonds.neighbours[k];
                if F && nb & BROKEN != 0 {
                    continue;
                }
                let j = (nb & INDEX) as usize;
                let d = [y[j][0] - yi[0], y[j][1] - yi[1], y[j][2] - yi[2]];
                let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                let r = bonds.rest_length[k];
                let lam = projection::<L>(m, i, j, d, l, r);
                let omega = if A {
                    m.omega.as_ref().map_or(0.0, |w| w[k] as f64)
                } else {
                    c.delta / r
                };
                let ep = ext[slot];
                let e_dev = l - r - 0.25 * c.delta * bonds.weight[k] as f64 * lam * theta;
                let b = c.b * bonds.dev_weight[k] as f64;
                let a_dev = 4.0 * omega * b * (e_dev - ep);
                if 0.5 * a_dev * a_dev > c.psi0 {
                    let a_c = critical.copysign(a_dev);
                    let trial = ep + (a_dev - a_c) / (4.0 * omega * b);
                    let limit = c.plastic_limit * r;
                    let capped = if trial.abs() > limit { limit.copysign(trial) } else { trial };
                    ext[slot] = capped;
                }
            }
        });
    }
    m.plastic = Some(plastic);
}

/// Breaks bonds whose weighted elastic stretch s^ω = (1 + αφ)(e − e^p)/(ω|ξ|)
/// (Chen Eq. 18–19) exceeds the material's critical value, in either direction of
/// the bond (so both ends agree); then updates the damage φ. Returns the number of
/// directed bonds broken.
fn fracture<const P: bool, const A: bool>(m: &mut PdModel) -> usize {
    let mut neighbours = std::mem::take(&mut m.bonds.neighbours);
    let broken: usize = {
        let m = &*m;
        let y = &m.particles.position;
        let phi = &m.particles.damage;
        let bonds = &m.bonds;
        let rows = rows_mut(&mut neighbours, &bonds.offsets);
        rows.into_par_iter()
            .enumerate()
            .with_min_len(64)
            .map(|(i, row)| {
                let c = &m.bodies[m.reference.body[i] as usize].constants;
                if !c.critical_stretch.is_finite() {
                    return 0;
                }
                let yi = y[i];
                let mut count = 0;
                for (slot, nb) in row.iter_mut().enumerate() {
                    if *nb & BROKEN != 0 {
                        continue;
                    }
                    let k = bonds.offsets[i] + slot;
                    let j = (*nb & INDEX) as usize;
                    let d = [y[j][0] - yi[0], y[j][1] - yi[1], y[j][2] - yi[2]];
                    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    let r = bonds.rest_length[k];
                    let e = l - r;
                    let omega_r = if A {
                        m.omega.as_ref().map_or(1.0, |w| w[k] as f64) * r
                    } else {
                        c.delta
                    };
                    let (ep_ij, ep_ji) = match (&m.plastic, P) {
                        (Some(p), true) => (p.extension[k], p.extension[p.reverse[k] as usize]),
                        _ => (0.0, 0.0),
                    };
                    let s_ij = (1.0 + c.alpha * phi[i]) * (e - ep_ij) / omega_r;
                    let s_ji = (1.0 + c.alpha * phi[j]) * (e - ep_ji) / omega_r;
                    if s_ij.max(s_ji) > c.critical_stretch {
                        *nb |= BROKEN;
                        count += 1;
                    }
                }
                count
            })
            .sum()
    };
    m.bonds.neighbours = neighbours;
    if broken > 0 {
        m.update_damage();
    }
    broken
}

/// f_i = Σ_j ½(A_ij + A_ji) ŷ_ij V_j (Chen Eq. 2–3) with
/// A_ij = 4ω[a'_i q_ij Λ θ_i + b p_ij (e − e^p_ij)], the sum of Eq. 4 and Eq. 12 written
/// with a' = a − bδ/4 (see the module doc of [`super`]).
fn forces<const P: bool, const F: bool, const A: bool, const L: bool>(m: &mut PdModel) {
    let n = m.len();
    // a'_j θ_j: one gather per neighbour.
    let packed: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|j| m.bodies[m.reference.body[j] as usize].a_prime * m.theta[j])
        .collect();
    let mut force = std::mem::take(&mut m.force);
    {
        let m = &*m;
        let y = &m.particles.position;
        let v = &m.reference.volume;
        let bonds = &m.bonds;
        let packed = &packed;
        force.par_iter_mut().enumerate().with_min_len(64).for_each(|(i, fi)| {
            let c = &m.bodies[m.reference.body[i] as usize].constants;
            let (delta, b) = (c.delta, c.b);
            let yi = y[i];
            let pti = packed[i];
            let mut f = [0.0f64; 3];
            for k in bonds.range(i) {
                let nb = bonds.neighbours[k];
                if F && nb & BROKEN != 0 {
                    continue;
                }
                let j = (nb & INDEX) as usize;
                let d = [y[j][0] - yi[0], y[j][1] - yi[1], y[j][2] - yi[2]];
                let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                if l == 0.0 {
                    continue;
                }
                let r = bonds.rest_length[k];
                let e = l - r;
                let lam = projection::<L>(m, i, j, d, l, r);
                let omega = if A {
                    m.omega.as_ref().map_or(0.0, |w| w[k] as f64)
                } else {
                    delta / r
                };
                let (ep_ij, ep_ji) = match (&m.plastic, P) {
                    (Some(p), true) => (p.extension[k], p.extension[p.reverse[k] as usize]),
                    _ => (0.0, 0.0),
                };
                let ptj = packed[j];
                let a_sum = 4.0
                    * omega
                    * (lam * (pti * bonds.weight[k] as f64 + ptj * m.weight_reverse[k] as f64)
                        + b * (bonds.dev_weight[k] as f64 * (e - ep_ij) + m.dev_weight_reverse[k] as f64 * (e - ep_ji)));
                let s = 0.5 * a_sum * v[j] / l;
                f[0] += s * d[0];
                f[1] += s * d[1];
                f[2] += s * d[2];
            }
            *fi = f;
        });
    }
    m.force = force;
}

/// Σ_i V_i (c θ_i² + b Σ_j p_ij ω (e − e^p)² V_j), c = a'δV_H∞/3 = (κ − 5μ/3)/2.
/// Uses the θ of the last force evaluation.
pub(super) fn strain_energy(m: &PdModel) -> f64 {
    let y = &m.particles.position;
    let v = &m.reference.volume;
    let bonds = &m.bonds;
    det_sum(m.len(), |i| {
        let body = &m.bodies[m.reference.body[i] as usize];
        let delta = body.constants.delta;
        let c = body.a_prime * delta * family_volume(delta) / 3.0;
        let yi = y[i];
        let mut dev = 0.0;
        for k in bonds.range(i) {
            let nb = bonds.neighbours[k];
            if nb & BROKEN != 0 {
                continue;
            }
            let j = (nb & INDEX) as usize;
            let d = [y[j][0] - yi[0], y[j][1] - yi[1], y[j][2] - yi[2]];
            let r = bonds.rest_length[k];
            let e = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() - r;
            let omega = m.omega.as_ref().map_or(delta / r, |w| w[k] as f64);
            let ep = m.plastic.as_ref().map_or(0.0, |p| p.extension[k]);
            dev += omega * bonds.dev_weight[k] as f64 * (e - ep) * (e - ep) * v[j];
        }
        v[i] * (c * m.theta[i] * m.theta[i] + body.constants.b * dev)
    })
}
