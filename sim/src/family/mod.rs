//! Families and bonds: every particle's neighbours within its horizon δ, in CSR arrays.
//!
//! Neighbours are found with a k-d tree (`kiddo`) in parallel; each family is sorted
//! by neighbour index so that sums over it run in a fixed order and results do not
//! depend on the thread count. Bonds only join particles of the same body and, for a
//! body that is not convex, only through its material ([`Solid`]).
//!
//! The surface correction of Chen et al. §6 ("Choice of δ") lives here too, in
//! `correction`: per-bond weights q_ij and p_ij that make a family cut by a free
//! surface, or too small to be isotropic, sum as the continuum integrals of Chen
//! Eq. 10 do.

mod correction;
mod crack;
mod rows;

pub use crack::Cracks;
pub use rows::{blocks_mut, rows_mut};

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use perifrac_math::{UnionFind, dist, lerp, sub};
use rayon::prelude::*;

use crate::error::{Result, SimError};
use crate::geometry::Sdf;
use correction::{deviatoric_weights, dilatation_weights};

/// High bit of a neighbour index: the bond is broken.
pub const BROKEN: u32 = 1 << 31;
/// Mask for the neighbour index without the broken bit.
pub const INDEX: u32 = !BROKEN;

/// Bonds in compressed sparse rows: the family of particle i is
/// `neighbours[offsets[i]..offsets[i + 1]]`. What a model keeps per bond besides
/// (lengths, weights, state) it keeps itself, for the rows it works on ([`Weights`]).
#[derive(Debug, Clone)]
pub struct Bonds {
    /// Row starts, one more than there are particles.
    pub offsets: Vec<usize>,
    /// Neighbour index per directed bond; the [`BROKEN`] bit marks a broken bond.
    pub neighbours: Vec<u32>,
}

/// The reference lengths and surface corrections (see the `correction` module; 1 for
/// a complete continuum family) of the bonds of some rows, in row order: all of them
/// ([`build`]), or the rows a rank of a distributed run works on ([`weights`]).
#[derive(Debug, Clone, Default)]
pub struct Weights {
    /// Reference bond length |ξ| = |x_j − x_i|.
    pub rest_length: Vec<f64>,
    /// Dilatation weight q_ij.
    pub dilatation: Vec<f32>,
    /// Deviatoric weight p_ij multiplying b.
    pub deviatoric: Vec<f32>,
}

impl Bonds {
    /// Connected components of intact bonds over the `offsets.len() − 1` particles,
    /// numbered by their smallest particle index in increasing order (deterministic).
    pub fn fragments(&self) -> Vec<u32> {
        let n = self.offsets.len().saturating_sub(1);
        let mut sets = UnionFind::new(n);
        for i in 0..n {
            for k in self.range(i) {
                let nb = self.neighbours[k];
                if nb & BROKEN == 0 {
                    sets.union(i, (nb & INDEX) as usize);
                }
            }
        }
        sets.labels()
    }

    /// Number of directed bonds.
    pub fn len(&self) -> usize {
        self.neighbours.len()
    }

    /// Whether there are no bonds at all.
    pub fn is_empty(&self) -> bool {
        self.neighbours.is_empty()
    }

    /// The bond range of particle i.
    #[inline]
    pub fn range(&self, i: usize) -> std::ops::Range<usize> {
        self.offsets[i]..self.offsets[i + 1]
    }

    /// Directed bonds whose [`BROKEN`] bit is set.
    pub fn broken_count(&self) -> u64 {
        self.neighbours
            .iter()
            .filter(|&&nb| nb & BROKEN != 0)
            .count() as u64
    }

    /// Checks the neighbour words a checkpoint stores against these bonds (the ones
    /// the scene builds, cracks cut): each bond points at the same particle, and a
    /// bond the scene starts broken is still broken (bonds never heal). Returns what
    /// is wrong with the first bond that fails.
    pub fn check_restored(&self, stored: &[u32]) -> std::result::Result<(), String> {
        if stored.len() != self.neighbours.len() {
            return Err(format!(
                "{} bonds in the checkpoint, the scene has {}",
                stored.len(),
                self.neighbours.len()
            ));
        }
        let bad = self
            .neighbours
            .iter()
            .zip(stored)
            .position(|(&scene, &saved)| {
                scene & INDEX != saved & INDEX || (scene & BROKEN != 0 && saved & BROKEN == 0)
            });
        match bad {
            None => Ok(()),
            Some(k) if self.neighbours[k] & INDEX != stored[k] & INDEX => Err(format!(
                "bond {k} points at particle {} where the scene has {}",
                stored[k] & INDEX,
                self.neighbours[k] & INDEX
            )),
            Some(k) => Err(format!(
                "bond {k} is intact but the scene cuts it before the first step (bonds \
                 never heal)"
            )),
        }
    }

