//! The hand-off: which fragments go rigid at a look, and the switch of one fragment
//! to a rapier body with its momenta and its collider (the module comment of
//! [`super`], "When", "The switch" and "Colliders").

use std::collections::BTreeMap;

use perifrac_math::mat_vec;
use rapier3d_f64::na::Point3;
use rapier3d_f64::prelude::*;

use super::fit::{self, Fit, fit};
use super::{Piece, RigidPhase, place, shape, vector};
use crate::model::Stepping;
use crate::world::Part;

/// Pieces of fewer points than this turn with their solid's inertia (their tets'),
/// not their points' ([`RigidPhase::hand_over`]).
const SOLID_BELOW: usize = 4;

impl RigidPhase {
    /// Looks for fragments to hand over at `time` and hands them over; returns how
    /// many went rigid.
    pub fn look(&mut self, parts: &mut [Part], time: f64) -> usize {
        let before = self.pieces.len();
        let mut handed = 0;
        let mut seen = BTreeMap::new();
        // Small fragments wait here until nothing else deformable is left.
        let mut small_ones: Vec<(usize, Vec<u32>)> = Vec::new();
        for (p, part) in parts.iter_mut().enumerate() {
            let Some(fragments) = part.model.fragments() else {
                continue;
            };
            let frozen = part.model.frozen().map(|f| f.to_vec());
            // Every point of a fragment, or none when any is frozen, anchored or
            // cannot break.
            // Points of each scene body: a fragment that is a whole body (cut at set-up
            // perhaps, but not broken apart) waits for what breaks it.
            let mut body_points: BTreeMap<u32, usize> = BTreeMap::new();
            for &b in part.model.point_bodies() {
                *body_points.entry(b).or_default() += 1;
            }
            let mut whole: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
            let mut blocked: Vec<bool> = vec![false; fragments.fragment.len()];
            // Points back from the rigid phase whose hit is not over.
            for hold in self.holds.iter().filter(|h| h.part as usize == p) {
                for &i in &hold.points {
                    blocked[fragments.fragment[i as usize] as usize] = true;
                }
            }
            for (i, &f) in fragments.fragment.iter().enumerate() {
                if frozen.as_ref().is_some_and(|z| z[i])
                    || part.is_anchored(i)
                    || fragments.breaking[i] < 0.0
                {
                    blocked[f as usize] = true;
                }
                whole.entry(f).or_default().push(i as u32);
            }
            for (f, points) in whole {
                if blocked[f as usize] {
                    continue;
                }
                let key = (p as u32, points[0]);
                let body = part.model.point_bodies()[points[0] as usize];
                let whole_body = points.len() == body_points[&body];
                if points.len() <= self.settings.small_fragment {
                    if whole_body {
                        // A small body of its own (a pellet): rigid at once.
                        let fit = fit(part, &points);
                        self.hand_over(p, part, points, &fit, f64::INFINITY);
                        handed += 1;
                    } else {
                        small_ones.push((p, points));
                    }
                    continue;
                }
                let broke_off =
                    !whole_body && points.iter().any(|&i| fragments.damaged[i as usize]);
                if !broke_off {
                    continue;
                }
                let worst = points
                    .iter()
                    .map(|&i| fragments.breaking[i as usize])
                    .fold(0.0, f64::max);
                let fit = fit(part, &points);
                let wave_speed = fragments.wave_speed[body as usize];
                let still = worst < self.settings.margin
                    && (fit.relative <= self.settings.vibration * fit.kinetic
                        || fit.amplitude(wave_speed) <= self.settings.rest_amplitude);
                if !still {
                    continue;
                }
                let since = *self.calm.get(&key).unwrap_or(&time);
                seen.insert(key, since);
                if time - since >= self.settings.settle_time {
                    let limit = if self.settings.reenter > 0.0
                        && points.len() > self.settings.reenter_points
                    {
                        self.settings.reenter * fragments.hit_speed[body as usize]
                    } else {
                        f64::INFINITY
                    };
                    self.hand_over(p, part, points, &fit, limit);
                    seen.remove(&key);
                    handed += 1;
                }
            }
        }
        self.calm = seen;
        // The small fragments go when they are all that is left to deform: every
        // point of every model is rigid or in one of them, and every model is one the
        // world steps (so that the step can grow).
        let total: usize = parts.iter().map(|p| p.model.points().mass.len()).sum();
        let waiting: usize = small_ones.iter().map(|(_, points)| points.len()).sum();
        let all_verlet = parts.iter().all(|p| p.model.stepping() == Stepping::Verlet);
        if all_verlet && self.frozen_points() + waiting == total {
            for (p, points) in small_ones {
                let fit = fit(&parts[p], &points);
                self.hand_over(p, &mut parts[p], points, &fit, f64::INFINITY);
                handed += 1;
            }
        }
        for a in before..self.pieces.len() {
            self.find_partners(a, parts);
        }
        handed
    }

