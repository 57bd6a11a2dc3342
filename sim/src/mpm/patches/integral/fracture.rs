//! The integral-based MPM's fracture (Lyu Eq. 5.21 and §5.4): the failure measure l
//! with p_inactive, the bonds past l_threshold, and the crack cut by each cell's
//! fracture plane (the module documentation of [`super`], "Failure").

use std::collections::{BTreeMap, HashMap};

use perifrac_math::{add, dot, norm, normalize, scale, sub};
use rayon::prelude::*;

use super::{IntegralBonds, Strain};
use crate::family::{BROKEN, INDEX};
use crate::mpm::MpmParticles;
use crate::mpm::patches::Patches;

/// l of Eq. 5.21 for a bond of reference length `length` now `y` with plastic
/// extension `plastic`, measured as `strain`, in a cell whose share of broken bonds
/// is `inactive`.
pub(in crate::mpm::patches) fn failure_measure(
    strain: Strain,
    length: f64,
    y: [f64; 3],
    plastic: f64,
    inactive: f64,
) -> f64 {
    strain.elastic(norm(y), length, plastic) / (1.0 + inactive)
}

/// A fracture plane of §5.4 in the grid cell `cell`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::mpm::patches) struct Plane {
    cell: [i64; 3],
    centre: [f64; 3],
    normal: [f64; 3],
}

impl Plane {
    /// Whether the segment from `a` to `b` crosses the plane inside its cell of
    /// spacing `dx`. Symmetric in `a` and `b` only if the caller orders them.
    pub(in crate::mpm::patches) fn cuts(&self, a: [f64; 3], b: [f64; 3], dx: f64) -> bool {
        let (sa, sb) = (
            dot(self.normal, sub(a, self.centre)),
            dot(self.normal, sub(b, self.centre)),
        );
        if sa * sb >= 0.0 {
            return false;
        }
        let t = sa / (sa - sb);
        let crossing = [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]));
        cell_of(crossing, dx) == self.cell
    }
}

/// The grid cell [⌊x/Δx⌋] of a point.
pub(in crate::mpm::patches) fn cell_of(x: [f64; 3], dx: f64) -> [i64; 3] {
    x.map(|c| (c / dx).floor() as i64)
}

impl Patches {
    /// Whether particle `i` belongs to a body with bonds that can break.
    fn breakable(&self, i: usize, p: &MpmParticles) -> bool {
        self.bodies[p.body[i] as usize]
            .bonds
            .is_some_and(|b| b.critical_stretch.is_some())
    }

    /// p_inactive of Eq. 5.21 for each particle: the share of broken bonds among the
    /// bonds of the breakable integral-based members in its grid cell (empty when no
    /// body has bonds that break).
    pub(in crate::mpm::patches) fn inactive_shares(&self, p: &MpmParticles) -> Vec<f64> {
        if !(0..self.bodies.len()).any(|b| {
            self.bodies[b]
                .bonds
                .is_some_and(|b| b.critical_stretch.is_some())
        }) {
            return Vec::new();
        }
        let counts: Vec<Option<([i64; 3], usize, usize)>> = self
            .members
            .par_iter()
            .zip(&self.families)
            .map(|(&i, family)| {
                let i = i as usize;
                self.breakable(i, p).then(|| {
                    let broken = family.iter().filter(|&&nb| nb & BROKEN != 0).count();
                    (cell_of(p.position[i], self.dx), broken, family.len())
                })
            })
            .collect();
        let mut cells: HashMap<[i64; 3], (usize, usize)> = HashMap::new();
        for &(cell, broken, total) in counts.iter().flatten() {
            let entry = cells.entry(cell).or_default();
            entry.0 += broken;
            entry.1 += total;
        }
        let mut shares = vec![0.0; p.len()];
        for (&i, count) in self.members.iter().zip(&counts) {
            if let Some((cell, _, _)) = count {
                let (broken, total) = cells[cell];
                shares[i as usize] = broken as f64 / total.max(1) as f64;
            }
        }
        shares
    }