    /// For each directed bond i→j, the index of the bond j→i.
    pub fn reverse_index(&self) -> Vec<u32> {
        let n = self.offsets.len() - 1;
        (0..n)
            .into_par_iter()
            .flat_map_iter(|i| {
                self.range(i).map(move |k| {
                    let j = (self.neighbours[k] & INDEX) as usize;
                    let r = self.range(j);
                    let row = &self.neighbours[r.clone()];
                    let pos = row
                        .binary_search_by_key(&(i as u32), |&x| x & INDEX)
                        .expect("families are symmetric: j is in i's family iff i is in j's");
                    (r.start + pos) as u32
                })
            })
            .collect()
    }
}

/// Bytes a bond costs in the elastic model (neighbour, rest length, and the four
/// coefficients of [`crate::pd::Coefficients`]).
pub const BYTES_PER_BOND: usize = 4 + 8 + 4 * 4;

/// Counts bonds within `delta[i]` (δ in metres) without storing them (for `perifrac
/// check`).
pub fn count_bonds(positions: &[[f64; 3]], body: &[u32], delta: &[f64]) -> Result<usize> {
    let tree = build_tree(positions)?;
    Ok((0..positions.len())
        .into_par_iter()
        .map(|i| neighbours_of(&tree, positions, body, delta[i], None, &|_| 0.0, i).len())
        .sum())
}

/// A neighbour search over fixed reference positions, for a model that builds the
/// family of one particle at a time (SPB-MPM's peridynamic particles join as the
/// grid erodes their cells).
pub struct Search {
    tree: ImmutableKdTree<f64, 3>,
}

impl std::fmt::Debug for Search {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Search").finish_non_exhaustive()
    }
}

impl Search {
    /// The search over `positions`.
    ///
    /// # Errors
    /// [`SimError::Refused`] if the tree cannot be built (too many particles).
    pub fn new(positions: &[[f64; 3]]) -> Result<Search> {
        Ok(Search {
            tree: build_tree(positions)?,
        })
    }

    /// The family of particle `i` as [`families_through`] finds it: the particles of its
    /// body within `delta` of it (not itself), through `solid` when given, sorted by
    /// index. `positions` and `body` are those the search was built over; `depths`
    /// each particle's signed distance to its body's solid (read only with a `solid`).
    pub fn family(
        &self,
        positions: &[[f64; 3]],
        body: &[u32],
        i: usize,
        delta: f64,
        solid: Option<&Solid>,
        depths: &[f64],
    ) -> Vec<u32> {
        neighbours_of(&self.tree, positions, body, delta, solid, &|k| depths[k], i)
    }
}

fn build_tree(positions: &[[f64; 3]]) -> Result<ImmutableKdTree<f64, 3>> {
    ImmutableKdTree::new_from_slice(positions)
        .map_err(|e| SimError::Refused(format!("could not build the neighbour search tree: {e:?}")))
}

/// The material a bond must stay inside (issue 13): a body's shape as a signed
/// distance, sampled along each bond. Families found by distance alone join particles
/// across slots, notches and gaps narrower than δ.
pub struct Solid<'a> {
    /// The body's signed distance (negative inside).
    pub sdf: &'a dyn Sdf,
    /// Largest distance between samples along a bond (0.2λ).
    pub step: f64,
    /// Largest signed distance a sample may have (0.05λ: the tet mesh's boundary and
    /// the particles near it stray that far from the exact surface).
    pub tolerance: f64,
}

