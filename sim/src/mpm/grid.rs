//! The sparse background grid of MLS-MPM (Lyu 2021 §3.2, Hu et al. 2018) and the
//! three transfers: [`SparseGrid::p2g`], [`SparseGrid::grid_update`],
//! [`SparseGrid::g2p`], with quadratic B-spline weights.
//!
//! Nodes live in blocks of [`BLOCK`]³; a block exists only while a particle's stencil
//! touches it, so the grid follows the particles (a projectile in flight carries its
//! few blocks along, nothing is allocated along its path). The blocks are rebuilt
//! every step ([`SparseGrid::rebuild`]) from the particles' positions.
//!
//! **Determinism of the P2G scatter.** Particles are sorted by (block of their stencil
//! base node, particle index); the particles of one block (a *bin*) scatter, in that
//! order, into a private padded buffer of ([`BLOCK`] + 2)³ nodes — a quadratic stencil
//! reaches at most two nodes past its block. Each grid block then gathers the buffers
//! of the (up to 8) bins that overlap it, in a fixed order of neighbours. Every sum is
//! taken in an order fixed by the positions alone, so 1 and N threads give the same
//! bytes; no atomics, no locks.

use std::collections::HashMap;

use rayon::prelude::*;

use super::constitutive::Mat3;
use crate::contact::{Collider, ColliderShape};

/// Nodes along each axis of a block.
pub const BLOCK: usize = 4;
/// log₂ [`BLOCK`].
const BLOCK_SHIFT: u32 = 2;
/// Nodes of a block.
const BLOCK_NODES: usize = BLOCK * BLOCK * BLOCK;
/// Nodes along each axis of a bin's scatter buffer: the block and the two nodes a
/// quadratic stencil reaches past it.
const SPAN: usize = BLOCK + 2;
/// Nodes of a bin's scatter buffer.
const SPAN_NODES: usize = SPAN * SPAN * SPAN;
/// Bits of each block coordinate in a block key.
const KEY_BITS: u32 = 21;
/// Offset that makes block coordinates non-negative in a key.
const KEY_OFFSET: i64 = 1 << (KEY_BITS - 1);
/// The inertia-like tensor of quadratic B-splines is D = Δx²/4 I (Hu et al. 2018), so
/// D⁻¹ = `D_INVERSE_FACTOR`/Δx².
pub const D_INVERSE_FACTOR: f64 = 4.0;
/// The offsets, in blocks, of the 8 blocks a bin's buffer overlaps (x fastest).
const NEIGHBOURS: [[i64; 3]; 8] = [
    [0, 0, 0],
    [1, 0, 0],
    [0, 1, 0],
    [1, 1, 0],
    [0, 0, 1],
    [1, 0, 1],
    [0, 1, 1],
    [1, 1, 1],
];

/// The key of a block: its coordinates, offset and packed (x major, so that sorting
/// keys sorts blocks lexicographically).
fn block_key(b: [i64; 3]) -> u64 {
    let part = |c: i64| (c + KEY_OFFSET) as u64;
    (part(b[0]) << (2 * KEY_BITS)) | (part(b[1]) << KEY_BITS) | part(b[2])
}

/// The coordinates of a block from its key.
fn key_block(k: u64) -> [i64; 3] {
    let mask = (1u64 << KEY_BITS) - 1;
    [2 * KEY_BITS, KEY_BITS, 0].map(|s| ((k >> s) & mask) as i64 - KEY_OFFSET)
}

/// The key of the block a particle at `x` scatters from on a grid of spacing `dx`:
/// sorting particles by it orders them as the grid's bins.
pub fn block_order(x: [f64; 3], dx: f64) -> u64 {
    block_key(Stencil::new(x, 1.0 / dx).block())
}

/// The quadratic B-spline stencil of a particle: the first of its 3³ nodes and the
/// weights along each axis.
#[derive(Debug, Clone, Copy)]
pub struct Stencil {
    /// Grid index of the first node (the stencil spans base..base + 3).
    pub base: [i64; 3],
    /// Position in cells relative to `base`, in [0.5, 1.5).
    pub fx: [f64; 3],
    /// `w[axis][i]`: the weight of node base + i along that axis.
    pub w: [[f64; 3]; 3],
}

/// The most negative or positive node index the keys hold (positions beyond are
/// clamped; they are non-finite or kilometres away, and the blow-up detector stops
/// the run).
const NODE_LIMIT: i64 = (KEY_OFFSET - 1) * BLOCK as i64;

