//! A membrane's pass over its bonds split over ranks ([`crate::ranks`]), as
//! peridynamics' is (`sim/src/pd/share.rs`): each rank strains, breaks and sums the
//! bonds of its own contiguous range of particles (about equal bond counts,
//! [`Share::by_bonds`]), then sends what it computed and takes in the others', so
//! that every rank holds the whole model again before the rest of the step (the
//! integrator, the diffusion step of Eq. 26, damping) runs on every rank alike.
//!
//! What goes out, and why each is needed:
//! - after the state-based option's first pass, the dilatations ϑ_i of the owned
//!   particles: the force state of bond i→j reads ϑ_j;
//! - after the forces, f_i (Eq. 18, 22), φ_i, the diffusion rate θ̇_i of Eq. 25 when a
//!   body conducts (every rank steps θ for every particle), the count of bonds broken,
//!   and the broken bits (Eq. 27–28) that changed in the owned rows in either pass,
//!   sent as changes against a copy of those rows taken before the first.
//!
//! Each particle still gathers over its own bonds in the same order, so a run on any
//! number of ranks gives the bytes of one process.

use std::ops::Range;
use std::sync::Arc;
use std::time::Instant;

use super::MembraneModel;
use crate::ranks::{Message, Ranks, Reader, Share};

impl MembraneModel {
    /// Splits the pass over the bonds over `ranks`: from the next step on, this rank
    /// strains, breaks and sums its range of particles and takes in the others'. One
    /// rank keeps it whole.
    pub fn share(&mut self, ranks: Arc<dyn Ranks>) {
        if self.share.is_some() || ranks.size() < 2 {
            return;
        }
        self.share = Some(Share::by_bonds(ranks, &self.bonds.offsets));
    }

    /// The particles whose bonds this process works on: all of them in one process.
    pub fn owned(&self) -> Range<usize> {
        self.share.as_ref().map_or(0..self.len(), Share::owned)
    }
}

/// The owned rows' broken bits before a step's passes over the bonds, on a shared
/// model whose bonds can break; `None` otherwise.
pub(super) fn before(m: &MembraneModel, owned: &Range<usize>) -> Option<Vec<u32>> {
    let breaks = m.bodies.iter().any(|b| b.critical_strain.is_finite());
    (m.share.is_some() && breaks).then(|| m.bonds.neighbours[bond_range(m, owned)].to_vec())
}

/// The bonds of the particles `owned`.
fn bond_range(m: &MembraneModel, owned: &Range<usize>) -> Range<usize> {
    m.bonds.offsets[owned.start]..m.bonds.offsets[owned.end]
}

/// Sends this rank's dilatations and takes in the others'. Nothing on a model that
/// is not shared.
pub(super) fn after_dilatations(m: &mut MembraneModel, owned: &Range<usize>) {
    let Some(share) = &m.share else {
        return;
    };
    let t = Instant::now();
    for (range, values) in share.gather(&m.dilatation[owned.clone()]) {
        m.dilatation[range].copy_from_slice(&values);
    }
    m.times.exchange += t.elapsed().as_secs_f64();
}

/// Sends this rank's forces, damage, rates (when a body conducts), broken count and
/// changed broken bits (against `before`), and takes in the others'; returns the
/// bonds broken on all ranks (this rank broke `broken`), or `broken` on a model that
/// is not shared.
pub(super) fn after_forces(
    m: &mut MembraneModel,
    owned: &Range<usize>,
    before: Option<Vec<u32>>,
    broken: usize,
) -> usize {
    let Some(share) = &m.share else {
        return broken;
    };
    let t = Instant::now();
    let first = m.bonds.offsets[owned.start];
    let mut mine = Message::default();
    mine.put(m.force[owned.clone()].as_flattened());
    mine.put(&m.damage[owned.clone()]);
    if !m.rate.is_empty() {
        mine.put(&m.rate[owned.clone()]);
    }
    mine.put(&[broken as f64]);
    if let Some(before) = &before {
        mine.put_changes(first, before, &m.bonds.neighbours);
    }
    let mut total = 0;
    for (range, message) in share.gather(&mine.0) {
        let mut reader = Reader::new(&message);
        m.force[range.clone()]
            .as_flattened_mut()
            .copy_from_slice(reader.take(3 * range.len()));
        m.damage[range.clone()].copy_from_slice(reader.take(range.len()));
        if !m.rate.is_empty() {
            m.rate[range.clone()].copy_from_slice(reader.take(range.len()));
        }
        total += reader.take(1)[0] as usize;
        if before.is_some() {
            for (k, word) in reader.changes() {
                m.bonds.neighbours[k] = word as u32;
            }
        }
    }
    m.times.exchange += t.elapsed().as_secs_f64();
    total
}
