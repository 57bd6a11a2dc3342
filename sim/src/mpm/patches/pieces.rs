//! SPB-MPM's pieces and checkpoint: the fragments a cache frame numbers, and what a
//! resume reads back.

use perifrac_math::UnionFind;
use rayon::prelude::*;

use super::{OUTSIDE, Patches, Reference};
use crate::cache::checkpoint::{Decoder, Encoder};
use crate::error::Result;
use crate::family::{BROKEN, INDEX};
use crate::mpm::MpmParticles;
use crate::mpm::constitutive::Mat3;

impl Patches {
    /// Connected pieces, numbered by their smallest particle index in increasing
    /// order: a member joins its intact bonds, a particle outside Ω^PD its reference
    /// neighbours within δ (its bonds, were it peridynamic, which no crack has cut).
    /// Before any particle joins, each body is one piece.
    ///
    /// # Errors
    /// [`crate::error::SimError::Refused`] if the neighbour search cannot be built.
    pub fn fragments(&self, particles: &MpmParticles) -> Result<Vec<u32>> {
        let p = particles;
        if self.members.is_empty() {
            return Ok(p.body.clone());
        }
        let built;
        let reference = match &self.reference {
            Some(r) => r,
            None => {
                built = Reference::new(&self.bodies, p)?;
                &built
            }
        };
        let outside: Vec<Vec<u32>> = (0..p.len())
            .into_par_iter()
            .map(|i| {
                if self.is_member(i) {
                    return Vec::new();
                }
                reference.family(&self.bodies, self.horizon, i, p)
            })
            .collect();
        let mut sets = UnionFind::new(p.len());
        for (i, family) in outside.iter().enumerate() {
            for &j in family {
                // A bond to a member is intact if its row says so.
                let intact = match self.slot[j as usize] {
                    OUTSIDE => true,
                    s => {
                        let row = &self.families[s as usize];
                        row.binary_search_by_key(&(i as u32), |&nb| nb & INDEX)
                            .is_ok_and(|k| row[k] & BROKEN == 0)
                    }
                };
                if intact {
                    sets.union(i, j as usize);
                }
            }
        }
        for (&i, family) in self.members.iter().zip(&self.families) {
            for &nb in family.iter().filter(|&&nb| nb & BROKEN == 0) {
                sets.union(i as usize, (nb & INDEX) as usize);
            }
        }
        Ok(sets.labels())
    }

    /// Writes the histories, the members, their bonds and plastic parts F_P⁻¹, and
    /// the integral-based MPM's plastic extensions where a body has them.
    pub fn save(&self, out: &mut Encoder) {
        out.put_f64_slice(&self.history);
        out.put_u64(self.members.len() as u64);
        out.put_u32_slice(&self.members);
        let lengths: Vec<u32> = self.families.iter().map(|f| f.len() as u32).collect();
        out.put_u32_slice(&lengths);
        let bonds: Vec<u32> = self.families.iter().flatten().copied().collect();
        out.put_u64(bonds.len() as u64);
        out.put_u32_slice(&bonds);
        let set: Vec<u32> = self
            .plastic_inverse
            .iter()
            .map(|f| u32::from(f.is_some()))
            .collect();
        out.put_u32_slice(&set);
        let values: Vec<f64> = self
            .plastic_inverse
            .iter()
            .flatten()
            .flatten()
            .flatten()
            .copied()
            .collect();
        out.put_f64_slice(&values);
        if self.plastic_bonds() {
            let extensions: Vec<f64> = self.extensions.iter().flatten().copied().collect();
            out.put_f64_slice(&extensions);
        }
    }

    /// Whether a body has the integral-based MPM's plastic bonds, whose extensions
    /// e^p the checkpoint carries.
    fn plastic_bonds(&self) -> bool {
        self.bodies
            .iter()
            .any(|b| b.bonds.is_some_and(|b| b.flows_per_bond() > 0))
    }