    /// Makes `points` of part `p` a rigid body with the momenta of `fit`, and sets
    /// their velocities to its rigid motion; a hit closing at `limit` (m/s) gives it
    /// back ([`RigidPhase::reenter`]).
    fn hand_over(&mut self, p: usize, part: &mut Part, points: Vec<u32>, fit: &Fit, limit: f64) {
        let s = &self.settings;
        let volume = part.model.contact_points().map(|c| c.volume.to_vec());
        let pts = part.model.points();
        let local: Vec<[f64; 3]> = points
            .iter()
            .map(|&i| {
                let x = pts.position[i as usize];
                [0, 1, 2].map(|k| x[k] - fit.center[k])
            })
            .collect();
        let spacing: Vec<f64> = points
            .iter()
            .map(|&i| {
                volume
                    .as_ref()
                    .map_or(0.0, |v| v[i as usize].cbrt())
                    .max(1e-9)
            })
            .collect();
        // Its own surface where the model has one, turned as the piece has since the
        // reference configuration; else its particles.
        let surface = part.model.reference_surface(&points).and_then(|surface| {
            let (rest, turn) = fit::reference_pose(part, &points)?;
            let vertices: Vec<[f64; 3]> = surface
                .vertices
                .iter()
                .map(|x| mat_vec(turn, [0, 1, 2].map(|k| x[k] - rest[k])))
                .collect();
            let solid = fit::solid_inertia(&vertices, &surface.triangles, fit.mass);
            let shape = shape::surface(&vertices, &surface.triangles, &local)?;
            Some((shape, surface.reach, solid, turn))
        });
        let (shape, reach, solid, turn) = match surface {
            Some((shape, reach, solid, turn)) => (shape, reach, solid, Some(turn)),
            None => (
                shape::piece(&local, &spacing, 0.5 * fit.spacing),
                0.0,
                None,
                None,
            ),
        };
        // A piece of fewer than four points has next to no inertia of its points
        // (none at all about the line through two): it turns as the solid its
        // collider is, its tets' own inertia, with the fragment's angular momentum
        // (docs/rigid.md, "The switch"). Larger pieces keep their points' inertia, so
        // that their kinetic energy is kept exactly.
        let (inertia, spin) = match solid {
            Some(solid) if points.len() < SOLID_BELOW => {
                let angular = fit.inertia * vector(fit.spin);
                let spin = solid
                    .try_inverse()
                    .map_or(vector(fit.spin), |inv| inv * angular);
                (solid, spin)
            }
            _ => (fit.inertia, vector(fit.spin)),
        };
        let piece_volume: f64 = spacing.iter().map(|l| l * l * l).sum();
        let body = RigidBodyBuilder::dynamic()
            .translation(vector(fit.center))
            .linvel(vector(fit.velocity))
            .angvel(spin)
            .additional_mass_properties(MassProperties::with_inertia_matrix(
                Point3::origin(),
                fit.mass,
                inertia,
            ))
            .build();
        let handle = self.physics.bodies.insert(body);
        self.physics.colliders.insert_with_parent(
            shape
                .density(0.0)
                .friction(s.friction)
                .restitution(s.restitution)
                .build(),
            handle,
            &mut self.physics.bodies,
        );
        part.model.freeze(&points);
        let piece = Piece {
            part: p as u32,
            points,
            local,
            body: handle,
            thickness: fit.spacing,
            size: fit.size,
            volume: piece_volume,
            reach,
            limit,
            turn,
            partners: Vec::new(),
            balls: None,
        };
        place(&piece, &self.physics.bodies[handle], part);
        self.pieces.push(piece);
        self.contact.push(([0.0; 3], [0.0; 3]));
    }
}
