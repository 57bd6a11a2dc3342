//! Rolling resistance of rigid pieces in contact (docs/rigid.md, "Rolling
//! resistance"): rapier's contacts resist sliding (Coulomb friction) and approach
//! (restitution), not rolling or spinning about a contact, so a chip spinning on the
//! ground never stops and a piece spinning at hundreds of radians a second keeps
//! turning its spin into bounces.

use rapier3d_f64::na::Vector3;
use rapier3d_f64::prelude::*;

use super::RigidPhase;

impl RigidPhase {
    /// Opposes the spin of every awake piece relative to each body it touched in the
    /// step just taken, as rolling resistance does: the normal force N of a contact
    /// acts a distance b ahead of it (b the coefficient of rolling resistance, a
    /// length: `rolling_resistance`), a couple of at most b N against the relative
    /// angular velocity ω_a − ω_b, in every direction (rolling, and spinning about the
    /// normal: Bullet's rolling and spinning friction). It is given as the angular
    /// impulse b J_n of the step's normal impulse J_n, never more than stops the
    /// relative spin. Between two pieces the couples are equal and opposite, so their
    /// angular momentum is kept; against the ground and the scene's colliders it goes
    /// to them, as friction's does. Linear momentum is not touched, and a piece in
    /// flight feels nothing.
    pub(super) fn resist_rolling(&mut self) {
        let arm = self.settings.rolling_resistance;
        if arm == 0.0 {
            return;
        }
        let ph = &mut self.physics;
        let pieces: std::collections::BTreeSet<(u32, u32)> = self
            .pieces
            .iter()
            .map(|p| p.body.into_raw_parts())
            .collect();
        for piece in &self.pieces {
            let a = piece.body;
            if ph.bodies[a].is_sleeping() || !ph.bodies[a].is_dynamic() {
                continue;
            }
            let colliders = ph.bodies[a].colliders().to_vec();
            for collider in colliders {
                for pair in ph.narrow_phase.contact_pairs_with(collider) {
                    let other = if pair.collider1 == collider {
                        pair.collider2
                    } else {
                        pair.collider1
                    };
                    let Some(b) = ph.colliders.get(other).and_then(|c| c.parent()) else {
                        continue;
                    };
                    // A pair of awake pieces once, from the one with the lower handle.
                    let b_moves = ph.bodies[b].is_dynamic() && !ph.bodies[b].is_sleeping();
                    if b_moves
                        && pieces.contains(&b.into_raw_parts())
                        && b.into_raw_parts() < a.into_raw_parts()
                    {
                        continue;
                    }
                    // The first collider's impulse along the normal: positive, pushing
                    // the two apart.
                    let normal: f64 = pair
                        .manifolds
                        .iter()
                        .filter(|m| !m.data.solver_contacts.is_empty())
                        .flat_map(|m| m.points.iter().map(|p| p.data.impulse))
                        .sum();
                    if normal <= 0.0 {
                        continue;
                    }
                    let limit = arm * normal;
                    let spin_b = if b_moves || ph.bodies[b].is_kinematic() {
                        *ph.bodies[b].angvel()
                    } else {
                        Vector3::zeros()
                    };
                    let relative = ph.bodies[a].angvel() - spin_b;
                    let rate = relative.norm();
                    if rate == 0.0 {
                        continue;
                    }
                    let axis = relative / rate;
                    let softness = |body: &RigidBody| {
                        let s = body.mass_properties().effective_world_inv_inertia_sqrt;
                        axis.dot(&(s * (s * axis)))
                    };
                    let mut compliance = softness(&ph.bodies[a]);
                    if b_moves {
                        compliance += softness(&ph.bodies[b]);
                    }
                    if compliance <= 0.0 {
                        continue;
                    }
                    let impulse = axis * limit.min(rate / compliance);
                    ph.bodies[a].apply_torque_impulse(-impulse, false);
                    if b_moves {
                        ph.bodies[b].apply_torque_impulse(impulse, false);
                    }
                }
            }
        }
    }
}
