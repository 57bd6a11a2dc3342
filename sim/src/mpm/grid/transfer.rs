//! The three transfers of MLS-MPM (Lyu 2021 §3.2–3.4, Hu et al. 2018) over the
//! [`SparseGrid`]'s bins and blocks: particle to grid (a private scatter per bin, then
//! a gather per block), the explicit grid update with the anchors and the colliders'
//! boundary conditions, and grid to particle (APIC, or the PIC/FLIP blend).

use std::collections::HashMap;

use rayon::prelude::*;

use super::{
    BLOCK, BLOCK_NODES, BLOCK_SHIFT, Boundary, D_INVERSE_FACTOR, HELD_MASS_SHARE, NEIGHBOURS, SPAN,
    SPAN_NODES, SparseGrid, Stencil, block_key, cube_index, key_block,
};
use crate::contact::{Collider, ColliderShape};
use crate::mpm::constitutive::Mat3;

impl SparseGrid {
    /// Particle to grid (Hu et al. 2018 Eq. 16–17; Lyu §3.2): each node receives
    /// Σ_p w_ip m_p and Σ_p w_ip (m_p v_p + A_p (x_i − x_p)), where the affine momentum
    /// A_p = m_p C_p − Δt V_p⁰ D⁻¹ P_p F_pᵀ carries APIC's C and the stress (MLS-MPM).
    /// Deterministic (see the [`grid`](super) module's documentation).
    pub fn p2g(
        &mut self,
        position: &[[f64; 3]],
        mass: &[f64],
        velocity: &[[f64; 3]],
        affine: &[Mat3],
    ) {
        let dx = self.dx;
        self.scatter_each(position, |p, s, local, buffer| {
            let (m, c) = (mass[p], &affine[p]);
            // The momentum a node receives, m v + A (x_i − x_p) with
            // x_i − x_p = ((i, j, k) − fx) Δx, is q + Δx (i A₀ + j A₁ + k A₂)
            // with q = m v − Δx A fx and A_e the columns of A: sums of
            // per-axis terms hoisted out of the loops.
            let q = [0, 1, 2].map(|a| {
                m * velocity[p][a]
                    - dx * (c[a][0] * s.fx[0] + c[a][1] * s.fx[1] + c[a][2] * s.fx[2])
            });
            // column[e][n] = n Δx A_e, for the node offset n = 0, 1, 2 along e.
            let mut column = [[[0.0; 3]; 3]; 3];
            for (e, per_axis) in column.iter_mut().enumerate() {
                for (n, term) in per_axis.iter_mut().enumerate() {
                    for (a, x) in term.iter_mut().enumerate() {
                        *x = dx * n as f64 * c[a][e];
                    }
                }
            }
            for k in 0..3 {
                let (wk, ck) = (s.w[2][k], column[2][k]);
                for j in 0..3 {
                    let (wjk, cj) = (s.w[1][j] * wk, column[1][j]);
                    let row = cube_index(local[0], local[1] + j, local[2] + k, SPAN);
                    for i in 0..3 {
                        let w = s.w[0][i] * wjk;
                        let ci = column[0][i];
                        let node = &mut buffer[row + i];
                        node[0] += w * m;
                        for a in 0..3 {
                            node[1 + a] += w * (q[a] + ck[a] + cj[a] + ci[a]);
                        }
                    }
                }
            }
        });
    }

    /// A P2G of momentum alone: each node receives Σ_p w_ip m_p and Σ_p w_ip m_p v_p,
    /// the nodes [`SparseGrid::p2g`] gives with no affine momentum, to the bit, without
    /// its work on A_p; particles of zero mass (those a held P2G leaves out) are skipped.
    pub fn p2g_momentum(&mut self, position: &[[f64; 3]], mass: &[f64], velocity: &[[f64; 3]]) {
        self.scatter_each(position, |p, s, local, buffer| {
            let m = mass[p];
            if m == 0.0 {
                return;
            }
            let q = velocity[p].map(|v| m * v);
            each_node(s, local, buffer, |node, w| {
                node[0] += w * m;
                for a in 0..3 {
                    node[1 + a] += w * q[a];
                }
            });
        });
    }

