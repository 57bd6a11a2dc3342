//! The per-bond constants of the kernels, for the rows this process works on: all of
//! them in one process, a rank's own particles in a distributed run ([`super::share`]),
//! so that a rank's bond memory shrinks with the rank count (issue 35). The topology
//! (neighbour words with their broken bits) stays whole on every rank; see
//! docs/ranks.md.

use std::ops::Range;

use perifrac_math::{mat_vec, norm, sub};
use rayon::prelude::*;

use super::BodyModel;
use crate::family::{self, Bonds, INDEX, Weights};

/// Per-bond coefficients with ω, the surface corrections and b folded in, so the
/// kernels divide by nothing but the deformed length. The `_rev` arrays hold, at bond
/// i→j, the value of bond j→i: the force gather needs no reverse lookup, and both
/// ends of a bond use the very same numbers (momentum is conserved exactly).
///
/// Every array holds the bonds of the rows [`Coefficients::rows`], from bond
/// [`Coefficients::first`] on: bond k is at `k − first`.
#[derive(Debug, Clone, Default)]
pub struct Coefficients {
    /// The particles whose bonds these are.
    pub rows: Range<usize>,
    /// The first of their bonds (`offsets[rows.start]`).
    pub first: usize,
    /// Reference bond length |ξ|.
    pub rest_length: Vec<f64>,
    /// ω_ij q_ij (Eq. 4, 6).
    pub dil: Vec<f32>,
    /// ω_ji q_ji.
    pub dil_rev: Vec<f32>,
    /// ω_ij b p_ij (Eq. 8, 12).
    pub dev: Vec<f32>,
    /// ω_ji b p_ji.
    pub dev_rev: Vec<f32>,
    /// ω per bond, only for anisotropic materials (Eq. 17): fracture and return
    /// mapping need it apart from the coefficients.
    pub omega: Option<Vec<f32>>,
    /// The index of the reverse bond j→i of each bond i→j (global), only when a
    /// material yields: the force pass reads e^p_ji.
    pub reverse: Option<Vec<u32>>,
}

/// ω of a bond of length `rest` from `xi` = x_j − x_i: δ/|ξ| (Eq. 5), or δ/|Gξ|
/// (Eq. 17) for an anisotropic material with G = `g`.
pub fn omega(delta: f64, g: Option<[[f64; 3]; 3]>, xi: [f64; 3], rest: f64) -> f64 {
    match g {
        Some(g) => delta / norm(mat_vec(g, xi)),
        None => delta / rest,
    }
}

/// What the coefficients are built from.
pub struct Inputs<'a> {
    /// Reference positions.
    pub position: &'a [[f64; 3]],
    /// Particle volumes.
    pub volume: &'a [f64],
    /// Each particle's body.
    pub body: &'a [u32],
    /// The bodies' constants.
    pub bodies: &'a [BodyModel],
    /// Chen §6's surface correction.
    pub surface_correction: bool,
    /// Whether the reverse index is kept (a material yields).
    pub keep_reverse: bool,
}

