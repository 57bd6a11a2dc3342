//! Families and bonds: every particle's neighbours within its horizon δ, in CSR arrays.
//!
//! Neighbours are found with a k-d tree (`kiddo`) in parallel; each family is sorted
//! by neighbour index so that sums over it run in a fixed order and results do not
//! depend on the thread count. Bonds only join particles of the same body and, for a
//! body that is not convex, only through its material ([`Solid`]).
//!
//! The surface correction of Chen et al. §6 ("Choice of δ") lives here too. A family
//! cut by a free surface, or too small to be isotropic (δ ≈ λ on a tet lattice), has
//! sums over bonds that differ from the continuum integrals the constants of Chen
//! Eq. 10 assume. Per-bond weights fix the two moments the model uses: q_ij (second
//! moment, for θ of Eq. 6) and p_ij (fourth moment weighted by |ξ|, for the b-term of
//! Eq. 8), each the smallest polynomial change of uniform weights that makes the
//! discrete moment equal the continuum one, so θ and the energy are exact for every
//! homogeneous deformation wherever positive weights can do it.

mod crack;
mod rows;

pub use crack::Cracks;
pub use rows::{blocks_mut, rows_mut};

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use perifrac_math::{UnionFind, dist, lerp, sub};
use rayon::prelude::*;

use crate::error::{Result, SimError};
use crate::geometry::Sdf;

/// High bit of a neighbour index: the bond is broken.
pub const BROKEN: u32 = 1 << 31;
/// Mask for the neighbour index without the broken bit.
pub const INDEX: u32 = !BROKEN;

/// Bonds in compressed sparse rows: the family of particle i is
/// `neighbours[offsets[i]..offsets[i + 1]]`.
#[derive(Debug, Clone)]
pub struct Bonds {
    /// Row starts, one more than there are particles.
    pub offsets: Vec<usize>,
    /// Neighbour index per directed bond; the [`BROKEN`] bit marks a broken bond.
    pub neighbours: Vec<u32>,
    /// Reference bond length |ξ| = |x_j − x_i|.
    pub rest_length: Vec<f64>,
}

/// The surface corrections of each directed bond (see the module doc); 1 for a
/// complete continuum family.
#[derive(Debug, Clone)]
pub struct Corrections {
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