    /// A P2G of a scalar s_p alone: each node receives Σ_p w_ip m_p and Σ_p w_ip m_p s_p
    /// as its mass and first momentum component (the other two zero), the nodes
    /// [`SparseGrid::p2g`] gives for the velocity (s_p, 0, 0) and no affine momentum,
    /// to the bit, at half its work. [`SparseGrid::centre_ratio`] reads them.
    pub fn p2g_scalar(&mut self, position: &[[f64; 3]], mass: &[f64], value: &[f64]) {
        self.scatter_each(position, |p, s, local, buffer| {
            let (m, q) = (mass[p], mass[p] * value[p]);
            each_node(s, local, buffer, |node, w| {
                node[0] += w * m;
                node[1] += w * q;
            });
        });
    }

    /// The scatter and gather of a P2G: each bin's particles, in their sorted order,
    /// `deposit` into the bin's private buffer (`local`: the stencil's base node in
    /// it), then [`SparseGrid::gather`].
    fn scatter_each(
        &mut self,
        position: &[[f64; 3]],
        deposit: impl Fn(usize, &Stencil, [usize; 3], &mut [[f64; 4]]) + Sync,
    ) {
        let inv_dx = 1.0 / self.dx;
        self.scatter.clear();
        self.scatter.resize(self.bins.len() * SPAN_NODES, [0.0; 4]);
        let order = &self.order;
        self.scatter
            .par_chunks_mut(SPAN_NODES)
            .zip(self.bins.par_iter())
            .for_each(|(buffer, bin)| {
                let origin = key_block(bin.key).map(|c| c << BLOCK_SHIFT);
                for &(_, p) in &order[bin.start..bin.end] {
                    let p = p as usize;
                    let s = Stencil::new(position[p], inv_dx);
                    let local = [0, 1, 2].map(|a| (s.base[a] - origin[a]) as usize);
                    deposit(p, &s, local, buffer);
                }
            });
        self.gather();
    }

    /// Each block sums the scatter buffers of the bins that overlap it, bins in the
    /// order of [`NEIGHBOURS`] reversed (the bin at the block itself first).
    fn gather(&mut self) {
        self.nodes.clear();
        self.nodes.resize(self.blocks.len() * BLOCK_NODES, [0.0; 4]);
        let bin_index: HashMap<u64, usize> = self
            .bins
            .iter()
            .enumerate()
            .map(|(i, b)| (b.key, i))
            .collect();
        let scatter = &self.scatter;
        self.nodes
            .par_chunks_mut(BLOCK_NODES)
            .zip(self.blocks.par_iter())
            .for_each(|(nodes, &key)| {
                let b = key_block(key);
                for o in NEIGHBOURS {
                    let source = block_key([b[0] - o[0], b[1] - o[1], b[2] - o[2]]);
                    let Some(&bin) = bin_index.get(&source) else {
                        continue;
                    };
                    let buffer = &scatter[bin * SPAN_NODES..(bin + 1) * SPAN_NODES];
                    // Node (i, j, k) of this block is node (i, j, k) + BLOCK·o of the
                    // bin's buffer, which holds SPAN nodes a side.
                    let shift = o.map(|c| c as usize * BLOCK);
                    let range = |a: usize| 0..(SPAN - shift[a]).min(BLOCK);
                    for k in range(2) {
                        for j in range(1) {
                            for i in range(0) {
                                let from = buffer
                                    [cube_index(i + shift[0], j + shift[1], k + shift[2], SPAN)];
                                let to = &mut nodes[cube_index(i, j, k, BLOCK)];
                                for c in 0..4 {
                                    to[c] += from[c];
                                }
                            }
                        }
                    }
                }
            });
    }

    /// Grid update (Lyu §3.4, explicit): v_i = (m v)_i / m_i + Δt g; a node held by
    /// anchors (after [`SparseGrid::keep_held`]) takes their velocity; then the
    /// colliders' boundary conditions at each node inside one: the normal velocity
    /// relative to the collider is made non-negative and Coulomb friction μ removes at
    /// most μ|Δv_n| of the tangential velocity (μ = 0 slips; a large μ sticks).
    pub fn grid_update(&mut self, dt: f64, boundary: &Boundary<'_>) {
        let dx = self.dx;
        let held = &self.held;
        self.nodes
            .par_chunks_mut(BLOCK_NODES)
            .zip(self.blocks.par_iter())
            .enumerate()
            .for_each(|(slot, (nodes, &key))| {
                let origin = key_block(key).map(|c| c << BLOCK_SHIFT);
                for k in 0..BLOCK {
                    for j in 0..BLOCK {
                        for i in 0..BLOCK {
                            let node = &mut nodes[cube_index(i, j, k, BLOCK)];
                            if node[0] <= 0.0 {
                                continue;
                            }
                            let index = slot * BLOCK_NODES + cube_index(i, j, k, BLOCK);
                            let mut v =
                                [0, 1, 2].map(|a| node[1 + a] / node[0] + dt * boundary.gravity[a]);
                            if let Some(h) = held.get(index)
                                && h[0] >= HELD_MASS_SHARE * node[0]
                            {
                                v = [h[1] / h[0], h[2] / h[0], h[3] / h[0]];
                            }
                            let x = [
                                (origin[0] + i as i64) as f64 * dx,
                                (origin[1] + j as i64) as f64 * dx,
                                (origin[2] + k as i64) as f64 * dx,
                            ];
                            for c in boundary.colliders {
                                collide(c, x, &mut v);
                            }
                            node[1..].copy_from_slice(&v);
                        }
                    }
                }
            });
    }