impl Coefficients {
    /// The coefficients of the bonds of `rows`. The `_rev` values need the weights of
    /// the neighbours' rows; those outside `rows` (the ghost rows of a rank) are
    /// computed for the moment and dropped, so that no whole-world per-bond array is
    /// ever held. The values are those of a build over all rows, to the bit.
    pub fn build(bonds: &Bonds, rows: Range<usize>, input: &Inputs) -> Coefficients {
        let delta: Vec<f64> = input
            .body
            .iter()
            .map(|&b| input.bodies[b as usize].constants.delta)
            .collect();
        let weights = |rows: &[usize]| {
            family::weights(
                bonds,
                input.position,
                input.volume,
                &delta,
                input.surface_correction,
                rows,
            )
        };
        let own = weights(&rows.clone().collect::<Vec<_>>());
        let mut ghosts: Vec<usize> = rows
            .clone()
            .flat_map(|i| bonds.neighbours[bonds.range(i)].iter())
            .map(|&j| (j & INDEX) as usize)
            .filter(|j| !rows.contains(j))
            .collect();
        ghosts.par_sort_unstable();
        ghosts.dedup();
        let ghost = weights(&ghosts);
        // Where each ghost row starts in `ghost`.
        let mut ghost_start = Vec::with_capacity(ghosts.len());
        let mut at = 0;
        for &g in &ghosts {
            ghost_start.push(at);
            at += bonds.range(g).len();
        }
        let first = bonds.offsets[rows.start];
        // (ω q, ω b p, ω) of bond k of row i, whose weights are `w[at]`.
        let coefficient = |i: usize, k: usize, w: &Weights, at: usize| {
            let body = &input.bodies[input.body[i] as usize];
            let j = (bonds.neighbours[k] & INDEX) as usize;
            let xi = sub(input.position[j], input.position[i]);
            let omega = omega(
                body.constants.delta,
                body.material.anisotropy,
                xi,
                w.rest_length[at],
            );
            (
                (omega * w.dilatation[at] as f64) as f32,
                (omega * body.constants.b * w.deviatoric[at] as f64) as f32,
                omega as f32,
            )
        };
        let row_bonds = |i: usize| bonds.range(i).map(move |k| (i, k));
        let own_bonds = || rows.clone().into_par_iter().flat_map_iter(row_bonds);
        // One array at a time, so that set-up holds little more than the run keeps.
        let part = |c: fn((f32, f32, f32)) -> f32| -> Vec<f32> {
            own_bonds()
                .map(|(i, k)| c(coefficient(i, k, &own, k - first)))
                .collect()
        };
        let dil = part(|c| c.0);
        let dev = part(|c| c.1);
        let anisotropic = input.bodies.iter().any(|b| b.material.anisotropy.is_some());
        let omega = anisotropic.then(|| part(|c| c.2));
        let Weights {
            rest_length,
            dilatation,
            deviatoric,
        } = own;
        drop((dilatation, deviatoric));
        // The reverse bond j→i of each bond.
        let reverse: Vec<u32> = own_bonds()
            .map(|(i, k)| {
                let j = (bonds.neighbours[k] & INDEX) as usize;
                let row = bonds.range(j);
                let pos =
                    bonds.neighbours[row.clone()].partition_point(|&x| (x & INDEX) < i as u32);
                (row.start + pos) as u32
            })
            .collect();
        // Its coefficients: this process's own, or a ghost row's.
        let reversed = |c: fn((f32, f32, f32)) -> f32, mine: &[f32]| -> Vec<f32> {
            reverse
                .par_iter()
                .map(|&r| {
                    let r = r as usize;
                    if (first..first + mine.len()).contains(&r) {
                        return mine[r - first];
                    }
                    let j = bonds.offsets.partition_point(|&o| o <= r) - 1;
                    let g = ghosts.partition_point(|&x| x < j);
                    c(coefficient(
                        j,
                        r,
                        &ghost,
                        ghost_start[g] + r - bonds.offsets[j],
                    ))
                })
                .collect()
        };
        let dil_rev = reversed(|c| c.0, &dil);
        let dev_rev = reversed(|c| c.1, &dev);
        Coefficients {
            rows,
            first,
            rest_length,
            dil,
            dil_rev,
            dev,
            dev_rev,
            omega,
            reverse: input.keep_reverse.then_some(reverse),
        }
    }

