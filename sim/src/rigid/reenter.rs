//! Going back: a rigid piece about to be hit hard returns to its model before the hit,
//! so that the hit's stress wave runs through its bonds and breaks what it breaks
//! (docs/rigid.md, "Going back").
//!
//! **How hard.** A hit closing at speed u sends a stress wave of strain u/c_p into the
//! piece (a bar striking a rigid wall: σ = ρ c_p u); its bonds start to break when
//! that strain nears the critical stretch s_c. A piece goes back when a hit would close
//! at `reenter` × s_c c_p or faster ([`crate::model::Fragments::hit_speed`]); by
//! default (0) none does, and why: docs/rigid.md, "Going back".
//!
//! **When.** Before every step, each piece of more than `reenter_points` points (a piece
//! a few particles across has next to no interior to crack) looks for a contact that
//! the step would close at such a speed: its points against the ground and the sphere
//! and box colliders (the gap under how far its collider reaches beyond its points,
//! less what the step closes), and against the other pieces but debris (a point against the
//! other piece's nearest point, the closing speed along the line between them). The bounding spheres (a piece's centre
//! of mass, half its size plus that reach) leave out all but the pieces that can
//! touch within the step, and a point moving relative to the other piece's rigid
//! motion slower than the limit is not looked at further.
//!
//! **The switch back.** The body leaves rapier; its points keep the pose and velocity
//! it gave them, so the fragment's momenta are the body's, and its bonds are as they
//! were at the hand-off (a rigid motion changes no bond's stretch). It may not go
//! rigid again before the hit it was thawed for is over: not before the end of the
//! step it was thawed for plus `settle_time`.

use perifrac_math::{add, cross, dist, dot, norm, sub};

use super::{Hold, Piece, RigidPhase};
use crate::contact::{Collider, ColliderShape};
use crate::model::Points;
use crate::world::Part;

/// A rigid piece given back to its model: its part and points.
#[derive(Debug, Clone, PartialEq)]
pub struct Thawed {
    /// The world part.
    pub part: usize,
    /// Its points in that part's model.
    pub points: Vec<u32>,
}

/// The closing speed (m/s) at which point `x`, moving at `v`, meets the collider
/// within `dt`, with `rounding` (how far the piece's collider reaches beyond its
/// points, [`Piece::rounding`]) around the point; 0 when
/// it does not meet it.
fn collider_closing(c: &Collider, x: [f64; 3], v: [f64; 3], rounding: f64, dt: f64) -> f64 {
    let (gap, normal) = match c.shape {
        ColliderShape::Ground => (x[1] - c.center[1], [0.0, 1.0, 0.0]),
        ColliderShape::Sphere(r) => {
            let d = sub(x, c.center);
            let l = norm(d);
            if l == 0.0 {
                return 0.0;
            }
            (l - r, d.map(|a| a / l))
        }
        ColliderShape::Box(h) => {
            let d = sub(x, c.center);
            let out = [0, 1, 2].map(|k| d[k] - d[k].clamp(-h[k], h[k]));
            let l = norm(out);
            if l == 0.0 {
                // Inside the box: closing at its whole relative speed.
                return dist(v, c.velocity);
            }
            (l, out.map(|a| a / l))
        }
        ColliderShape::Mesh(_) => match c.outside(x) {
            Some(gap) => gap,
            // Inside it: closing at its whole relative speed, as in a box.
            None => return dist(v, c.velocity_at(x)),
        },
    };
    let closing = -dot(sub(v, c.velocity_at(x)), normal);
    if closing > 0.0 && gap - rounding <= closing * dt {
        closing
    } else {
        0.0
    }
}

/// A piece's bounding sphere: its centre of mass and radius (half its size plus its
/// collider's reach beyond its points), its linear velocity and the speed its spin adds at that radius.
struct Bound {
    center: [f64; 3],
    radius: f64,
    velocity: [f64; 3],
    spin: [f64; 3],
    reach: f64,
}

/// Two pieces that may meet within a step of `dt`, their points `rounding` apart at
/// contact (each one's [`Piece::rounding`]), and the closing speed that counts (`limit`).
struct Pair {
    rounding: f64,
    dt: f64,
    limit: f64,
}