    /// Copies each bin's ([`SPAN`])³ neighbourhood of node velocities (and, with
    /// `previous`, the velocities before forces) out of the blocks, so that G2P reads
    /// a particle's 27 nodes at fixed strides: the reverse of [`SparseGrid::gather`].
    fn spread(&mut self, previous: bool) {
        let nodes = &self.nodes;
        let fill = |span: &mut Vec<[f64; 3]>, value: &(dyn Fn(usize) -> [f64; 3] + Sync)| {
            span.clear();
            span.resize(self.bins.len() * SPAN_NODES, [0.0; 3]);
            span.par_chunks_mut(SPAN_NODES)
                .zip(self.bins.par_iter())
                .for_each(|(buffer, bin)| {
                    for k in 0..SPAN {
                        for j in 0..SPAN {
                            for i in 0..SPAN {
                                let o = (i >> BLOCK_SHIFT)
                                    + 2 * (j >> BLOCK_SHIFT)
                                    + 4 * (k >> BLOCK_SHIFT);
                                let index = bin.neighbours[o] as usize * BLOCK_NODES
                                    + cube_index(
                                        i & (BLOCK - 1),
                                        j & (BLOCK - 1),
                                        k & (BLOCK - 1),
                                        BLOCK,
                                    );
                                buffer[cube_index(i, j, k, SPAN)] = value(index);
                            }
                        }
                    }
                });
        };
        fill(&mut self.span_velocity, &|i| {
            let n = nodes[i];
            [n[1], n[2], n[3]]
        });
        if previous {
            let before = &self.previous;
            fill(&mut self.span_previous, &|i| before[i]);
        } else {
            self.span_previous.clear();
        }
    }