    /// These coefficients for the rows `keep` alone (within [`Coefficients::rows`]),
    /// the rest dropped: a model built whole and then split over ranks.
    pub fn keep(&mut self, keep: Range<usize>, offsets: &[usize]) {
        let bonds = offsets[keep.start] - self.first..offsets[keep.end] - self.first;
        let cut_f32 = |v: &mut Vec<f32>| *v = v[bonds.clone()].to_vec();
        cut_f32(&mut self.dil);
        cut_f32(&mut self.dil_rev);
        cut_f32(&mut self.dev);
        cut_f32(&mut self.dev_rev);
        if let Some(w) = &mut self.omega {
            cut_f32(w);
        }
        if let Some(r) = &mut self.reverse {
            *r = r[bonds.clone()].to_vec();
        }
        self.rest_length = self.rest_length[bonds].to_vec();
        self.first = offsets[keep.start];
        self.rows = keep;
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.rest_length.len() * 8
            + self.dil.len() * 16
            + self.omega.as_ref().map_or(0, |w| w.len() * 4)
            + self.reverse.as_ref().map_or(0, |r| r.len() * 4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Cuboid, stuff};
    use crate::material::Material;
    use crate::ranks::split_by_bonds;

    /// Each rank's coefficients, built from its own rows and its ghosts' weights, are
    /// the rows of a build over every particle, to the bit, and hold only its rows'
    /// bonds: an anisotropic, yielding body (ω and the reverse index kept) with
    /// surface corrections, split over three ranks and over one, and the whole model's
    /// split after it was built ([`Coefficients::keep`]). A ghost row's weights
    /// taken from the wrong row, or the reverse bond's coefficients from the bond
    /// itself, would differ at the boundary particles.
    #[test]
    fn a_ranks_coefficients_are_its_rows_of_the_whole_models() {
        let shape = Cuboid {
            center: [0.0; 3],
            half_extents: [0.1, 0.05, 0.03],
        };
        let mesh = stuff(&shape, 0.02).expect("box meshes");
        let x: Vec<[f64; 3]> = (0..mesh.tets.len()).map(|t| mesh.barycentre(t)).collect();
        let v: Vec<f64> = (0..mesh.tets.len()).map(|t| mesh.volume(t)).collect();
        let body = vec![0u32; x.len()];
        let delta = 1.45 * 0.02;
        let material = Material::from_spec(&crate::scene::MaterialSpec {
            density: 1000.0,
            bulk_modulus: None,
            shear_modulus: None,
            youngs_modulus: Some(1e6),
            poisson_ratio: Some(0.3),
            yield_psi0: Some(10.0),
            yield_stretch: None,
            plastic_limit: f64::INFINITY,
            critical_stretch: None,
            critical_compression: None,
            alpha: 0.0,
            anisotropy: Some([[1.0, 0.0, 0.0], [0.0, 2.0, 0.5], [0.0, 0.0, 1.0]]),
            air_damping: 0.0,
            laplacian_damping: 0.0,
            membrane: None,
            mpm: None,
            color: None,
        });
        let bodies = vec![BodyModel::new(material, delta)];
        let bonds = family::families_through(&x, &body, &vec![delta; x.len()], &[]).expect("bonds");
        let input = Inputs {
            position: &x,
            volume: &v,
            body: &body,
            bodies: &bodies,
            surface_correction: true,
            keep_reverse: true,
        };
        let whole = Coefficients::build(&bonds, 0..x.len(), &input);
        let bounds = split_by_bonds(&bonds.offsets, 3);
        let mut ghosts_read = 0;
        for rank in 0..3 {
            let rows = bounds[rank]..bounds[rank + 1];
            let part = Coefficients::build(&bonds, rows.clone(), &input);
            let b = bonds.offsets[rows.start]..bonds.offsets[rows.end];
            assert_eq!(part.first, b.start);
            // A model built whole and split after keeps the same.
            let mut kept = whole.clone();
            kept.keep(rows.clone(), &bonds.offsets);
            assert_eq!(
                format!("{kept:?}"),
                format!("{part:?}"),
                "rank {rank}: kept"
            );
            let same = |a: &[f32], w: &[f32]| {
                a.len() == b.len()
                    && a.iter()
                        .zip(&w[b.clone()])
                        .all(|(p, q)| p.to_bits() == q.to_bits())
            };
            assert!(
                same(&part.dil, &whole.dil) && same(&part.dev, &whole.dev),
                "rank {rank}"
            );
            assert!(same(&part.dil_rev, &whole.dil_rev), "rank {rank}: dil_rev");
            assert!(same(&part.dev_rev, &whole.dev_rev), "rank {rank}: dev_rev");
            let (omega, whole_omega) = (part.omega.expect("ω"), whole.omega.as_ref().expect("ω"));
            assert!(same(&omega, whole_omega), "rank {rank}: ω");
            assert_eq!(part.rest_length, whole.rest_length[b.clone()]);
            assert_eq!(
                part.reverse.expect("reverse"),
                whole.reverse.as_ref().expect("reverse")[b.clone()]
            );
            ghosts_read += (b.clone())
                .filter(|&k| {
                    let j = (bonds.neighbours[k] & INDEX) as usize;
                    !rows.contains(&j)
                })
                .count();
        }
        assert!(
            ghosts_read > 1000,
            "{ghosts_read} bonds reach another rank's rows"
        );
    }
}
