//! Pieces born side by side (docs/rigid.md, "Pieces born side by side"). Two pieces
//! that go rigid where a crack ran between them touch along a jagged face, and the
//! convex parts of their surface colliders bulge across it by up to a tet: colliding
//! as those parts, rapier pushes the two apart or wedges them. So a piece whose surface
//! collider overlaps another piece's when it goes rigid becomes that piece's
//! *partner* (debris takes none): the two meet as balls at their particles along the
//! crack (within two spacings of the other's), not as their surfaces, until
//! their surfaces no longer overlap; with everything else each collides as its surface
//! throughout. The balls' radius is half the closest distance between the two pieces'
//! particles at the switch (so they start apart, as the particles were), kept within a
//! quarter and a half of a spacing.

use std::collections::{BTreeMap, BTreeSet};

use rapier3d_f64::parry::query;
use rapier3d_f64::prelude::*;

use super::{Piece, RigidPhase, vector};
use crate::world::Part;

/// `user_data` of a piece's collider of balls (its surface collider's is 0).
const BALLS: u128 = 1;

/// A pair of bodies in a fixed order.
type Pair = ((u32, u32), (u32, u32));

fn pair(a: RigidBodyHandle, b: RigidBodyHandle) -> Pair {
    let (a, b) = (a.into_raw_parts(), b.into_raw_parts());
    if a < b { (a, b) } else { (b, a) }
}

/// What rapier asks about the pairs of colliders that involve a partnered piece:
/// partners meet as balls only, and balls meet nothing but their partners' balls.
pub(super) struct Filter {
    partners: BTreeSet<Pair>,
}

impl PhysicsHooks for Filter {
    fn filter_contact_pair(&self, c: &PairFilterContext) -> Option<SolverFlags> {
        let balls = |h: ColliderHandle| c.colliders[h].user_data == BALLS;
        let (b1, b2) = (balls(c.collider1), balls(c.collider2));
        let partners = match (c.rigid_body1, c.rigid_body2) {
            (Some(a), Some(b)) => self.partners.contains(&pair(a, b)),
            _ => false,
        };
        let meet = if b1 || b2 {
            b1 && b2 && partners
        } else {
            !partners
        };
        meet.then(SolverFlags::default)
    }
}

impl RigidPhase {
    /// The contact filter for this step: every pair of partners.
    pub(super) fn filter(&self) -> Filter {
        let partners = self
            .pieces
            .iter()
            .flat_map(|p| p.partners.iter().map(|&h| pair(p.body, h)))
            .collect();
        Filter { partners }
    }

    /// A piece's surface collider (the first it was given).
    fn surface_collider(&self, piece: &Piece) -> ColliderHandle {
        self.physics.bodies[piece.body].colliders()[0]
    }

    /// Whether the surface colliders of two pieces overlap.
    fn overlap(&self, a: &Piece, b: &Piece) -> bool {
        let colliders = &self.physics.colliders;
        let (ca, cb) = (
            &colliders[self.surface_collider(a)],
            &colliders[self.surface_collider(b)],
        );
        ca.compute_aabb().intersects(&cb.compute_aabb())
            && query::intersection_test(ca.position(), ca.shape(), cb.position(), cb.shape())
                .unwrap_or(false)
    }

    /// Makes piece `a` (just gone rigid) the partner of every earlier piece its
    /// surface collider overlaps, and gives both their balls (or smaller ones).
    /// Debris (at most `small_fragment` points) takes no partner: its bulges are a
    /// grain's, and on the demo shot the thousands of grains that go rigid together
    /// at the end made rapier's step six times as long as partners.
    pub(super) fn find_partners(&mut self, a: usize, parts: &[Part]) {
        let small = self.settings.small_fragment;
        let piece = &self.pieces[a];
        if piece.points.len() <= small {
            return;
        }
        let found: Vec<(usize, f64)> = self.pieces[..a]
            .iter()
            .enumerate()
            .filter(|(_, b)| b.points.len() > small && self.overlap(piece, b))
            .map(|(k, b)| (k, closest(piece, b, parts)))
            .collect();
        if found.is_empty() {
            return;
        }
        // Every partnership first, then each piece's balls once: `a` takes the
        // smallest radius of its new partnerships.
        let mut smallest = f64::INFINITY;
        let mut radii = Vec::with_capacity(found.len());
        for &(b, distance) in &found {
            let spacing = self.pieces[a].thickness.min(self.pieces[b].thickness);
            let radius = (0.5 * distance).clamp(0.25 * spacing, 0.5 * spacing);
            let (ha, hb) = (self.pieces[a].body, self.pieces[b].body);
            self.pieces[a].partners.push(hb);
            self.pieces[b].partners.push(ha);
            smallest = smallest.min(radius);
            radii.push((b, radius));
        }
        self.give_balls(a, smallest, parts);
        for (b, radius) in radii {
            self.give_balls(b, radius, parts);
        }
    }