impl Stencil {
    /// The stencil of a particle at `x` on a grid of spacing 1/`inv_dx`.
    pub fn new(x: [f64; 3], inv_dx: f64) -> Stencil {
        let mut base = [0i64; 3];
        let mut fx = [0.0; 3];
        let mut w = [[0.0; 3]; 3];
        for a in 0..3 {
            let cell = x[a] * inv_dx;
            // ⌊cell − ½⌋ by truncation (a saturating cast; NaN gives 0) corrected for
            // negative values: `floor` is a libm call on baseline x86-64.
            let shifted = cell - 0.5;
            let truncated = shifted as i64;
            let b = truncated
                .saturating_sub(i64::from((truncated as f64) > shifted))
                .clamp(-NODE_LIMIT, NODE_LIMIT);
            let f = cell - b as f64;
            base[a] = b;
            fx[a] = f;
            w[a] = [
                0.5 * (1.5 - f) * (1.5 - f),
                0.75 - (f - 1.0) * (f - 1.0),
                0.5 * (f - 0.5) * (f - 0.5),
            ];
        }
        Stencil { base, fx, w }
    }

    /// The block holding the base node.
    fn block(&self) -> [i64; 3] {
        self.base.map(|b| b >> BLOCK_SHIFT)
    }
}

/// A bin: the particles whose stencil base lies in one block.
#[derive(Debug, Clone, Copy)]
struct Bin {
    /// The block's key.
    key: u64,
    /// The bin's particles are `order[start..end]`.
    start: usize,
    end: usize,
    /// Slots of the grid blocks at [`NEIGHBOURS`].
    neighbours: [u32; 8],
}

/// What the grid update imposes on nodes besides gravity.
#[derive(Debug, Clone, Copy)]
pub struct Boundary<'a> {
    /// Gravity (m/s²).
    pub gravity: [f64; 3],
    /// Rigid colliders (ground, spheres, boxes).
    pub colliders: &'a [Collider],
}

/// The sparse grid of one MPM model.
#[derive(Debug, Clone, Default)]
pub struct SparseGrid {
    /// Node spacing Δx (m).
    pub dx: f64,
    /// (bin key, particle) sorted: the scatter order.
    order: Vec<(u64, u32)>,
    /// The bins, in key order.
    bins: Vec<Bin>,
    /// Each particle's bin.
    bin_of: Vec<u32>,
    /// Keys of the allocated blocks, sorted.
    blocks: Vec<u64>,
    /// Block key → slot in `blocks`.
    slot: HashMap<u64, u32>,
    /// Bin scatter buffers, [`SPAN_NODES`] each: mass and momentum.
    scatter: Vec<[f64; 4]>,
    /// Block nodes, [`BLOCK_NODES`] each: mass and momentum after P2G, mass and
    /// velocity after the grid update.
    nodes: Vec<[f64; 4]>,
    /// PIC/FLIP only: each node's velocity before forces, v̄_i (empty under APIC).
    previous: Vec<[f64; 3]>,
    /// With anchors only: each node's held mass and momentum (empty otherwise).
    held: Vec<[f64; 4]>,
    /// Bin neighbourhoods of node velocities, [`SPAN_NODES`] each, for G2P.
    span_velocity: Vec<[f64; 3]>,
    /// PIC/FLIP only: the same of v̄_i (empty under APIC).
    span_previous: Vec<[f64; 3]>,
}

/// A node is held by the anchors when at least this share of its mass comes from
/// anchored particles; it then moves at their mass-weighted velocity.
pub const HELD_MASS_SHARE: f64 = 0.5;

/// Index of node (i, j, k) in a cube of `n` nodes a side (x fastest).
#[inline]
fn cube_index(i: usize, j: usize, k: usize, n: usize) -> usize {
    (k * n + j) * n + i
}

impl SparseGrid {
    /// An empty grid of spacing `dx`.
    pub fn new(dx: f64) -> SparseGrid {
        SparseGrid {
            dx,
            ..SparseGrid::default()
        }
    }

    /// Blocks allocated at the last rebuild.
    pub fn block_count(&self) -> usize {
        self.blocks.len()
    }

