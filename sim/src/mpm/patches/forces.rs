//! The bond forces of a step, as accelerations of the members and their halo, and
//! their application before P2G (the module documentation of [`super`], "Forces").

use perifrac_math::sub;
use rayon::prelude::*;

use super::Patches;
use super::integral::force_state;
use super::reference::NO_MIRROR;
use crate::family::{BROKEN, INDEX};
use crate::mpm::MpmParticles;

impl Patches {
    /// The bond forces of this step (Eq. 6.6) as accelerations. Each particle's stress
    /// acts once: a material point's through the grid, a member's through its bonds,
    /// T_pq on p and −T_pq on q (Newton's third law). So a bond between two members
    /// carries T_pq − T_qp, and a bond from a member to a material point of the halo
    /// carries only the member's T_pq: the material point's own stress is already on
    /// the grid (counting it on the bond too pulled the halo away from the MPM region
    /// below it, which opened a gap there: 4.8 mm of a 6 mm stretch in the half
    /// peridynamic bar of the tests).
    ///
    /// Each member's T_p⟨q⟩ is worked out once a step, into [`Patches::tractions`];
    /// a bond then reads T_q⟨p⟩ from the other end's row at its mirror index.
    pub(super) fn forces(&mut self, p: &MpmParticles) {
        let delta = self.horizon;
        let mut tractions = std::mem::take(&mut self.tractions);
        tractions.resize_with(self.members.len(), Vec::new);
        let this = &*self;
        tractions.par_iter_mut().enumerate().for_each(|(s, row)| {
            let i = this.members[s] as usize;
            let state = &this.states[s];
            row.clear();
            row.extend(this.families[s].iter().zip(&this.table[s]).enumerate().map(
                |(k, (&nb, bond))| {
                    if nb & BROKEN != 0 {
                        return [0.0; 3];
                    }
                    let q = (nb & INDEX) as usize;
                    let xi = sub(p.reference[q], p.reference[i]);
                    let y = sub(p.position[q], p.position[i]);
                    force_state(state, xi, y, bond, this.extension(s, k), delta)
                },
            ));
        });
        // Each member's acceleration and the forces on its halo neighbours.
        type Row = ([f64; 3], Vec<(u32, [f64; 3])>);
        let rows: Vec<Row> = (0..self.members.len())
            .into_par_iter()
            .map(|s| {
                let i = this.members[s] as usize;
                let mut sum = [0.0; 3];
                let mut reactions = Vec::new();
                for (k, &nb) in this.families[s]
                    .iter()
                    .enumerate()
                    .filter(|&(_, &nb)| nb & BROKEN == 0)
                {
                    let q = nb as usize;
                    let tpq = tractions[s][k];
                    let member = this.is_member(q);
                    // Families are symmetric to the bit (`family::neighbours_of`), so a
                    // bond between members has its mirror; a bond broken at the other
                    // end only is one to a free member, whose T is zero.
                    let mirror = this.table[s][k].mirror;
                    let tqp = if member && mirror != NO_MIRROR {
                        tractions[this.slot[q] as usize][mirror as usize]
                    } else {
                        [0.0; 3]
                    };
                    let pair = p.volume[i] * p.volume[q];
                    let f = [0, 1, 2].map(|a| pair * (tpq[a] - tqp[a]));
                    for a in 0..3 {
                        sum[a] += f[a];
                    }
                    if !member {
                        reactions.push((q as u32, f.map(|c| -c)));
                    }
                }
                (sum.map(|c| c / p.mass[i]), reactions)
            })
            .collect();
        self.tractions = tractions;
        // Each halo particle's reactions summed in member order (and each member's in
        // its family's), into a total a particle, then taken in particle order.
        self.accelerations.clear();
        self.halo_totals.resize(p.len(), [0.0; 3]);
        self.halo_seen.resize(p.len(), false);
        let mut halo = Vec::new();
        for (&i, (a, reactions)) in self.members.iter().zip(rows) {
            self.accelerations.push((i, a));
            for (q, f) in reactions {
                let q = q as usize;
                if !self.halo_seen[q] {
                    self.halo_seen[q] = true;
                    halo.push(q);
                }
                let total = &mut self.halo_totals[q];
                for a in 0..3 {
                    total[a] += f[a];
                }
            }
        }
        halo.sort_unstable();
        for q in halo {
            self.halo_seen[q] = false;
            let total = std::mem::take(&mut self.halo_totals[q]);
            let m = p.mass[q];
            self.accelerations.push((q as u32, total.map(|c| c / m)));
        }
    }

    /// Before P2G: the members and their halo take this step's bond accelerations,
    /// v ← v + Δt a, which the transfer carries to the grid as any particle force
    /// (Σ_p w_ip Δt f_p): the particles then move with the grid's velocities.
    /// Algorithm 3 (line 21) corrects the velocity and the position after G2P
    /// instead; positions moved apart from the grid's flow leave F^MPM behind them,
    /// and the MPM region next to a patch let go of it (a bar half peridynamic opened
    /// 4 mm at the edge of the patch under a 6 mm stretch, F^MPM there 1.01).
    ///
    /// Particles `anchored` this step (one flag a particle, empty when no anchor is
    /// active) keep their velocities. An anchor prescribes its particles' motion (the
    /// world puts them back on its path after the step), so their virtual
    /// displacements δu_p vanish in the weak form (Lyu Eq. 5.1; Eq. 6.3 for SPB-MPM)
    /// and their force densities drop out of the grid's forces (Eq. 5.2, Eq. 6.6): the
    /// bond force on an anchored particle is its anchor's reaction. They still bring
    /// their mass and their anchor's velocity to the grid. Applied, the reaction went
    /// through P2G onto the free nodes next to a clamp (where the anchored particles
    /// have less than half the mass, [`crate::mpm::grid::HELD_MASS_SHARE`]), 23–42% of
    /// the bar's tension pulling them back towards its middle, and the bonds across
    /// the clamp's edge stretched ahead of a notch that took half the bar's section
    /// away: the bar broke there, not at its notch (docs/mpm.md, "Integral-based MPM").
    pub fn apply(&self, dt: f64, anchored: &[bool], particles: &mut MpmParticles) {
        for &(i, a) in &self.accelerations {
            if anchored.get(i as usize).copied().unwrap_or(false) {
                continue;
            }
            let v = &mut particles.velocity[i as usize];
            for c in 0..3 {
                v[c] += dt * a[c];
            }
        }
    }
}