    /// The family of particle `i` as [`build_through`] finds it: the particles of its
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
/// same body, and the surface corrections q_ij and p_ij (all 1 when
/// `surface_correction` is off, which is Chen Eq. 6 and 8 as printed).
pub fn build(
    positions: &[[f64; 3]],
    volumes: &[f64],
    body: &[u32],
    delta: &[f64],
    surface_correction: bool,
) -> Result<(Bonds, Corrections)> {
    build_through(positions, volumes, body, delta, surface_correction, &[])
}

/// [`build`], keeping only the bonds that stay inside their body's solid
/// (`solids[body]`, see [`Solid`]); a body without one (`None`, or past the end of
/// `solids`: a convex shape, where every bond is inside) pays nothing.
pub fn build_through(
    positions: &[[f64; 3]],
    volumes: &[f64],
    body: &[u32],
    delta: &[f64],
    surface_correction: bool,
    solids: &[Option<Solid>],
) -> Result<(Bonds, Corrections)> {
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
    let per_particle: Vec<(Vec<f64>, Vec<f32>, Vec<f32>)> = families
        .par_iter()
        .enumerate()
        .map(|(i, family)| {
            let lengths: Vec<f64> = family
                .iter()
                .map(|&j| dist(positions[i], positions[j as usize]))
                .collect();
            if !surface_correction {
                return (lengths, vec![1.0; family.len()], vec![1.0; family.len()]);
            }
            let dirs: Vec<[f64; 3]> = family
                .iter()
                .map(|&j| unit(positions[i], positions[j as usize]))
                .collect();
            let vols: Vec<f64> = family.iter().map(|&j| volumes[j as usize]).collect();
            let q = dilatation_weights(&dirs, &vols, delta[i]);
            let p = deviatoric_weights(&dirs, &vols, &lengths, delta[i]);
            (lengths, q, p)
        })
        .collect();
    let neighbours: Vec<u32> = families.into_iter().flatten().collect();
    let mut rest_length = Vec::with_capacity(neighbours.len());
    let mut weight = Vec::with_capacity(neighbours.len());
    let mut dev_weight = Vec::with_capacity(neighbours.len());
    for (l, q, p) in per_particle {
        rest_length.extend(l);
        weight.extend(q);
        dev_weight.extend(p);
    }
    Ok((
        Bonds {
            offsets,
            neighbours,
            rest_length,
        },
        Corrections {
            dilatation: weight,
            deviatoric: dev_weight,
        },
    ))
}

/// (b − a) / |b − a|.
fn unit(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    let l = dist(a, b);
    sub(b, a).map(|x| x / l)
}

/// Exponents (a, b, c) of the monomials n_x^a n_y^b n_z^c of degree `degree`.
fn monomials(degree: u32) -> Vec<[u32; 3]> {
    let mut out = Vec::new();
    for a in (0..=degree).rev() {
        for b in (0..=degree - a).rev() {
            out.push([a, b, degree - a - b]);
        }
    }
    out
}

/// ∫ n_x^a n_y^b n_z^c dΩ over the unit sphere (zero unless all exponents are even).
fn sphere_moment(e: [u32; 3]) -> f64 {
    if e.iter().any(|x| x % 2 == 1) {
        return 0.0;
    }
    // 2 Γ((a+1)/2) Γ((b+1)/2) Γ((c+1)/2) / Γ((a+b+c+3)/2), via double factorials.
    let df = |k: i64| -> f64 {
        (1..=k)
            .rev()
            .step_by(2)
            .map(|x| x as f64)
            .product::<f64>()
            .max(1.0)
    };
    let [a, b, c] = e.map(|x| x as i64);
    4.0 * std::f64::consts::PI * df(a - 1) * df(b - 1) * df(c - 1) / df(a + b + c + 1)
}

/// The K monomials n_x^a n_y^b n_z^c of degree `degree` at `n` (K = 6 for degree 2,
/// 15 for degree 4), in the order of [`monomials`].
fn monomial_values<const K: usize>(n: [f64; 3], degree: u32) -> [f64; K] {
    let powers = |x: f64| {
        let mut p = [1.0f64; 5];
        for e in 1..5 {
            p[e] = p[e - 1] * x;
        }
        p
    };
    let (px, py, pz) = (powers(n[0]), powers(n[1]), powers(n[2]));
    let mut out = [0.0; K];
    let mut k = 0;
    for a in (0..=degree as usize).rev() {
        for b in (0..=degree as usize - a).rev() {
            out[k] = px[a] * py[b] * pz[degree as usize - a - b];
            k += 1;
        }
    }
    out
}

/// Per-bond weights w_j (a polynomial of degree `degree` in ξ̂, K coefficients, which
/// includes the constant for even degrees) that make Σ_j w_j m_j ξ̂^⊗degree equal
/// `target` times the unit-sphere moments, checked to stay within [0.1, 10]; `None`
/// otherwise.
fn moment_weights<const K: usize>(
    dirs: &[[f64; 3]],
    measure: &[f64],
    degree: u32,
    target: f64,
) -> Option<Vec<f32>> {
    let phis: Vec<[f64; K]> = dirs
        .iter()
        .map(|n| monomial_values::<K>(*n, degree))
        .collect();
    let mut mat = [[0.0f64; K]; K];
    for (phi, &m) in phis.iter().zip(measure) {
        for r in 0..K {
            let mr = m * phi[r];
            for c in r..K {
                mat[r][c] += mr * phi[c];
            }
        }
    }
    for r in 1..K {
        let (upper, lower) = mat.split_at_mut(r);
        for (c, row) in upper.iter().enumerate() {
            lower[0][c] = row[r];
        }
    }
    let rhs: Vec<f64> = monomials(degree)
        .into_iter()
        .map(|e| target * sphere_moment(e))
        .collect();
    let coef = solve(mat.iter().map(|row| row.to_vec()).collect(), rhs)?;
    let w: Vec<f64> = phis
        .iter()
        .map(|phi| phi.iter().zip(&coef).map(|(p, c)| p * c).sum())
        .collect();
    w.iter()
        .all(|&x| x > 0.1 && x < 10.0)
        .then(|| w.into_iter().map(|x| x as f32).collect())
}

/// Dilatation weights q_j: Σ_j q_j V_j ξ̂⊗ξ̂ = (V_H∞/3) I, V_H∞ = 4πδ³/3, so θ is exact
/// for every homogeneous deformation (a quadratic form in ξ̂, the least change from
/// uniform weights). Where that needs weights that are not positive (near edges and
/// corners no positive weights are exact for shear: Σ q V n_y n_z > 0 there), the
/// weights match the diagonal (axis stretches) only; failing that, the family-volume
/// ratio V_H∞/V_H,i (exact for isotropic expansion).
fn dilatation_weights(dirs: &[[f64; 3]], vols: &[f64], delta: f64) -> Vec<f32> {
    let full = 4.0 / 3.0 * std::f64::consts::PI * delta.powi(3);
    // Target moments (V_H∞/4π) ∫ n⊗n dΩ.
    if let Some(q) = moment_weights::<6>(dirs, vols, 2, full / (4.0 * std::f64::consts::PI)) {
        return q;
    }
    let mut k = [[0.0f64; 3]; 3];
    for (n, &v) in dirs.iter().zip(vols) {
        for r in 0..3 {
            for c in 0..3 {
                k[r][c] += v * n[r] * n[r] * n[c] * n[c];
            }
        }
    }
    let diag = solve(k.iter().map(|r| r.to_vec()).collect(), vec![full / 3.0; 3]);
    if let Some(d) = diag {
        let q: Vec<f64> = dirs
            .iter()
            .map(|n| d[0] * n[0] * n[0] + d[1] * n[1] * n[1] + d[2] * n[2] * n[2])
            .collect();
        if q.iter().all(|&x| x > 0.1 && x < 10.0) {
            return q.into_iter().map(|x| x as f32).collect();
        }
    }
    let family_volume: f64 = vols.iter().sum();
    let scalar = if family_volume > 0.0 {
        full / family_volume
    } else {
        1.0
    };
    vec![scalar as f32; dirs.len()]
}

/// Deviatoric weights p_j: Σ_j p_j |ξ_j| V_j ξ̂^⊗4 = (δ⁴/4) ∫ n^⊗4 dΩ, the fourth
/// moment of a complete continuum family, so that the b-term of Chen Eq. 8 has the
/// continuum's isotropic stiffness (μ) for every homogeneous deformation; families of
/// few bonds (δ ≈ λ) are far from isotropic otherwise. Falls back to the trace
/// correction πδ⁴ / Σ_j |ξ_j| V_j where positive polynomial weights do not exist.
fn deviatoric_weights(dirs: &[[f64; 3]], vols: &[f64], lengths: &[f64], delta: f64) -> Vec<f32> {
    let measure: Vec<f64> = vols.iter().zip(lengths).map(|(v, l)| v * l).collect();
    if let Some(p) = moment_weights::<15>(dirs, &measure, 4, delta.powi(4) / 4.0) {
        return p;
    }
    let m: f64 = measure.iter().sum();
    let scalar = if m > 0.0 {
        std::f64::consts::PI * delta.powi(4) / m
    } else {
        1.0
    };
    vec![scalar as f32; dirs.len()]
}

/// Gaussian elimination with partial pivoting; `None` if (nearly) singular.
fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    let scale = a.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    if scale == 0.0 {
        return None;
    }
    for col in 0..n {
        let pivot = (col..n).max_by(|&r, &s| a[r][col].abs().total_cmp(&a[s][col].abs()))?;
        if a[pivot][col].abs() < 1e-10 * scale {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        let (top, rest) = a.split_at_mut(col + 1);
        let pivot_row = &top[col];
        for (r, row) in rest.iter_mut().enumerate() {
            let f = row[col] / pivot_row[col];
            for (x, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                *x -= f * p;
            }
            b[col + 1 + r] -= f * b[col];
        }
    }
    let mut x = vec![0.0; n];
    for r in (0..n).rev() {
        let s: f64 = (r + 1..n).map(|c| a[r][c] * x[c]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    Some(x)
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

    #[test]
    fn sphere_moments() {
        let pi = std::f64::consts::PI;
        assert!((sphere_moment([0, 0, 0]) - 4.0 * pi).abs() < 1e-12);
        assert!((sphere_moment([2, 0, 0]) - 4.0 * pi / 3.0).abs() < 1e-12);
        assert!((sphere_moment([4, 0, 0]) - 4.0 * pi / 5.0).abs() < 1e-12);
        assert!((sphere_moment([2, 2, 0]) - 4.0 * pi / 15.0).abs() < 1e-12);
        assert_eq!(sphere_moment([3, 1, 0]), 0.0);
        assert_eq!(monomials(4).len(), 15);
    }
}