    /// The intact bonds of member slot `s` (of a body with `bonds`) whose l of Eq.
    /// 5.21 at either end passes l_threshold, by index in its family.
    pub(in crate::mpm::patches) fn stretched(
        &self,
        s: usize,
        bonds: &IntegralBonds,
        inactive: &[f64],
        p: &MpmParticles,
    ) -> Vec<usize> {
        let Some(threshold) = bonds.critical_stretch else {
            return Vec::new();
        };
        let i = self.members[s] as usize;
        self.families[s]
            .iter()
            .enumerate()
            .filter(|&(_, &nb)| nb & BROKEN == 0)
            .filter(|&(k, &nb)| {
                let q = (nb & INDEX) as usize;
                let length = self.table[s][k].length;
                let y = sub(p.position[q], p.position[i]);
                let strain = bonds.strain();
                let own = failure_measure(strain, length, y, self.extension(s, k), inactive[i]);
                let back = self.extension_back(s, k, q);
                let theirs = failure_measure(strain, length, y, back, inactive[q]);
                own.max(theirs) > threshold
            })
            .map(|(k, _)| k)
            .collect()
    }

    /// The crack cut of §5.4: each grid cell where bonds of breakable members broke
    /// this step (`broken`, by member slot) gets a fracture plane through the mean
    /// position of those members, normal to the current direction of the most
    /// stretched of their broken bonds; each intact bond with both ends within reach
    /// of the cell that crosses its plane inside the cell is added to `broken`.
    pub(in crate::mpm::patches) fn cut(
        &self,
        broken: &mut [Vec<usize>],
        inactive: &[f64],
        p: &MpmParticles,
    ) {
        if inactive.is_empty() {
            return;
        }
        let x = &p.position;
        // (Σ x, count, largest l, its bond's direction) of each cell, in cell order.
        type Group = ([f64; 3], f64, f64, [f64; 3]);
        let mut groups: BTreeMap<[i64; 3], Group> = BTreeMap::new();
        for (s, ks) in broken.iter().enumerate() {
            let i = self.members[s] as usize;
            if ks.is_empty() || !self.breakable(i, p) {
                continue;
            }
            let group = groups.entry(cell_of(x[i], self.dx)).or_insert((
                [0.0; 3],
                0.0,
                f64::NEG_INFINITY,
                [0.0; 3],
            ));
            group.0 = add(group.0, x[i]);
            group.1 += 1.0;
            let strain = self.states[s].strain;
            for &k in ks {
                let q = (self.families[s][k] & INDEX) as usize;
                let y = sub(x[q], x[i]);
                let l = failure_measure(
                    strain,
                    self.table[s][k].length,
                    y,
                    self.extension(s, k),
                    inactive[i],
                );
                if l > group.2 {
                    group.2 = l;
                    group.3 = normalize(y);
                }
            }
        }
        let planes: HashMap<[i64; 3], Plane> = groups
            .into_iter()
            .map(|(cell, (sum, count, _, normal))| {
                let plane = Plane {
                    cell,
                    centre: scale(sum, 1.0 / count),
                    normal,
                };
                (cell, plane)
            })
            .collect();
        if planes.is_empty() {
            return;
        }
        let reach = (self.horizon / self.dx).ceil() as i64 + 1;
        let within = |a: [i64; 3], b: [i64; 3]| (0..3).all(|k| (a[k] - b[k]).abs() <= reach);
        let this = self;
        let cuts: Vec<Vec<usize>> = broken
            .par_iter()
            .enumerate()
            .map(|(s, already)| {
                let i = this.members[s] as usize;
                if !this.breakable(i, p) {
                    return Vec::new();
                }
                let cell = cell_of(x[i], this.dx);
                let mut near: Vec<&Plane> = Vec::new();
                for dz in -reach..=reach {
                    for dy in -reach..=reach {
                        for dx in -reach..=reach {
                            let at = [cell[0] + dx, cell[1] + dy, cell[2] + dz];
                            near.extend(planes.get(&at));
                        }
                    }
                }
                if near.is_empty() {
                    return Vec::new();
                }
                this.families[s]
                    .iter()
                    .enumerate()
                    .filter(|&(k, &nb)| nb & BROKEN == 0 && !already.contains(&k))
                    .filter(|&(_, &nb)| {
                        let q = (nb & INDEX) as usize;
                        // Ordered by index, so both directions decide alike.
                        let (a, b) = if i < q { (x[i], x[q]) } else { (x[q], x[i]) };
                        let other = cell_of(x[q], this.dx);
                        near.iter()
                            .any(|plane| within(other, plane.cell) && plane.cuts(a, b, this.dx))
                    })
                    .map(|(k, _)| k)
                    .collect()
            })
            .collect();
        for (row, cut) in broken.iter_mut().zip(cuts) {
            row.extend(cut);
        }
    }
}