impl Solid<'_> {
    /// The solid of a body of resolution λ.
    pub fn of(sdf: &dyn Sdf, lambda: f64) -> Solid<'_> {
        Solid {
            sdf,
            step: 0.2 * lambda,
            tolerance: 0.05 * lambda,
        }
    }

    /// Whether the segment a–b stays inside: no sample strictly between the ends lies
    /// more than `tolerance` outside. A slot of width w is found when w/2 − step/2 >
    /// tolerance (any w above 0.3λ). `da` and `db` are the signed distances at a and b.
    ///
    /// The signed distance is 1-Lipschitz (exact for a mesh and the primitives, and
    /// kept by the min/max of unions and differences), so a sample within
    /// `tolerance − d` of a point of signed distance d ≤ `tolerance` cannot lie farther
    /// out than `tolerance`: such samples are not evaluated (the ends prove the
    /// samples near them, each evaluated sample those after it), and a bond between
    /// two particles deep inside evaluates none. The answer is the sampling's.
    /// Sampled from the end given first; callers pass the lower particle index first
    /// so that i→j and j→i agree to the bit.
    pub fn contains_segment(&self, a: [f64; 3], b: [f64; 3], da: f64, db: f64) -> bool {
        let length = dist(a, b);
        let samples = (length / self.step).ceil().max(1.0) as usize;
        // The segment is proven inside up to this distance from a.
        let mut proven = self.tolerance - da;
        for k in 1..samples {
            let t = k as f64 / samples as f64;
            let at = t * length;
            if at <= proven || db + (length - at) <= self.tolerance {
                continue;
            }
            let d = self.sdf.distance(lerp(a, b, t));
            if d > self.tolerance {
                return false;
            }
            proven = at + (self.tolerance - d);
        }
        true
    }
}

/// The family of particle `i`: particles of its body within `d` and, with a `solid`,
/// joined to it inside that solid (`depth(k)` is particle k's signed distance to it).
fn neighbours_of(
    tree: &ImmutableKdTree<f64, 3>,
    positions: &[[f64; 3]],
    body: &[u32],
    d: f64,
    solid: Option<&Solid>,
    depth: &dyn Fn(usize) -> f64,
    i: usize,
) -> Vec<u32> {
    let found = tree
        .query(&positions[i])
        .within::<SquaredEuclidean<f64>>(d * d)
        .unsorted()
        .execute();
    let mut family: Vec<u32> = found
        .into_iter()
        .map(|item| item.item)
        .filter(|&j| j as usize != i && body[j as usize] == body[i])
        .filter(|&j| {
            let p = positions[j as usize];
            let q = positions[i];
            let r2 = (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2);
            r2 <= d * d
        })
        .filter(|&j| {
            solid.is_none_or(|s| {
                let (lo, hi) = (i.min(j as usize), i.max(j as usize));
                s.contains_segment(positions[lo], positions[hi], depth(lo), depth(hi))
            })
        })
        .collect();
    family.sort_unstable();
    family
}

/// Builds every family within `delta[i]` (δ in metres of i's body), among particles of the
/// same body, and the weights of every row (surface corrections q_ij and p_ij all 1
/// when `surface_correction` is off, which is Chen Eq. 6 and 8 as printed).
pub fn build(
    positions: &[[f64; 3]],
    volumes: &[f64],
    body: &[u32],
    delta: &[f64],
    surface_correction: bool,
) -> Result<(Bonds, Weights)> {
    let bonds = families_through(positions, body, delta, &[])?;
    let all: Vec<usize> = (0..positions.len()).collect();
    let weights = weights(&bonds, positions, volumes, delta, surface_correction, &all);
    Ok((bonds, weights))
}

/// Every family within `delta[i]` of particle i among the particles of its body,
/// keeping only the bonds that stay inside their body's solid (`solids[body]`, see
/// [`Solid`]); a body without one (`None`, or past the end of `solids`: a convex
/// shape, where every bond is inside) pays nothing.
pub fn families_through(
    positions: &[[f64; 3]],
    body: &[u32],
    delta: &[f64],
    solids: &[Option<Solid>],
) -> Result<Bonds> {
    let n = positions.len();
    if n >= INDEX as usize {
        return Err(SimError::Refused(format!(
            "{n} particles: at most {INDEX} are supported"
        )));
    }
    let tree = build_tree(positions)?;
    // Each particle's signed distance to its body's solid (0, unread, without one).
    let depth: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|i| {
            solids
                .get(body[i] as usize)
                .and_then(Option::as_ref)
                .map_or(0.0, |s| s.sdf.distance(positions[i]))
        })
        .collect();
    let families: Vec<Vec<u32>> = (0..n)
        .into_par_iter()
        .map(|i| {
            let solid = solids.get(body[i] as usize).and_then(Option::as_ref);
            neighbours_of(&tree, positions, body, delta[i], solid, &|k| depth[k], i)
        })
        .collect();
    let mut offsets = Vec::with_capacity(n + 1);
    offsets.push(0usize);
    for f in &families {
        offsets.push(offsets.last().copied().unwrap_or(0) + f.len());
    }
    let mut neighbours = Vec::with_capacity(offsets[n]);
    for f in families {
        neighbours.extend(f);
    }
    Ok(Bonds {
        offsets,
        neighbours,
    })
}