    /// Gives piece `k` balls at its points within two spacings of a partner's (the
    /// faces along the crack: a piece's far side meets its partners as its surface
    /// would not, but it is not near them while their surfaces overlap), of `radius` or
    /// its balls' radius if smaller.
    fn give_balls(&mut self, k: usize, radius: f64, parts: &[Part]) {
        let piece = &self.pieces[k];
        let radius = piece.balls.map_or(radius, |(_, r)| r.min(radius));
        let x = parts[piece.part as usize].model.points().position;
        let reach = 2.0 * piece.thickness;
        let mut near = vec![false; piece.points.len()];
        for &h in &piece.partners {
            let Some(other) = self.pieces.iter().find(|p| p.body == h) else {
                continue;
            };
            let y = parts[other.part as usize].model.points().position;
            let theirs = within(&other.points, y, &piece.points, x, reach);
            for (flag, &i) in near.iter_mut().zip(&piece.points) {
                let p = vector(x[i as usize]);
                *flag = *flag || theirs.iter().any(|q| (p - vector(*q)).norm() < reach);
            }
        }
        // Every point where none is that near (surfaces overlapping farther off).
        let all = !near.contains(&true);
        let balls: Vec<(Isometry<f64>, SharedShape)> = piece
            .local
            .iter()
            .zip(&near)
            .filter(|&(_, &n)| n || all)
            .map(|(r, _)| {
                (
                    Isometry::translation(r[0], r[1], r[2]),
                    SharedShape::ball(radius),
                )
            })
            .collect();
        let surface = self.surface_collider(piece);
        let ph = &mut self.physics;
        if let Some((old, _)) = piece.balls {
            ph.colliders
                .remove(old, &mut ph.islands, &mut ph.bodies, true);
        }
        let surface = &mut ph.colliders[surface];
        surface.set_active_hooks(ActiveHooks::FILTER_CONTACT_PAIRS);
        let collider = ColliderBuilder::compound(balls)
            .density(0.0)
            .friction(surface.friction())
            .restitution(surface.restitution())
            .user_data(BALLS)
            .active_hooks(ActiveHooks::FILTER_CONTACT_PAIRS)
            .build();
        let handle = ph
            .colliders
            .insert_with_parent(collider, piece.body, &mut ph.bodies);
        self.pieces[k].balls = Some((handle, radius));
    }

    /// Ends the partnerships whose surfaces no longer overlap (or whose other piece
    /// went back to its model), and takes the balls from pieces left without a
    /// partner.
    pub(super) fn part_partners(&mut self) {
        if self.pieces.iter().all(|p| p.partners.is_empty()) {
            return;
        }
        let index: BTreeMap<(u32, u32), usize> = self
            .pieces
            .iter()
            .enumerate()
            .map(|(k, p)| (p.body.into_raw_parts(), k))
            .collect();
        let bodies = &self.physics.bodies;
        let mut ended = Vec::new();
        for (a, piece) in self.pieces.iter().enumerate() {
            for &h in &piece.partners {
                match index.get(&h.into_raw_parts()) {
                    None => ended.push((a, h, None)),
                    Some(&b) if piece.body.into_raw_parts() < h.into_raw_parts() => {
                        let asleep = bodies[piece.body].is_sleeping() && bodies[h].is_sleeping();
                        if !asleep && !self.overlap(piece, &self.pieces[b]) {
                            ended.push((a, h, Some(b)));
                        }
                    }
                    Some(_) => {}
                }
            }
        }
        for (a, h, b) in ended {
            let ha = self.pieces[a].body;
            self.pieces[a].partners.retain(|&p| p != h);
            if let Some(b) = b {
                self.pieces[b].partners.retain(|&p| p != ha);
            }
        }
        for k in 0..self.pieces.len() {
            let piece = &self.pieces[k];
            let Some((balls, _)) = piece.balls.filter(|_| piece.partners.is_empty()) else {
                continue;
            };
            let surface = self.surface_collider(piece);
            let ph = &mut self.physics;
            ph.colliders
                .remove(balls, &mut ph.islands, &mut ph.bodies, true);
            ph.colliders[surface].set_active_hooks(ActiveHooks::empty());
            self.pieces[k].balls = None;
        }
    }
}

/// The closest distance between a particle of `a` and one of `b` (m), among those
/// near the other piece (at most the larger spacing).
fn closest(a: &Piece, b: &Piece, parts: &[Part]) -> f64 {
    let (xa, xb) = (
        parts[a.part as usize].model.points().position,
        parts[b.part as usize].model.points().position,
    );
    let reach = a.thickness.max(b.thickness);
    let (na, nb) = (
        within(&a.points, xa, &b.points, xb, reach),
        within(&b.points, xb, &a.points, xa, reach),
    );
    na.iter()
        .flat_map(|p| nb.iter().map(move |q| (vector(*p) - vector(*q)).norm()))
        .fold(reach, f64::min)
}

/// The positions of `points` of `x` inside the box around `other` of `y` grown by
/// `reach`.
fn within(
    points: &[u32],
    x: &[[f64; 3]],
    other: &[u32],
    y: &[[f64; 3]],
    reach: f64,
) -> Vec<[f64; 3]> {
    let (lo, hi) = other.iter().fold(
        ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
        |(lo, hi), &i| {
            let p = y[i as usize];
            (
                [0, 1, 2].map(|k| lo[k].min(p[k])),
                [0, 1, 2].map(|k| hi[k].max(p[k])),
            )
        },
    );
    points
        .iter()
        .map(|&i| x[i as usize])
        .filter(|p| (0..3).all(|k| p[k] >= lo[k] - reach && p[k] <= hi[k] + reach))
        .collect()
}
