//! The rigid phase: fragments that have stopped breaking and vibrating leave their
//! model and become rigid bodies stepped by `rapier3d` (ARCHITECTURE, "A rigid phase").
//! Nothing in the papers does it; it is how studios finish a destruction shot (a
//! fracture solver's pieces handed to Houdini's RBD or Bullet).
//!
//! **When.** Every `check_every` steps the world looks at each model that can break
//! ([`crate::model::Model::fragments`]): a fragment (a connected component of intact bonds, as the
//! cache numbers them) of at most `small_fragment` points goes rigid, whatever its
//! motion: at once when it is a whole body (a pellet), and when it broke off a larger
//! body once nothing else deformable is left (with the last larger piece: until then
//! it moves as particles, bond-free and cheap, where as a rapier body it would be
//! stepped at the deformable bodies' microsecond step; see docs/rigid.md); a larger
//! one that broke off (less than its whole body, and a point of it lost a bond: an
//! intact or only pre-cut body at rest waits for what breaks it) when, for `settle_time`, no intact bond is within `margin` of what
//! breaks it and
//! the kinetic energy of its motion relative to its best-fit rigid motion is under
//! `vibration` of its kinetic energy (or that motion's amplitude, its r.m.s. speed
//! v times L/(π c_p) for a piece of size L and P-wave speed c_p, under
//! `rest_amplitude` of a spacing: a piece left standing rings at kilohertz, and what
//! shows of it is how far it moves, not how fast). A fragment that holds an anchored point stays in its model.
//!
//! **The switch.** With M = Σ m_i, c = Σ m_i x_i / M, P = Σ m_i v_i, L = Σ m_i
//! (x_i − c) × v_i and I = Σ m_i (|r_i|² 1 − r_i r_iᵀ), the body starts at c with
//! V = P/M and ω = I⁻¹L: its linear and angular momentum are the fragment's, and its
//! kinetic energy ½MV² + ½ωᵀIω is the fragment's less the relative motion's (the
//! best-fit rigid motion is the one that keeps both momenta). I is the points' own,
//! so a fragment moving rigidly keeps its kinetic energy exactly; fragments of fewer
//! than four points (their points' I is singular or next to it) take the inertia of
//! their solid, the tets their surface bounds, and ω = I⁻¹L with it.
//!
//! **Going back.** With `reenter` above 0, a piece of more than `reenter_points` points
//! about to be hit at `reenter` × s_c c_p or faster goes back to its model before the
//! hit ([`RigidPhase::reenter`]); by default pieces stay rigid.
//!
//! **Colliders** come from the fragment's own surface where its model has a tet mesh
//! (peridynamics: the faces of its particles' tets that it shares with no tet of the
//! piece, turned by the best-fit rotation since the reference configuration): the
//! convex hull of its vertices up to [`HULL_POINTS`] points, parry's convex
//! decomposition (V-HACD) above. Otherwise from its particles: a cube of its spacing
//! for a single particle (a ball would roll forever), the convex hull of the particle
//! centres rounded by half a spacing up to [`HULL_POINTS`] points (or, where the hull
//! is flat, the union of the particles' cubes), and above that the union of the
//! particles' cubes (concave where the piece is). Two pieces whose surface colliders
//! overlap when one goes rigid (born side by side across a crack) meet as balls at
//! their particles until their surfaces part (`partners.rs`). Rigid pieces collide with each other,
//! the ground and the scene's colliders in rapier (meshes as their triangle meshes),
//! with a rolling resistance rapier lacks (`rolling.rs`); with the particles still deformable
//! through particle contact, its force on a piece's points summed into a force and a
//! torque and given to the piece as two half impulses, as velocity Verlet gives it to
//! the particles, so the two sides exchange the same momentum. A dynamic scene collider
//! (a ball with a mass) is moved by rapier from the first hand-off on, so pieces push
//! it and it lands on the ground.
//!
//! Rapier is built with `enhanced-determinism` and without its `parallel` feature:
//! the same bytes with any thread count; its state is serialized into checkpoints (CBOR).

use std::collections::BTreeMap;