/// The weights of the bonds of `rows` (ascending), in row order: each bond's reference
/// length and, with `surface_correction`, the corrections of its particle's family
/// (Chen §6; a row's weights depend on its own family alone, so any set of rows gets
/// the values a build of all of them does).
pub fn weights(
    bonds: &Bonds,
    positions: &[[f64; 3]],
    volumes: &[f64],
    delta: &[f64],
    surface_correction: bool,
    rows: &[usize],
) -> Weights {
    // Each row's bonds start at `starts[r]` of the output, written in place.
    let mut starts = Vec::with_capacity(rows.len() + 1);
    starts.push(0usize);
    for &i in rows {
        starts.push(starts[starts.len() - 1] + bonds.range(i).len());
    }
    let total = starts[rows.len()];
    let mut out = Weights {
        rest_length: vec![0.0; total],
        dilatation: vec![1.0; total],
        deviatoric: vec![1.0; total],
    };
    rows_mut(&mut out.rest_length, &starts)
        .into_par_iter()
        .zip(rows_mut(&mut out.dilatation, &starts))
        .zip(rows_mut(&mut out.deviatoric, &starts))
        .zip(rows)
        .for_each(|(((lengths, q), p), &i)| {
            let family = &bonds.neighbours[bonds.range(i)];
            let at = |j: u32| positions[(j & INDEX) as usize];
            for (l, &j) in lengths.iter_mut().zip(family) {
                *l = dist(positions[i], at(j));
            }
            if !surface_correction {
                return;
            }
            let dirs: Vec<[f64; 3]> = family.iter().map(|&j| unit(positions[i], at(j))).collect();
            let vols: Vec<f64> = family
                .iter()
                .map(|&j| volumes[(j & INDEX) as usize])
                .collect();
            q.copy_from_slice(&dilatation_weights(&dirs, &vols, delta[i]));
            p.copy_from_slice(&deviatoric_weights(&dirs, &vols, lengths, delta[i]));
        });
    out
}

/// (b − a) / |b − a|.
fn unit(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    let l = dist(a, b);
    sub(b, a).map(|x| x / l)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Cuboid, Difference};
    use perifrac_math::SplitMix64;

    /// Skipping the samples the ends and earlier samples prove inside gives the answer
    /// of evaluating every sample, on 20,000 random segments in and around a slotted
    /// bar (between a quarter and three quarters of them crossing the slot or leaving
    /// the bar).
    #[test]
    fn a_bond_skips_only_samples_proven_inside() {
        let bar = Difference(
            Box::new(Cuboid {
                center: [0.0; 3],
                half_extents: [0.15, 0.03, 0.03],
            }),
            Box::new(Cuboid {
                center: [0.0; 3],
                half_extents: [0.005, 0.1, 0.1],
            }),
        );
        let solid = Solid::of(&bar, 0.02);
        let every_sample = |a: [f64; 3], b: [f64; 3]| {
            let samples = (dist(a, b) / solid.step).ceil().max(1.0) as usize;
            (1..samples)
                .all(|k| bar.distance(lerp(a, b, k as f64 / samples as f64)) <= solid.tolerance)
        };
        let mut rng = SplitMix64::new(3);
        let mut point = |half: [f64; 3]| half.map(|h| (2.0 * rng.next_f64() - 1.0) * h);
        let mut kept = 0;
        for _ in 0..20_000 {
            let a = point([0.16, 0.035, 0.035]);
            let offset = point([0.03, 0.03, 0.03]);
            let b = [0, 1, 2].map(|k| a[k] + offset[k]);
            let (da, db) = (bar.distance(a), bar.distance(b));
            let skipping = solid.contains_segment(a, b, da, db);
            assert_eq!(skipping, every_sample(a, b), "{a:?}–{b:?}");
            kept += usize::from(skipping);
        }
        assert!(kept > 5_000 && kept < 15_000, "{kept} of 20,000 kept");
    }
}
