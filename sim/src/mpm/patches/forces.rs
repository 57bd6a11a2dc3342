//! The bond forces of a step, as accelerations of the members and their halo, and
//! their application before P2G (the module documentation of [`super`], "Forces").

use perifrac_math::sub;
use rayon::prelude::*;

use super::Patches;
use super::integral::force_state;
use crate::family::BROKEN;
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
    pub(super) fn forces(&mut self, p: &MpmParticles) {
        let this = &*self;
        // Each member's acceleration and the forces on its halo neighbours.
        type Row = ([f64; 3], Vec<(u32, [f64; 3])>);
        let rows: Vec<Row> = self
            .members
            .par_iter()
            .zip(&self.families)
            .map(|(&i, family)| {
                let i = i as usize;
                let s = this.slot[i] as usize;
                let own = &this.states[s];
                let mut sum = [0.0; 3];
                let mut reactions = Vec::new();
                for (k, &nb) in family
                    .iter()
                    .enumerate()
                    .filter(|&(_, &nb)| nb & BROKEN == 0)
                {
                    let q = nb as usize;
                    let xi = sub(p.reference[q], p.reference[i]);
                    let y = sub(p.position[q], p.position[i]);
                    let tpq = force_state(own, xi, y, this.extension(s, k), this.horizon);
                    let member = this.is_member(q);
                    let tqp = if member {
                        let back = (xi.map(|c| -c), y.map(|c| -c));
                        let state = &this.states[this.slot[q] as usize];
                        let plastic = this.extension_of(q, i);
                        force_state(state, back.0, back.1, plastic, this.horizon)
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
        let mut reactions: Vec<(u32, [f64; 3])> = Vec::new();
        self.accelerations.clear();
        for (&i, (a, r)) in self.members.iter().zip(rows) {
            self.accelerations.push((i, a));
            reactions.extend(r);
        }
        // A stable sort keeps each halo particle's reactions in member order.
        reactions.sort_by_key(|&(q, _)| q);
        for chunk in reactions.chunk_by(|a, b| a.0 == b.0) {
            let q = chunk[0].0;
            let mut total = [0.0; 3];
            for (_, f) in chunk {
                for a in 0..3 {
                    total[a] += f[a];
                }
            }
            let m = p.mass[q as usize];
            self.accelerations.push((q, total.map(|c| c / m)));
        }
    }

    /// Before P2G: the members and their halo take this step's bond accelerations,
    /// v ← v + Δt a, which the transfer carries to the grid as any particle force
    /// (Σ_p w_ip Δt f_p): the particles then move with the grid's velocities.
    /// Algorithm 3 (line 21) corrects the velocity and the position after G2P
    /// instead; positions moved apart from the grid's flow leave F^MPM behind them,
    /// and the MPM region next to a patch let go of it (a bar half peridynamic opened
    /// 4 mm at the edge of the patch under a 6 mm stretch, F^MPM there 1.01).
    pub fn apply(&self, dt: f64, particles: &mut MpmParticles) {
        for &(i, a) in &self.accelerations {
            let v = &mut particles.velocity[i as usize];
            for c in 0..3 {
                v[c] += dt * a[c];
            }
        }
    }
}