use perifrac_math::mat_mul;
use rapier3d_f64::na::{UnitQuaternion, Vector3};
use rapier3d_f64::prelude::*;
use serde::{Deserialize, Serialize};

use crate::contact::{Collider, ColliderShape};
use crate::scene::RigidSpec;
use crate::world::Part;

mod air;
mod checkpoint;
mod fit;
mod handoff;
mod partners;
mod reenter;
mod rolling;
mod shape;

pub use reenter::Thawed;

/// Above this many points a piece collides as a convex decomposition of its surface
/// (or the union of its particles' cubes) instead of a convex hull.
pub const HULL_POINTS: usize = 256;

/// The penetration rapier leaves at a contact without pushing the bodies apart (m;
/// `normalized_allowed_linear_error` with rapier's `length_unit` of 1). Rapier's 1 mm
/// is a thousandth of the metre-sized bodies it is tuned for, and a sixth of the
/// demo's grains: every one of them rested 1 to 2 mm into the ground (docs/rigid.md,
/// "Resting on the ground").
const ALLOWED_PENETRATION: f64 = 1e-4;

/// The natural frequency of rapier's soft contacts (Hz; rapier's default is 30). A
/// piece at rest sinks until its contacts' springs, each of stiffness ω² times its
/// effective mass, carry its weight: g/ω² = 0.28 mm at 30 Hz for a point under the
/// centre of mass, and about three times that for a tet lying on a face, whose corners'
/// effective masses are a tenth of its mass. At 120 Hz the sag is a sixteenth of
/// that; the soft contact stays stable at the rigid step (ω Δt = 0.3 a substep).
const CONTACT_FREQUENCY: f64 = 120.0;

/// A fragment handed to rapier.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Piece {
    /// The world part its points belong to.
    part: u32,
    /// Its points in that part's model.
    points: Vec<u32>,
    /// Each point's position in the body frame (from the centre of mass, the body's
    /// orientation at the switch being the identity).
    local: Vec<[f64; 3]>,
    /// Its rapier body.
    body: RigidBodyHandle,
    /// Its thinnest size, the particles' mean spacing (m): a step that moves it
    /// further than half of this turns on rapier's continuous collision detection.
    thickness: f64,
    /// Twice its largest distance from the centre of mass (m).
    size: f64,
    /// Its volume, the sum of its points' (m³): the air's drag ([`RigidPhase::drag`]).
    /// A checkpoint written before it was kept reads 0: no drag on that piece.
    #[serde(default)]
    volume: f64,
    /// How far its collider reaches beyond its points (m): its surface's
    /// [`crate::model::PieceSurface::reach`], or 0 for one of particles (then half a
    /// spacing, [`Piece::rounding`]; also what a checkpoint written before it reads).
    #[serde(default)]
    reach: f64,
    /// The closing speed of a hit (m/s) before which it goes back to its model:
    /// `reenter` × s_c c_p, ∞ for small pieces and what cannot break ([`RigidPhase::reenter`]).
    #[serde(default = "never")]
    limit: f64,
    /// The rotation from the reference configuration to the body frame at the switch
    /// (its collider's surface was turned by it), `None` for a piece that collides as
    /// its particles; with the body's rotation, how its tets turn
    /// ([`RigidPhase::orient`]). A checkpoint written before it was kept reads `None`.
    #[serde(default)]
    turn: Option<[[f64; 3]; 3]>,
    /// The pieces whose surfaces its own overlapped when it went rigid and still
    /// overlap: they meet as balls, not surfaces (`partners.rs`).
    #[serde(default)]
    partners: Vec<RigidBodyHandle>,
    /// Its collider of balls at its points while it has partners, and their radius (m).
    #[serde(default)]
    balls: Option<(ColliderHandle, f64)>,
}

impl Piece {
    /// How far its collider reaches beyond its points' centres (m): at least half a
    /// spacing (a collider of particles is rounded by that much).
    fn rounding(&self) -> f64 {
        self.reach.max(0.5 * self.thickness)
    }
}

fn never() -> f64 {
    f64::INFINITY
}

/// Points given back to their model that may not go rigid again before `until` (s):
/// the hit they were thawed for is not over.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Hold {
    part: u32,
    points: Vec<u32>,
    until: f64,
}

