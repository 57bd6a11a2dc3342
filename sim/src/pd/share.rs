//! A peridynamic model's bond work split over ranks ([`crate::ranks`]): after each
//! stage of the step (`dilatation → forces`), a rank sends what it computed for its
//! own particles and takes in the others', so that every rank holds the whole model
//! again before the next stage reads it.
//!
//! What each stage changes, and so what goes out:
//! - dilatation (Chen Eq. 6) with the return mapping (Eq. 13–16): θ_i of each owned
//!   particle; with plasticity, its `yielded` flag and the plastic extensions e^p of
//!   its bonds that changed (the force pass of i reads e^p_ji from j's row);
//! - forces (Eq. 2–4, 8, 12) with fracture (Eq. 18–19): f_i and φ_i of each owned
//!   particle, the broken bits that changed in its rows and the crushed bonds' e^c
//!   that changed, and the count of bonds broken.
//!
//! Per-bond state goes as changes (a copy of the owned rows before the stage, compared
//! after), so a step sends per bond only what broke, crushed or yielded. A stage's
//! values go in one [`Message`]: one gather a stage.

use std::ops::Range;

use super::PdModel;
use crate::ranks::{Message, Reader};

/// The owned rows' per-bond state before a stage, on a shared model.
#[derive(Debug, Default)]
pub(super) struct Before {
    /// Neighbour words (the broken bit) of the owned rows.
    neighbours: Option<Vec<u32>>,
    /// e^c of the owned rows.
    crushed: Option<Vec<f32>>,
    /// e^p of the owned rows.
    extension: Option<Vec<f64>>,
}

impl Before {
    /// What the dilatation stage may change in the owned rows: e^p.
    pub(super) fn dilatation(m: &PdModel, owned: &Range<usize>) -> Before {
        if m.share.is_none() {
            return Before::default();
        }
        let rows = bond_range(m, owned);
        Before {
            extension: m.plastic.as_ref().map(|p| p.extension[rows].to_vec()),
            ..Before::default()
        }
    }

    /// What the force stage may change in the owned rows: broken bits and e^c.
    pub(super) fn forces(m: &PdModel, owned: &Range<usize>) -> Before {
        if m.share.is_none() || !m.features.fracture {
            return Before::default();
        }
        let rows = bond_range(m, owned);
        Before {
            neighbours: Some(m.bonds.neighbours[rows.clone()].to_vec()),
            crushed: m.crushed.as_ref().map(|c| c[rows].to_vec()),
            ..Before::default()
        }
    }
}

/// The bonds of the particles `owned`.
fn bond_range(m: &PdModel, owned: &Range<usize>) -> Range<usize> {
    m.bonds.offsets[owned.start]..m.bonds.offsets[owned.end]
}

/// Sends this rank's θ and, with plasticity, its `yielded` flags and changed e^p, and
/// takes in the others'. Nothing on a model that is not shared.
pub(super) fn after_dilatation(m: &mut PdModel, owned: &Range<usize>, before: Before) {
    let Some(share) = &m.share else {
        return;
    };
    let first = m.bonds.offsets[owned.start];
    let mut mine = Message::default();
    mine.put(&m.theta[owned.clone()]);
    if let Some(p) = &m.plastic {
        let yielded: Vec<f64> = p.yielded[owned.clone()]
            .iter()
            .map(|&y| y as u8 as f64)
            .collect();
        mine.put(&yielded);
        if let Some(before) = &before.extension {
            mine.put_changes(first, before, &p.extension);
        }
    }
    for (range, message) in share.gather(&mine.0) {
        let mut reader = Reader::new(&message);
        m.theta[range.clone()].copy_from_slice(reader.take(range.len()));
        if let Some(p) = &mut m.plastic {
            for (y, &flag) in p.yielded[range.clone()]
                .iter_mut()
                .zip(reader.take(range.len()))
            {
                *y = flag != 0.0;
            }
            for (k, value) in reader.changes() {
                p.extension[k] = value;
            }
        }
    }
}

/// Sends this rank's forces and, with fracture, its damage, broken count, broken bits
/// and changed e^c, and takes in the others'; returns the bonds broken on all ranks
/// (this rank broke `broken`), or `broken` on a model that is not shared.
pub(super) fn after_forces(
    m: &mut PdModel,
    owned: &Range<usize>,
    before: Before,
    broken: usize,
) -> usize {
    let Some(share) = &m.share else {
        return broken;
    };
    let first = m.bonds.offsets[owned.start];
    let fracture = m.features.fracture;
    let mut mine = Message::default();
    mine.put(m.force[owned.clone()].as_flattened());
    if fracture {
        mine.put(&m.particles.damage[owned.clone()]);
        mine.put(&[broken as f64]);
        if let Some(before) = &before.neighbours {
            mine.put_changes(first, before, &m.bonds.neighbours);
        }
        if let (Some(before), Some(crushed)) = (&before.crushed, &m.crushed) {
            mine.put_changes(first, before, crushed);
        }
    }
    let mut total = 0;
    for (range, message) in share.gather(&mine.0) {
        let mut reader = Reader::new(&message);
        m.force[range.clone()]
            .as_flattened_mut()
            .copy_from_slice(reader.take(3 * range.len()));
        if !fracture {
            continue;
        }
        m.particles.damage[range.clone()].copy_from_slice(reader.take(range.len()));
        total += reader.take(1)[0] as usize;
        for (k, word) in reader.changes() {
            m.bonds.neighbours[k] = word as u32;
        }
        if let Some(crushed) = &mut m.crushed {
            for (k, value) in reader.changes() {
                crushed[k] = value as f32;
            }
        }
    }
    if fracture { total } else { broken }
}
