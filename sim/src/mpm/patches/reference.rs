//! The reference configuration of Ω^PD: the neighbour search that builds a joining
//! particle's family, what each member's bonds keep from it for good (their lengths
//! |X|, the integral-based MPM's surface corrections G_p(n), and the other end's index
//! of each bond), computed once when the member joins instead of every step, and each
//! member's shape tensor K, kept until one of its bonds breaks.

use perifrac_math::{det3, inverse3, norm, sub};
use rayon::prelude::*;

use super::integral;
use super::{MIN_SHAPE, OUTSIDE, PatchBody, Patches};
use crate::error::Result;
use crate::family::{BROKEN, INDEX, Search, Solid};
use crate::mpm::MpmParticles;
use crate::mpm::constitutive::{self, Mat3};

/// [`Bond::mirror`] of a bond whose other end is not a member (or does not have the
/// bond back).
pub(super) const NO_MIRROR: u32 = u32::MAX;

/// A member's bond as the reference configuration fixes it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Bond {
    /// |X|, the reference length (m).
    pub(super) length: f64,
    /// The integral-based MPM's surface correction G_p(n) of the bond's direction
    /// ([`integral::surface_corrections`]); 1 for SPB-MPM's members.
    pub(super) correction: f64,
    /// The index of the same bond in the other end's family, or [`NO_MIRROR`].
    pub(super) mirror: u32,
}

/// A member and its bonds: particle `i`, its family and their [`Bond`]s.
#[derive(Clone, Copy)]
pub(super) struct Member<'a> {
    pub(super) i: usize,
    pub(super) family: &'a [u32],
    pub(super) table: &'a [Bond],
}

/// A member's shape tensor K = Σ ω X⊗X V over its intact bonds (Eq. 6.7), as its
/// state reads it: kept from step to step until one of its bonds breaks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Shape {
    /// Not worked out since the member joined or last lost a bond.
    Stale,
    /// K⁻¹: the intact bonds span space.
    Spanning(Mat3),
    /// The intact bonds no longer span space (K's smallest eigenvalue below
    /// [`MIN_SHAPE`] of the whole family's mean, or det K ≤ 0): an SPB-MPM member is
    /// free, an integral-based one keeps its springs only.
    Flat,
}

/// The [`Shape`] of a member's intact bonds.
pub(super) fn shape(member: Member<'_>, p: &MpmParticles, delta: f64) -> Shape {
    let Member { i, family, table } = member;
    let mut whole_moment = 0.0;
    let mut shape = [[0.0; 3]; 3];
    for (&nb, bond) in family.iter().zip(table) {
        let q = (nb & INDEX) as usize;
        let length = bond.length;
        let w = delta / length * p.volume[q];
        whole_moment += w * length * length;
        if nb & BROKEN != 0 {
            continue;
        }
        let xi = sub(p.reference[q], p.reference[i]);
        for a in 0..3 {
            for b in 0..3 {
                shape[a][b] += w * xi[a] * xi[b];
            }
        }
    }
    let eigenvalues = constitutive::symmetric_eigenvalues(&shape);
    let smallest = eigenvalues.iter().copied().fold(f64::INFINITY, f64::min);
    let det = det3(&shape);
    if smallest.is_nan() || smallest < MIN_SHAPE * whole_moment / 3.0 || det <= 0.0 {
        Shape::Flat
    } else {
        Shape::Spanning(inverse3(&shape, det))
    }
}

impl Patches {
    /// Fixes the bonds of the members from slot `from` on (those that just joined, or
    /// all of them after a restore): each bonded body's Σ ω V over its fullest family
    /// (all its particles join at once, so it is whole before any correction reads it),
    /// then each bond's [`Bond`], and the mirrors both ways between the new members
    /// and every member they are bonded to.
    pub(super) fn settle(&mut self, from: usize, p: &MpmParticles) {
        let delta = self.horizon;
        for (&i, family) in self.members[from..].iter().zip(&self.families[from..]) {
            let i = i as usize;
            let body = p.body[i] as usize;
            if self.bodies[body].bonds.is_none() {
                continue;
            }
            let weight: f64 = family
                .iter()
                .map(|&q| {
                    delta / norm(sub(p.reference[q as usize], p.reference[i]))
                        * p.volume[q as usize]
                })
                .sum();
            let full = &mut self.full_weights[body];
            *full = full.max(weight);
        }
        let this = &*self;
        let rows: Vec<Vec<Bond>> = (from..self.members.len())
            .into_par_iter()
            .map(|s| {
                let i = this.members[s] as usize;
                let family = &this.families[s];
                let body = p.body[i] as usize;
                let corrections = match this.bodies[body].bonds {
                    Some(_) => {
                        let full = this.full_weights[body];
                        integral::surface_corrections(i, family, p, full, delta)
                    }
                    None => vec![1.0; family.len()],
                };
                family
                    .iter()
                    .zip(corrections)
                    .map(|(&nb, correction)| {
                        let q = (nb & INDEX) as usize;
                        let mirror = match this.slot[q] {
                            OUTSIDE => NO_MIRROR,
                            t => this.families[t as usize]
                                .binary_search_by_key(&(i as u32), |&back| back & INDEX)
                                .map_or(NO_MIRROR, |k| k as u32),
                        };
                        Bond {
                            length: norm(sub(p.reference[q], p.reference[i])),
                            correction,
                            mirror,
                        }
                    })
                    .collect()
            })
            .collect();
        self.table.truncate(from);
        self.table.extend(rows);
        self.shapes.truncate(from);
        self.shapes.resize(self.members.len(), Shape::Stale);
        // The older members' bonds to the new ones point back now.
        for s in from..self.members.len() {
            for (k, &nb) in self.families[s].iter().enumerate() {
                let mirror = self.table[s][k].mirror;
                let t = self.slot[(nb & INDEX) as usize];
                if mirror != NO_MIRROR && (t as usize) < from {
                    self.table[t as usize][mirror as usize].mirror = k as u32;
                }
            }
        }
    }
}

/// The reference configuration's neighbour search, and each particle's signed
/// distance at its reference position to its body's shape (0 for a body without one),
/// which every family's bonds through the shape read: computed once, where a mesh's
/// distance costs a tree search (twice a bond, every frame, in the fragments before).
pub(super) struct Reference {
    search: Search,
    depths: Vec<f64>,
}

impl Reference {
    /// The search over `p`'s reference positions.
    ///
    /// # Errors
    /// [`crate::error::SimError::Refused`] if the tree cannot be built.
    pub(super) fn new(bodies: &[PatchBody], p: &MpmParticles) -> Result<Reference> {
        let depths = (0..p.len())
            .into_par_iter()
            .with_min_len(256)
            .map(|i| {
                let shape = bodies[p.body[i] as usize].shape.as_deref();
                shape.map_or(0.0, |sdf| sdf.distance(p.reference[i]))
            })
            .collect();
        Ok(Reference {
            search: Search::new(&p.reference)?,
            depths,
        })
    }

    /// The reference neighbours of particle `i` within `horizon` in its body, through
    /// the body's shape when it has one.
    pub(super) fn family(
        &self,
        bodies: &[PatchBody],
        horizon: f64,
        i: usize,
        p: &MpmParticles,
    ) -> Vec<u32> {
        let body = &bodies[p.body[i] as usize];
        let solid = body
            .shape
            .as_deref()
            .map(|sdf| Solid::of(sdf, body.resolution));
        self.search.family(
            &p.reference,
            &p.body,
            i,
            horizon,
            solid.as_ref(),
            &self.depths,
        )
    }
}

#[cfg(test)]
mod tests;