    /// Bytes the grid holds now (live blocks, bins and the sort order).
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        self.order.len() * size_of::<(u64, u32)>()
            + self.bins.len() * size_of::<Bin>()
            + self.bin_of.len() * size_of::<u32>()
            + self.blocks.len() * (size_of::<u64>() + size_of::<(u64, u32)>())
            + (self.scatter.len() + self.nodes.len()) * size_of::<[f64; 4]>()
            + (self.previous.len() + self.span_velocity.len() + self.span_previous.len())
                * size_of::<[f64; 3]>()
            + self.held.len() * size_of::<[f64; 4]>()
    }

    /// Keeps the nodes' mass and momentum after a P2G of the anchored particles alone
    /// (the others with zero mass, each anchored one at its anchor's velocity): the
    /// grid update then moves held nodes with the anchors ([`HELD_MASS_SHARE`]).
    pub fn keep_held(&mut self) {
        self.held.clear();
        self.held.extend_from_slice(&self.nodes);
    }

    /// Forgets the anchors' nodes (no anchor is active).
    pub fn release_held(&mut self) {
        self.held.clear();
    }

    /// Keeps the velocity (m v)_i / m_i of each node after a P2G, for FLIP's
    /// increment v_i − v̄_i in [`SparseGrid::g2p`].
    pub fn keep_velocity(&mut self) {
        self.previous.clear();
        self.previous.par_extend(self.nodes.par_iter().map(|n| {
            if n[0] > 0.0 {
                [n[1] / n[0], n[2] / n[0], n[3] / n[0]]
            } else {
                [0.0; 3]
            }
        }));
    }

    /// After a P2G that carried a scalar s_p as the velocity's first component (and no
    /// affine momentum), each particle's Σ_i w_ip m_p s_p / m_i at its nearest node, the
    /// centre of its stencil: the mass-weighted scalar of the cell it lies in (Lyu Eq.
    /// 6.10 reads the released energy there).
    pub fn centre_ratio(&self, position: &[[f64; 3]]) -> Vec<f64> {
        let inv_dx = 1.0 / self.dx;
        position
            .par_iter()
            .with_min_len(256)
            .map(|x| {
                let centre = Stencil::new(*x, inv_dx).base.map(|b| b + 1);
                let block = centre.map(|c| c >> BLOCK_SHIFT);
                let Some(&slot) = self.slot.get(&block_key(block)) else {
                    return 0.0;
                };
                let local = centre.map(|c| (c & (BLOCK as i64 - 1)) as usize);
                let node = self.nodes
                    [slot as usize * BLOCK_NODES + cube_index(local[0], local[1], local[2], BLOCK)];
                if node[0] > 0.0 {
                    node[1] / node[0]
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// Sorts the particles into bins and allocates the blocks their stencils touch.
    pub fn rebuild(&mut self, position: &[[f64; 3]]) {
        let inv_dx = 1.0 / self.dx;
        self.order.clear();
        self.order.par_extend(
            position
                .par_iter()
                .enumerate()
                .map(|(p, x)| (block_key(Stencil::new(*x, inv_dx).block()), p as u32)),
        );
        self.order.par_sort_unstable();
        self.bins.clear();
        let mut start = 0;
        while start < self.order.len() {
            let key = self.order[start].0;
            let mut end = start + 1;
            while end < self.order.len() && self.order[end].0 == key {
                end += 1;
            }
            self.bins.push(Bin {
                key,
                start,
                end,
                neighbours: [0; 8],
            });
            start = end;
        }
        self.blocks.clear();
        for bin in &self.bins {
            let b = key_block(bin.key);
            self.blocks.extend(
                NEIGHBOURS
                    .iter()
                    .map(|o| block_key([b[0] + o[0], b[1] + o[1], b[2] + o[2]])),
            );
        }
        self.blocks.par_sort_unstable();
        self.blocks.dedup();
        self.slot.clear();
        self.slot
            .extend(self.blocks.iter().enumerate().map(|(s, &k)| (k, s as u32)));
        for bin in &mut self.bins {
            let b = key_block(bin.key);
            for (n, o) in NEIGHBOURS.iter().enumerate() {
                bin.neighbours[n] = self.slot[&block_key([b[0] + o[0], b[1] + o[1], b[2] + o[2]])];
            }
        }
        self.bin_of.resize(position.len(), 0);
        for (i, bin) in self.bins.iter().enumerate() {
            for &(_, p) in &self.order[bin.start..bin.end] {
                self.bin_of[p as usize] = i as u32;
            }
        }
    }

    /// Particle to grid (Hu et al. 2018 Eq. 16–17; Lyu §3.2): each node receives
    /// Σ_p w_ip m_p and Σ_p w_ip (m_p v_p + A_p (x_i − x_p)), where the affine momentum
    /// A_p = m_p C_p − Δt V_p⁰ D⁻¹ P_p F_pᵀ carries APIC's C and the stress (MLS-MPM).
    /// Deterministic (see the module documentation).
    pub fn p2g(
        &mut self,
        position: &[[f64; 3]],
        mass: &[f64],
        velocity: &[[f64; 3]],
        affine: &[Mat3],
    ) {
        let inv_dx = 1.0 / self.dx;
        let dx = self.dx;
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