impl Pair {
    /// The largest closing speed, at `limit` or above, at which a point of `from`
    /// meets `onto` (of bounding sphere `bound`) within the step; 0 if none does.
    /// Only a point within the bounding sphere and moving relative to `onto`'s rigid
    /// motion at `limit` or faster is looked at; it closes on the nearest point of
    /// `onto` along the line between them.
    fn closing(
        &self,
        from: (&[u32], &Points<'_>),
        onto: (&[u32], &Points<'_>),
        bound: &Bound,
    ) -> f64 {
        let (xf, xo) = (from.1, onto.1);
        let mut fastest: f64 = 0.0;
        for &i in from.0 {
            let (p, v) = (xf.position[i as usize], xf.velocity[i as usize]);
            let r = sub(p, bound.center);
            if norm(r) > bound.radius + self.dt * (norm(v) + bound.reach) {
                continue;
            }
            let carried = add(bound.velocity, cross(bound.spin, r));
            if dist(v, carried) < self.limit {
                continue;
            }
            let (mut nearest, mut d2) = (0, f64::INFINITY);
            for &j in onto.0 {
                let q = xo.position[j as usize];
                let e = dot(sub(q, p), sub(q, p));
                if e < d2 {
                    (nearest, d2) = (j as usize, e);
                }
            }
            let d = d2.sqrt();
            if d == 0.0 {
                continue;
            }
            let (q, vq) = (xo.position[nearest], xo.velocity[nearest]);
            let closing = dot(sub(v, vq), sub(q, p)) / d;
            if closing >= self.limit && d - self.rounding <= closing * self.dt {
                fastest = fastest.max(closing);
            }
        }
        fastest
    }
}

impl RigidPhase {
    fn bound(&self, piece: &Piece) -> Bound {
        let body = &self.physics.bodies[piece.body];
        let radius = 0.5 * piece.size + piece.rounding();
        let velocity = super::array(body.linvel());
        let spin = super::array(body.angvel());
        Bound {
            center: super::array(body.translation()),
            radius,
            velocity,
            spin,
            reach: norm(velocity) + norm(spin) * radius,
        }
    }

    /// Gives back to their models, before a step of `dt` at `time`, the pieces that
    /// the step would bring into a hit at their closing-speed limit or faster (see the
    /// module's comment); returns them, in piece order.
    pub fn reenter(
        &mut self,
        dt: f64,
        time: f64,
        parts: &mut [Part],
        colliders: &[Collider],
    ) -> Vec<Thawed> {
        if self.settings.reenter == 0.0 {
            return Vec::new();
        }
        self.holds.retain(|h| h.until > time);
        if !self.pieces.iter().any(|p| p.limit.is_finite()) {
            return Vec::new();
        }
        let bounds: Vec<Bound> = self.pieces.iter().map(|p| self.bound(p)).collect();
        // Whether the step brings each piece into a hit at its limit.
        let mut hit = vec![false; self.pieces.len()];
        for (a, piece) in self.pieces.iter().enumerate() {
            if !piece.limit.is_finite() {
                continue;
            }
            let ba = &bounds[a];
            let x = parts[piece.part as usize].model.points();
            let rounding = piece.rounding();
            // The ground and the colliders.
            for c in colliders {
                let near = match c.shape {
                    ColliderShape::Ground => ba.center[1] - ba.radius - c.center[1],
                    ColliderShape::Sphere(r) => dist(ba.center, c.center) - ba.radius - r,
                    ColliderShape::Box(h) => dist(ba.center, c.center) - ba.radius - norm(h),
                    ColliderShape::Mesh(_) => {
                        c.outside(ba.center).map_or(0.0, |(gap, _)| gap) - ba.radius
                    }
                };
                let collider_speed = norm(c.velocity) + norm(c.angular_velocity) * ba.radius;
                if near > dt * (ba.reach + collider_speed) {
                    continue;
                }
                for &i in &piece.points {
                    let i = i as usize;
                    let u = collider_closing(c, x.position[i], x.velocity[i], rounding, dt);
                    if u >= piece.limit {
                        hit[a] = true;
                        break;
                    }
                }
            }
            // The other pieces, but debris.
            for (b, other) in self.pieces.iter().enumerate() {
                if a == b || other.points.len() <= self.settings.small_fragment {
                    continue;
                }
                let bb = &bounds[b];
                let apart = dist(ba.center, bb.center) - ba.radius - bb.radius;
                if apart > dt * (ba.reach + bb.reach) {
                    continue;
                }
                let xb = parts[other.part as usize].model.points();
                let pair = Pair {
                    rounding: piece.rounding() + other.rounding(),
                    dt,
                    limit: piece.limit,
                };
                let u = pair
                    .closing((&piece.points, &x), (&other.points, &xb), bb)
                    .max(pair.closing((&other.points, &xb), (&piece.points, &x), ba));
                if u >= piece.limit {
                    hit[a] = true;
                }
            }
        }
        let mut thawed = Vec::new();
        for a in (0..self.pieces.len()).rev() {
            if !hit[a] {
                continue;
            }
            let piece = self.pieces.remove(a);
            self.contact.remove(a);
            let ph = &mut self.physics;
            ph.bodies.remove(
                piece.body,
                &mut ph.islands,
                &mut ph.colliders,
                &mut ph.impulse_joints,
                &mut ph.multibody_joints,
                true,
            );
            parts[piece.part as usize].model.thaw(&piece.points);
            self.holds.push(Hold {
                part: piece.part,
                points: piece.points.clone(),
                until: time + dt + self.settings.settle_time,
            });
            thawed.push(Thawed {
                part: piece.part as usize,
                points: piece.points,
            });
        }
        thawed.reverse();
        thawed
    }
}