    /// Grid to particle (APIC; Hu et al. 2018 Eq. 12–13): v_p = Σ_i w_ip v_i,
    /// C_p = D⁻¹ Σ_i w_ip v_i (x_i − x_p)ᵀ, x_p ← x_p + Δt v_p, F_p ← (I + Δt C_p) F_p.
    /// With `flip` = Some(α) (after [`SparseGrid::keep_velocity`]) the particle velocity
    /// is the PIC/FLIP blend α (v_p + Σ_i w_ip (v_i − v̄_i)) + (1 − α) Σ_i w_ip v_i and
    /// x_p moves with the PIC velocity.
    pub fn g2p(
        &mut self,
        dt: f64,
        flip: Option<f64>,
        position: &mut [[f64; 3]],
        velocity: &mut [[f64; 3]],
        affine: &mut [Mat3],
        deformation: &mut [Mat3],
    ) {
        self.spread(flip.is_some());
        let inv_dx = 1.0 / self.dx;
        let dx = self.dx;
        let d_inv = D_INVERSE_FACTOR * inv_dx * inv_dx;
        let (bins, bin_of) = (&self.bins, &self.bin_of);
        let (span_velocity, span_previous) = (&self.span_velocity, &self.span_previous);
        position
            .par_iter_mut()
            .zip(velocity.par_iter_mut())
            .zip(affine.par_iter_mut())
            .zip(deformation.par_iter_mut())
            .enumerate()
            .with_min_len(256)
            .for_each(|(p, (((x, v), c), f))| {
                let s = Stencil::new(*x, inv_dx);
                let b = bin_of[p] as usize;
                let origin = key_block(bins[b].key).map(|c| c << BLOCK_SHIFT);
                let local = [0, 1, 2].map(|a| (s.base[a] - origin[a]) as usize);
                let first = b * SPAN_NODES;
                // Σ w v_i and its moments Σ w v_i n_e along each axis (n_e the node's
                // offset 0, 1, 2 in the stencil): Σ w v_i (x_i − x_p)_e =
                // Δx (Σ w v_i n_e − fx_e Σ w v_i).
                let mut sum = [0.0; 3];
                let mut moment = [[0.0; 3]; 3];
                let mut before = [0.0; 3];
                for k in 0..3 {
                    let wk = s.w[2][k];
                    for j in 0..3 {
                        let wjk = s.w[1][j] * wk;
                        let row = first + cube_index(local[0], local[1] + j, local[2] + k, SPAN);
                        let mut line = [[0.0; 3]; 3];
                        for (i, wv) in line.iter_mut().enumerate() {
                            let w = s.w[0][i] * wjk;
                            let node = span_velocity[row + i];
                            *wv = node.map(|x| w * x);
                            if let Some(old) = span_previous.get(row + i) {
                                for a in 0..3 {
                                    before[a] += w * old[a];
                                }
                            }
                        }
                        for a in 0..3 {
                            let total = line[0][a] + line[1][a] + line[2][a];
                            sum[a] += total;
                            moment[a][0] += line[1][a] + 2.0 * line[2][a];
                            moment[a][1] += j as f64 * total;
                            moment[a][2] += k as f64 * total;
                        }
                    }
                }
                let mut new_c: Mat3 = [[0.0; 3]; 3];
                for ((row, m_row), total) in new_c.iter_mut().zip(&moment).zip(&sum) {
                    for ((x, m), fx) in row.iter_mut().zip(m_row).zip(&s.fx) {
                        *x = d_inv * dx * (m - fx * total);
                    }
                }
                // F ← (I + Δt C) F.
                let mut grown = *f;
                for (row, c_row) in grown.iter_mut().zip(&new_c) {
                    for (e, x) in row.iter_mut().enumerate() {
                        *x += dt * (c_row[0] * f[0][e] + c_row[1] * f[1][e] + c_row[2] * f[2][e]);
                    }
                }
                for a in 0..3 {
                    x[a] += dt * sum[a];
                }
                *v = match flip {
                    Some(alpha) => [0, 1, 2]
                        .map(|a| alpha * (v[a] + sum[a] - before[a]) + (1.0 - alpha) * sum[a]),
                    None => sum,
                };
                *c = new_c;
                *f = grown;
            });
    }
}

/// The boundary condition of collider `c` on a node at `x` with velocity `v`: nodes on
/// or below the ground, or inside a sphere or box, get a non-negative normal velocity
/// relative to the collider and Coulomb friction on the tangential part: `friction = 0`
/// slips, a finite μ rubs, `friction = inf` sticks (the node takes the collider's
/// velocity, separating or not).
fn collide(c: &Collider, x: [f64; 3], v: &mut [f64; 3]) {
    let normal = match &c.shape {
        ColliderShape::Ground => (x[1] <= c.center[1]).then_some([0.0, 1.0, 0.0]),
        _ => c.penetration(x).map(|(n, _)| n),
    };
    let Some(n) = normal else {
        return;
    };
    let cv = c.velocity_at(x);
    if c.friction == f64::INFINITY {
        // Sticky: the node moves with the collider's surface.
        *v = cv;
        return;
    }
    let rel = [0, 1, 2].map(|a| v[a] - cv[a]);
    let vn = rel[0] * n[0] + rel[1] * n[1] + rel[2] * n[2];
    if vn >= 0.0 {
        return;
    }
    let t = [0, 1, 2].map(|a| rel[a] - vn * n[a]);
    let vt = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
    let keep = if vt > 0.0 {
        (1.0 - c.friction * (-vn) / vt).max(0.0)
    } else {
        0.0
    };
    *v = [0, 1, 2].map(|a| cv[a] + keep * t[a]);
}

/// Hands `add` each of the 3³ nodes of stencil `s` in a bin's scatter `buffer` (its
/// base node at `local`) with its weight w_ip, in the order of [`SparseGrid::p2g`].
#[inline(always)]
fn each_node(
    s: &Stencil,
    local: [usize; 3],
    buffer: &mut [[f64; 4]],
    mut add: impl FnMut(&mut [f64; 4], f64),
) {
    for k in 0..3 {
        for j in 0..3 {
            let wjk = s.w[1][j] * s.w[2][k];
            let row = cube_index(local[0], local[1] + j, local[2] + k, SPAN);
            for i in 0..3 {
                add(&mut buffer[row + i], s.w[0][i] * wjk);
            }
        }
    }
}