/// Rapier's state: what is saved in checkpoints.
#[derive(Serialize, Deserialize)]
struct Physics {
    bodies: RigidBodySet,
    colliders: ColliderSet,
    islands: IslandManager,
    broad_phase: DefaultBroadPhase,
    narrow_phase: NarrowPhase,
    impulse_joints: ImpulseJointSet,
    multibody_joints: MultibodyJointSet,
    ccd: CCDSolver,
}

impl Physics {
    fn new() -> Physics {
        Physics {
            bodies: RigidBodySet::new(),
            colliders: ColliderSet::new(),
            islands: IslandManager::new(),
            broad_phase: DefaultBroadPhase::new(),
            narrow_phase: NarrowPhase::new(),
            impulse_joints: ImpulseJointSet::new(),
            multibody_joints: MultibodyJointSet::new(),
            ccd: CCDSolver::new(),
        }
    }
}

/// The rigid phase of a world: rapier's bodies and the pieces they carry.
pub struct RigidPhase {
    settings: RigidSpec,
    physics: Physics,
    pipeline: PhysicsPipeline,
    pieces: Vec<Piece>,
    /// Scene colliders in rapier (index into the world's colliders, handle); the
    /// dynamic ones are moved by rapier.
    mirrors: Vec<(usize, RigidBodyHandle)>,
    /// Fragments that have met the conditions since a time: (part, smallest point).
    calm: BTreeMap<(u32, u32), f64>,
    /// Contact force and torque (about the centre of mass) on each piece at the last
    /// contact computation: the next step's first half impulse (saved, as the
    /// particles' accelerations are).
    contact: Vec<([f64; 3], [f64; 3])>,
    /// Pieces given back to their models and not yet free to go rigid again.
    holds: Vec<Hold>,
    /// Wall time spent (s).
    pub time: f64,
}

impl std::fmt::Debug for RigidPhase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RigidPhase")
            .field("pieces", &self.pieces.len())
            .field("mirrors", &self.mirrors)
            .finish_non_exhaustive()
    }
}

fn vector(v: [f64; 3]) -> Vector3<f64> {
    Vector3::new(v[0], v[1], v[2])
}

