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
//!
//! The three transfers and the colliders' boundary conditions are in the `transfer`
//! submodule; this file holds the grid's layout: keys, stencils, bins and blocks.

mod transfer;

use std::collections::HashMap;

use rayon::prelude::*;

use crate::contact::Collider;

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

/// Δx of a scene's one MPM grid: its finest body's resolution (also the depth inside
/// a collider at which set-up refuses a body's particles).
pub fn spacing(scene: &crate::scene::Scene) -> f64 {
    scene
        .bodies
        .iter()
        .map(|b| b.resolution)
        .fold(f64::INFINITY, f64::min)
}

/// How far from the origin (m, along each axis) a scene's MPM particles may start on a
/// grid of spacing `dx`: half the nodes its block keys hold, the other half left for
/// the motion.
pub fn reach(dx: f64) -> f64 {
    0.5 * NODE_LIMIT as f64 * dx
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

    /// Bytes a grid of spacing `dx` takes for particles at `position` once it has
    /// stepped (for `perifrac check`): each bin's scatter and velocity spans, each
    /// block's nodes, key and slot ([`SparseGrid::memory_bytes`] under APIC without
    /// anchors; the sort's 16 bytes a particle are the particles' own).
    pub fn estimate_bytes(position: &[[f64; 3]], dx: f64) -> f64 {
        use std::mem::size_of;
        let mut grid = SparseGrid::new(dx);
        grid.rebuild(position);
        let bin = size_of::<Bin>() + SPAN_NODES * (size_of::<[f64; 4]>() + size_of::<[f64; 3]>());
        // A block's nodes, its key, and its map entry (key, slot and the table's control byte).
        let block =
            BLOCK_NODES * size_of::<[f64; 4]>() + 2 * size_of::<u64>() + 2 * size_of::<u32>() + 1;
        (grid.bins.len() * bin + grid.blocks.len() * block) as f64
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
}