    /// Reads what [`Patches::save`] wrote, refusing members or bonds that are not
    /// this scene's particles and families that differ from those the reference
    /// positions give.
    ///
    /// # Errors
    /// A [`crate::cache::CacheError`] naming the field.
    pub fn restore(&mut self, input: &mut Decoder<'_>, particles: &MpmParticles) -> Result<()> {
        let n = self.slot.len();
        let history = input.take_finite_f64_slice("SPB-MPM energy histories", n)?;
        if let Some(i) = history.iter().position(|&h| h < 0.0) {
            let message = format!("particle {i} has a negative released energy");
            return Err(input.error("SPB-MPM energy histories", message).into());
        }
        let count = input.take_u64("SPB-MPM member count")?;
        if count > n as u64 {
            let message = format!("{count} members for {n} particles");
            return Err(input.error("SPB-MPM member count", message).into());
        }
        let members = input.take_u32_slice_bounded("SPB-MPM members", count as usize, n as u32)?;
        let lengths = input.take_u32_slice("SPB-MPM family sizes", count as usize)?;
        let total = input.take_u64("SPB-MPM bond count")?;
        if total != lengths.iter().map(|&l| u64::from(l)).sum::<u64>() {
            let message = format!("{total} bonds do not add up to the family sizes");
            return Err(input.error("SPB-MPM bond count", message).into());
        }
        let bonds = input
            .take_u32_slice_checked("SPB-MPM bonds", total as usize, |v| (v & INDEX) < n as u32)?;
        let set =
            input.take_u32_slice_checked("SPB-MPM plastic parts", count as usize, |v| v <= 1)?;
        let measured = set.iter().filter(|&&v| v == 1).count();
        let values = input.take_finite_f64_slice("SPB-MPM plastic parts", 9 * measured)?;
        let mut matrices = values
            .chunks_exact(9)
            .map(|m| [0, 1, 2].map(|a| [0, 1, 2].map(|b| m[3 * a + b])));
        let plastic_inverse: Vec<Option<Mat3>> = set
            .iter()
            .map(|&v| if v == 1 { matrices.next() } else { None })
            .collect();
        let mut slot = vec![OUTSIDE; n];
        for (s, &i) in members.iter().enumerate() {
            if slot[i as usize] != OUTSIDE {
                let message = format!("particle {i} is a member twice");
                return Err(input.error("SPB-MPM members", message).into());
            }
            slot[i as usize] = s as u32;
        }
        if !members.is_empty() && self.reference.is_none() {
            self.reference = Some(Reference::new(&self.bodies, particles)?);
        }
        self.history = history;
        self.slot = slot;
        self.members = members;
        self.plastic_inverse = plastic_inverse;
        let mut families = Vec::with_capacity(lengths.len());
        let mut start = 0;
        for (&i, &l) in self.members.iter().zip(&lengths) {
            let family = bonds[start..start + l as usize].to_vec();
            start += l as usize;
            let expected = self.family(i as usize, particles);
            if family
                .iter()
                .map(|&nb| nb & INDEX)
                .ne(expected.iter().copied())
            {
                let message = format!("the family of particle {i} is not its reference neighbours");
                return Err(input.error("SPB-MPM bonds", message).into());
            }
            families.push(family);
        }
        let flows: Vec<usize> = self
            .members
            .iter()
            .map(|&i| {
                self.bodies[particles.body[i as usize] as usize]
                    .bonds
                    .map_or(0, |b| b.flows_per_bond())
            })
            .collect();
        let mut extensions = vec![Vec::new(); self.members.len()];
        if self.plastic_bonds() {
            let total = families.iter().zip(&flows).map(|(f, n)| n * f.len()).sum();
            let values =
                input.take_finite_f64_slice("integral-based MPM plastic extensions", total)?;
            let mut rest = &values[..];
            for ((row, family), n) in extensions.iter_mut().zip(&families).zip(&flows) {
                let (own, next) = rest.split_at(n * family.len());
                *row = own.to_vec();
                rest = next;
            }
        }
        self.extensions = extensions;
        self.families = families;
        self.full_weights.fill(0.0);
        self.settle(0, particles);
        Ok(())
    }
}