fn array(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

impl RigidPhase {
    /// An empty rigid phase with the scene's colliders mirrored in rapier.
    /// `calm`: the fragments settling before it existed ([`RigidPhase::take_calm`]).
    pub fn new(
        settings: RigidSpec,
        colliders: &[Collider],
        calm: BTreeMap<(u32, u32), f64>,
    ) -> RigidPhase {
        let mut phase = RigidPhase {
            settings,
            physics: Physics::new(),
            pipeline: PhysicsPipeline::new(),
            pieces: Vec::new(),
            mirrors: Vec::new(),
            calm,
            contact: Vec::new(),
            holds: Vec::new(),
            time: 0.0,
        };
        phase.mirror(colliders);
        phase
    }

    /// Puts the scene's colliders into rapier ([`shape::mirrored`]).
    fn mirror(&mut self, colliders: &[Collider]) {
        let s = &self.settings;
        for (i, c) in colliders.iter().enumerate() {
            let Some((body, shape)) = shape::mirrored(c) else {
                continue;
            };
            let handle = self.physics.bodies.insert(body.build());
            let mut collider = shape.friction(c.friction).restitution(s.restitution);
            if let Some(m) = c.mass {
                collider = collider.mass(m);
            }
            self.physics.colliders.insert_with_parent(
                collider.build(),
                handle,
                &mut self.physics.bodies,
            );
            self.mirrors.push((i, handle));
        }
    }

    /// Resets what rapier keeps between steps but does not save: the counters of
    /// parry's BVH optimiser (its `BvhWorkspace`, skipped by serde), which a restored
    /// broad phase starts from zero. Every run resets them at the same places, the
    /// world's stop points ([`crate::world::World::at_stop_point`]), by passing the
    /// broad phase through its serialized form, so a run resumed from any of those
    /// places continues with the same bytes. The rest of rapier's state round-trips
    /// exactly (with `enhanced-determinism` its maps keep their insertion order).
    pub fn reset_workspaces(&mut self) {
        let mut bytes = Vec::new();
        ciborium::into_writer(&self.physics.broad_phase, &mut bytes)
            .expect("rapier's broad phase serializes into memory");
        self.physics.broad_phase = ciborium::from_reader(bytes.as_slice())
            .expect("rapier's broad phase reads back what it wrote");
    }

    /// Pieces so far.
    pub fn pieces(&self) -> usize {
        self.pieces.len()
    }

    /// Points in rigid pieces.
    pub fn frozen_points(&self) -> usize {
        self.pieces.iter().map(|p| p.points.len()).sum()
    }

    /// The fragments settling, (part, smallest point) → since when: what a world
    /// keeps of a phase that handed nothing over yet, so that a fragment's
    /// `settle_time` runs on across the looks.
    pub fn take_calm(&mut self) -> BTreeMap<(u32, u32), f64> {
        std::mem::take(&mut self.calm)
    }

    /// Whether rapier moves world collider `i` (a dynamic one, mirrored).
    pub fn moves_collider(&self, i: usize, colliders: &[Collider]) -> bool {
        colliders[i].mass.is_some() && self.mirrors.iter().any(|&(c, _)| c == i)
    }

    /// Gives each piece half a step's impulse of the last contact forces (velocity
    /// Verlet's half kick), writing the new velocities to its points.
    pub fn half_kick(&mut self, dt: f64, parts: &mut [Part]) {
        for (piece, (f, tau)) in self.pieces.iter().zip(&self.contact) {
            let body = &mut self.physics.bodies[piece.body];
            if *f != [0.0; 3] || *tau != [0.0; 3] {
                body.apply_impulse(vector(*f) * (0.5 * dt), true);
                body.apply_torque_impulse(vector(*tau) * (0.5 * dt), true);
            }
            place(piece, body, &mut parts[piece.part as usize]);
        }
    }

    /// One rapier step of `dt` (the dynamic scene colliders' impulses since the last
    /// one already applied), then the pieces' points and the dynamic colliders to
    /// their bodies' new poses.
    pub fn step(
        &mut self,
        dt: f64,
        gravity: [f64; 3],
        parts: &mut [Part],
        colliders: &mut [Collider],
    ) {
        let t = std::time::Instant::now();
        for &(i, handle) in &self.mirrors {
            let c = &colliders[i];
            let body = &mut self.physics.bodies[handle];
            if let ColliderShape::Mesh(_) = c.shape {
                // At its keyframed pose, turning as the segment does.
                body.set_position(shape::pose(c), true);
                body.set_angvel(vector(c.angular_velocity), true);
            }
            if c.mass.is_none() && !matches!(c.shape, ColliderShape::Ground) {
                body.set_linvel(vector(c.velocity), true);
            }
        }
        self.drag(dt);
        // Continuous collision detection where a step moves a piece through half its
        // thickness: at the deformable phase's microsecond steps none, at the rigid
        // phase's 1/600 s the fast ones (it is most of rapier's cost with a thousand
        // grains in flight).
        for piece in &self.pieces {
            let body = &mut self.physics.bodies[piece.body];
            let reach = dt * (body.linvel().norm() + 0.5 * piece.size * body.angvel().norm());
            let ccd = reach > 0.5 * piece.thickness;
            if body.is_ccd_enabled() != ccd {
                body.enable_ccd(ccd);
            }
        }
        let params = IntegrationParameters {
            dt,
            normalized_allowed_linear_error: ALLOWED_PENETRATION,
            contact_natural_frequency: CONTACT_FREQUENCY,
            ..IntegrationParameters::default()
        };
        self.part_partners();
        let filter = self.filter();
        let ph = &mut self.physics;
        self.pipeline.step(
            &vector(gravity),
            &params,
            &mut ph.islands,
            &mut ph.broad_phase,
            &mut ph.narrow_phase,
            &mut ph.bodies,
            &mut ph.colliders,
            &mut ph.impulse_joints,
            &mut ph.multibody_joints,
            &mut ph.ccd,
            &filter,
            &(),
        );
        self.resist_rolling();
        let ph = &mut self.physics;
        for piece in &self.pieces {
            place(
                piece,
                &ph.bodies[piece.body],
                &mut parts[piece.part as usize],
            );
        }
        for &(i, handle) in &self.mirrors {
            let c = &mut colliders[i];
            if c.mass.is_some() {
                let body = &ph.bodies[handle];
                c.center = array(body.translation());
                c.velocity = array(body.linvel());
            }
        }
        self.time += t.elapsed().as_secs_f64();
    }

    /// Gives dynamic scene collider `i` the impulse `j` (from the particles).
    pub fn push_collider(&mut self, i: usize, j: [f64; 3]) {
        if let Some(&(_, handle)) = self.mirrors.iter().find(|&&(c, _)| c == i) {
            self.physics.bodies[handle].apply_impulse(vector(j), true);
        }
    }

    /// Sums the contact forces on each piece's points (`force(part)` gives a part's
    /// per-point forces) into a force and a torque about its centre of mass.
    pub fn gather_contact<'a>(&mut self, parts: &[Part], force: impl Fn(usize) -> &'a [[f64; 3]]) {
        for (piece, slot) in self.pieces.iter().zip(self.contact.iter_mut()) {
            let p = piece.part as usize;
            let f = force(p);
            if f.is_empty() {
                *slot = ([0.0; 3], [0.0; 3]);
                continue;
            }
            let x = parts[p].model.points().position;
            let c = array(self.physics.bodies[piece.body].translation());
            let (mut total, mut torque) = ([0.0; 3], [0.0; 3]);
            for &i in &piece.points {
                let (fi, r) = (f[i as usize], [0, 1, 2].map(|k| x[i as usize][k] - c[k]));
                for k in 0..3 {
                    total[k] += fi[k];
                }
                torque[0] += r[1] * fi[2] - r[2] * fi[1];
                torque[1] += r[2] * fi[0] - r[0] * fi[2];
                torque[2] += r[0] * fi[1] - r[1] * fi[0];
            }
            *slot = (total, torque);
        }
    }

    /// Tells each piece's model how the piece has turned from the reference
    /// configuration, R(t) R_s (its body's rotation since the switch after the turn
    /// its collider was given then), before the frame's tets are placed
    /// ([`crate::model::Model::orient`]): the tets of its points whose bonds no longer
    /// say (dust and chips) then turn with it and lie where its collider is.
    pub fn orient(&self, parts: &mut [Part]) {
        for piece in &self.pieces {
            let Some(turn) = piece.turn else {
                continue;
            };
            let body = self.physics.bodies[piece.body]
                .rotation()
                .to_rotation_matrix();
            let rotation = [0, 1, 2].map(|r| [0, 1, 2].map(|c| body[(r, c)]));
            parts[piece.part as usize]
                .model
                .orient(&piece.points, mat_mul(&rotation, &turn));
        }
    }

    /// Whether a piece is awake (moving).
    pub fn any_awake(&self) -> bool {
        self.pieces
            .iter()
            .any(|p| !self.physics.bodies[p.body].is_sleeping())
    }

    /// The longest step the rigid phase allows.
    pub fn longest_step(&self) -> f64 {
        self.settings.step
    }
}

/// Moves a piece's points to its body's pose: y = c + R r, v = V + ω × R r.
fn place(piece: &Piece, body: &RigidBody, part: &mut Part) {
    let pose = body.position();
    let rotation: UnitQuaternion<f64> = pose.rotation;
    let c = array(&pose.translation.vector);
    let (v, w) = (array(body.linvel()), array(body.angvel()));
    let p = part.model.points_mut();
    for (&i, r0) in piece.points.iter().zip(&piece.local) {
        let r = array(&(rotation * vector(*r0)));
        let i = i as usize;
        p.position[i] = [0, 1, 2].map(|k| c[k] + r[k]);
        p.velocity[i] = [
            v[0] + w[1] * r[2] - w[2] * r[1],
            v[1] + w[2] * r[0] - w[0] * r[2],
            v[2] + w[0] * r[1] - w[1] * r[0],
        ];
    }
}
